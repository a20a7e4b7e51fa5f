"""The presets drive the standard extras (issue 42): a sneer's upper lip, cheek puff, the jaw
sideways and surprise beyond a human face, from blendshape scores and from markers, on real takes
(a posed sneer and smile, a jaw exercise) and on synthetic performers that make none of them."""

import dataclasses

import numpy as np
import pytest

from capture import Take, load_take, synthesize
from capture.performance import default_performance
from common import InputError
from mapping import map_take
from mapping.mapfile import parse_mapping
from mapping.plan import normalise_pairs
from mapping.sources import BLENDSHAPE_NAMES


def _extra(track, code: str) -> np.ndarray:
    return track.extra[:, track.extra_codes.index(code)]


def test_only_keeps_one_way_of_a_source_by_hand():
    raw = np.array([[1.0, 1.0, 1.0], [3.0, 3.0, 3.0], [-1.0, -1.0, -1.0], [np.nan, np.nan, np.nan]])
    out = normalise_pairs(raw, np.zeros(3, dtype=int), np.ones(3), np.ones(3), np.ones(3), np.full(3, 2.0),
                          np.array([1.0, -1.0, -1.0]), np.array([1, -1, 0]))
    np.testing.assert_array_equal(out[:3], [[0, 0, 0], [1, 0, -1], [0, 1, 1]])  # (raw - 1) / 2, one way, signed
    assert np.isnan(out[3]).all()  # unseen stays unseen
    doc = {"format": "toonface.mapping/1", "markerset": "toon32",
           "motor": {"UL": {"sources": [{"marker": "LIP_UP", "only": "upward"}], "normalise": "scale"}}}
    with pytest.raises(InputError, match=r"motor.UL.sources\[0\].only"):
        parse_mapping(doc)


def _scored(seconds: float = 4.0):
    """The synthetic performer with every ARKit score at 0 but: cheekPuff 0.8 from 1.5 s, jawLeft
    0.6 from 2 s to 3 s, jawRight 0.4, noseSneerLeft 0.9 and browInnerUp 0.9 from 3 s."""
    take = synthesize(seconds=seconds, rate=30, performance=default_performance(seconds), seed=2).take
    names = tuple(sorted(BLENDSHAPE_NAMES - {"tongueOut"}))
    t = take.times
    scores = np.zeros((take.frames, len(names)))
    scores[:, names.index("cheekPuff")] = np.where(t > 1.5, 0.8, 0.0)
    scores[:, names.index("jawLeft")] = np.where((t > 2.0) & (t < 3.0), 0.6, 0.0)
    scores[:, names.index("jawRight")] = np.where(t >= 3.0, 0.4, 0.0)
    scores[:, names.index("noseSneerLeft")] = np.where(t >= 3.0, 0.9, 0.0)
    scores[:, names.index("browInnerUp")] = np.where(t >= 3.0, 0.9, 0.0)
    return Take(take.positions, take.labels, take.rate, take.times, take.dims, take.meta, channels=scores,
                channel_names=names)


def test_the_blendshape_preset_drives_cheek_puff_jaw_sideways_sneer_and_perk_by_hand():
    track = map_take(_scored(), "arkit")
    at = [int(s * 30) for s in (1.0, 1.8, 2.5, 3.5)]
    np.testing.assert_allclose(_extra(track, "CP")[at], [0, 0.8, 0.8, 0.8], atol=1e-3)  # a score: its fraction
    np.testing.assert_allclose(_extra(track, "JS")[at], [0.5, 0.5, 0.8, 0.3], atol=1e-3)  # 0.5 + (left - right) / 2
    np.testing.assert_allclose(_extra(track, "UL")[at], [0, 0, 0, 0.45], atol=1e-3)  # half a sneer on one side
    np.testing.assert_allclose(_extra(track, "PERK")[at], [0, 0, 0, (0.45 - 0.4) / 0.6], atol=1e-3)  # past 40 %


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_performer_who_never_sneers_puffs_or_shifts_the_jaw_leaves_them_at_rest(seed):
    take = synthesize(seconds=12.0, seed=seed).take  # smiles, talks, opens the jaw, raises the brows
    track = map_take(take)
    for code, rest in (("UL", 0.0), ("CP", 0.0), ("JS", 0.5)):
        assert np.percentile(np.abs(_extra(track, code) - rest), 95) < 0.1, code
    assert _extra(track, "PERK").max() > 0.5  # the brows' surprise does reach it


@pytest.mark.realdata
def test_a_posed_sneer_raises_the_upper_lip_and_a_smile_does_not(realdata):
    path = realdata / "facial" / "gluedots" / "Subject_01.csv"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    track = map_take(load_take(path), neutral_window=(800 / 30, 985 / 30))  # the posed neutral
    ul = _extra(track, "UL")
    segments = {"neutral": ul[800:985], "disgust": ul[986:1200], "happy": ul[1201:1415], "fear": ul[1416:1650]}
    assert np.percentile(segments["disgust"], 90) > 0.9 and np.mean(segments["disgust"] > 0.5) > 0.3
    for calm in ("neutral", "happy", "fear"):
        assert np.percentile(segments[calm], 99) < 0.1, calm
    corners = track.column("MLV")
    assert np.median(corners[1201:1415]) > 0.7  # the smile is there, on the corners (and not on UL)


@pytest.mark.realdata
def test_a_real_jaw_exercise_moves_the_jaw_sideways_and_not_the_cheeks_or_lip(realdata):
    path = realdata / "facial" / "animface" / "JawMoCap.csv"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    track = map_take(load_take(path, units="cm"))
    js = _extra(track, "JS")
    second = lambda s: slice(int(s * 60), int((s + 1) * 60))  # noqa: E731
    assert js[second(16)].max() < 0.35  # the chin 5-6 mm to the performer's right
    assert js[second(18.5)].min() > 0.9  # and 11 mm to the left
    wide = slice(5 * 60, 8 * 60)  # the mouth 4 cm open: the cheeks and the lip stretch, and are not read
    assert track.column("MB")[wide].max() > 0.95
    assert _extra(track, "CP")[wide].max() < 0.15 and _extra(track, "UL")[wide].max() < 0.1


@pytest.mark.realdata
def test_a_jaw_that_thrusts_or_slides_does_not_puff_the_cheeks_and_a_real_puff_still_does(realdata):
    """Issue 66: the jaw take's performer pushes the chin forward (13 mm, at 9-11 s) and sideways
    (6 mm, at 21-23 s), which spreads the cheeks by 3-6 mm: no puff. Cheeks blown out by 5 mm a
    side with the jaw still (put into the same take) are one."""
    path = realdata / "facial" / "animface" / "JawMoCap.csv"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    take = load_take(path, units="cm")
    cp = _extra(map_take(take), "CP")
    assert np.percentile(cp, 95) < 0.05 and cp.max() < 0.2  # was 0.59 and 0.81
    positions = take.positions.copy()
    right, left = take.labels.index("Rcheek_Outside"), take.labels.index("Lcheek_Outside")
    puff = slice(13 * 60, 15 * 60)
    ramp = np.clip(np.minimum(np.arange(120), 119 - np.arange(120)) / 15, 0, 1)[:, None]
    outward = positions[puff, left] - positions[puff, right]
    outward /= np.linalg.norm(outward, axis=1, keepdims=True)
    positions[puff, left] += 5 * ramp * outward
    positions[puff, right] -= 5 * ramp * outward
    puffed = _extra(map_take(dataclasses.replace(take, positions=positions)), "CP")
    assert np.median(puffed[int(13.4 * 60):int(14.6 * 60)]) > 0.8
