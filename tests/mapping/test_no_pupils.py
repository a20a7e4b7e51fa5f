"""A dot-marker video's take has no pupils (no sticker sits on an eye): it maps, its pupils stay at
the face's neutral, and the user is told; before, toon32's pupil rules refused the whole take
(track then map, and send VIDEO, ended in 'the take has no marker "PUPIL_R"')."""

import numpy as np
import pytest

from capture import Take, synthesize
from common import InputError
from mapping import choose_mapping
from toon import MOTOR_CODES, standard_neutral
from toonface.pipeline import map_onto_face


def without(take: Take, gone: set[str]) -> Take:
    keep = [i for i, label in enumerate(take.labels) if label not in gone]
    return Take(take.positions[:, keep], tuple(take.labels[i] for i in keep), take.rate, times=take.times,
                meta=take.meta)


def test_a_take_without_pupils_maps_with_its_pupils_at_neutral_and_says_so():
    take = without(synthesize(seconds=4, rate=30, noise_mm=0.0).take, {"PUPIL_R", "PUPIL_L"})
    mapping, _ = choose_mapping(take)
    assert set(mapping.left_out) == {"PRH", "PRV", "PLH", "PLV"} and "dot markers" in mapping.left_out_note()
    assert map_onto_face(take).frames == take.frames  # the one-call pipeline too


def test_a_take_without_a_marker_that_is_not_independent_is_still_refused():
    take = without(synthesize(seconds=2, rate=30, noise_mm=0.0).take, {"LIP_LOW"})
    with pytest.raises(InputError, match='no marker "LIP_LOW"'):
        choose_mapping(take)


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
