"""A dot-marker video's take has no pupils (no sticker sits on an eye): it maps, its pupils stay at
the face's neutral, and the user is told; before, toon32's pupil rules refused the whole take
(track then map, and send VIDEO, ended in 'the take has no marker "PUPIL_R"')."""

import numpy as np
import pytest

from capture import Take, synthesize
from common import InputError
from mapping import choose_mapping, prepare
from toon import MOTOR_CODES, standard_neutral
from toonface.pipeline import map_onto_face


def without(take: Take, gone: set[str]) -> Take:
    keep = [i for i, label in enumerate(take.labels) if label not in gone]
    return Take(take.positions[:, keep], tuple(take.labels[i] for i in keep), take.rate, times=take.times,
                meta=take.meta)


def test_a_take_without_pupils_maps_with_its_pupils_at_neutral_and_says_so():
    take = without(synthesize(seconds=4, rate=30, noise_mm=0.0).take, {"PUPIL_R", "PUPIL_L"})
    mapping, _ = choose_mapping(take)
    assert set(mapping.left_out) == {"PRH", "PRV", "PLH", "PLV"} and "PUPIL_R, PUPIL_L" in mapping.left_out_note()
    assert map_onto_face(take).frames == take.frames  # the one-call pipeline too


def test_a_rig_without_brows_and_lids_leaves_their_motors_out_and_names_them():
    """Issue 62: a rig that covers part of the face maps what it has; the motors that read a marker
    it lacks stay at neutral (never driven from the nearest markers) and the note names both. A
    motor that decoupled from one left out no longer does."""
    from mapping import calibrate, map_stabilised

    gone = {m for m in synthesize(seconds=1, rate=30).take.labels if m.startswith(("BROW", "LID"))}
    take = without(synthesize(seconds=4, rate=30, noise_mm=0.0).take, gone)
    mapping, markerset = choose_mapping(take)
    brows_lids = {c for c in MOTOR_CODES if c[0] in "BE"}
    assert brows_lids <= set(mapping.left_out) and not {"MB", "MLH", "PRH"} & set(mapping.left_out)
    assert set(mapping.absent) == gone and not any(set(r.decouple) & brows_lids for r in mapping.rules)
    note = mapping.left_out_note()
    assert note is not None and "BROW_R_MED" in note and "LID_L_LOW" in note and "BLC" in note
    prepared = prepare(take, markerset)
    values = map_stabilised(prepared.stable, prepared.columns, take.times, take.rate, mapping,
                            calibrate(mapping, prepared, (0.0, 1.0)), standard_neutral()).values
    out = [MOTOR_CODES.index(c) for c in sorted(brows_lids)]
    np.testing.assert_allclose(values[:, out], np.tile(standard_neutral()[out], (len(values), 1)))
    assert np.ptp(values[:, MOTOR_CODES.index("MB")]) > 0.05


def test_a_take_with_fewer_than_three_head_references_is_still_refused():
    take = without(synthesize(seconds=2, rate=30, noise_mm=0.0).take,
                   {"FOREHEAD", "TEMPLE_L", "NOSE_TIP", "EYE_R_IN", "EYE_L_IN"})
    with pytest.raises(InputError, match="head reference markers are present"):
        mapping, markerset = choose_mapping(take, "toon32")
        prepare(take, markerset)


def test_the_pupils_left_out_stay_at_the_faces_neutral_offline():
    from mapping import calibrate, map_stabilised, prepare

    take = without(synthesize(seconds=4, rate=30, noise_mm=0.0).take, {"PUPIL_R", "PUPIL_L"})
    mapping, markerset = choose_mapping(take)
    prepared = prepare(take, markerset)
    profile = calibrate(mapping, prepared, (0.0, 1.0))
    values = map_stabilised(prepared.stable, prepared.columns, take.times, take.rate, mapping, profile,
                            standard_neutral()).values
    pupils = [MOTOR_CODES.index(c) for c in ("PRH", "PRV", "PLH", "PLV")]
    np.testing.assert_allclose(values[:, pupils], np.tile(standard_neutral()[pupils], (len(values), 1)))
    assert np.ptp(values[:, MOTOR_CODES.index("MB")]) > 0.05  # the rest still moves
