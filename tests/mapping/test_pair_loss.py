"""toon32's lids and pupils follow the other eye's while their own marker is lost, or made up by
cleaning while the other's is measured (loss policy ``pair``): a blink or a glance behind a lost
marker is not lost with it. Its brows follow the other brow while their own markers are lost or
made up, but only as far as their own brow's other parts move with the other's (``near``)."""

import numpy as np
import pytest

from capture import Take, synthesize
from capture.performance import Cue, Performance
from mapping import calibrate, choose_mapping, map_stabilised, prepare
from mapping.mapper import FILLED_QUALITY, made_up, solved_shares
from mapping.rules import MotorRules
from mapping.solver import Solver
from mapping.stabilise import Stabilised
from mapping.stepwise import LiveMapper
from toon import MOTOR_CODES
from toon.motors import extended_neutral


def _mapped(take: Take) -> tuple[np.ndarray, np.ndarray]:
    mapping, markerset = choose_mapping(take)
    prepared = prepare(take, markerset)
    values = map_stabilised(prepared.stable, prepared.columns, take.times, take.rate, mapping,
                            calibrate(mapping, prepared, (0.0, 1.0))).values
    return values, prepared.stable.local


def _lost_over(cues: tuple[Cue, ...], labels: tuple[str, ...], codes: tuple[str, ...]
               ) -> list[tuple[str, float, float]]:
    """A 6 s performance of ``cues`` whose markers ``labels`` are lost from 1.8 to 4.3 s (longer
    than gap filling fills: asserted), mapped: for each motor of ``codes``, how far it moved then
    with its markers seen and how far it missed that with them lost."""
    syn = synthesize(seconds=6.0, rate=60.0, noise_mm=0.0, performance=Performance(6.0, cues), seed=4)
    positions = syn.take.positions.copy()
    lost = (syn.take.times >= 1.8) & (syn.take.times < 4.3)
    for label in labels:
        positions[lost, syn.take.index(label)] = np.nan
    seen, _ = _mapped(syn.take)
    values, local = _mapped(Take(positions, syn.take.labels, syn.take.rate, times=syn.take.times))
    assert np.isnan(local[lost][:, [syn.take.index(label) for label in labels]]).all()
    out = []
    for code in codes:
        j = MOTOR_CODES.index(code)
        out.append((code, float(np.abs(seen[lost, j] - seen[0, j]).max()),
                    float(np.abs(values[lost, j] - seen[lost, j]).max())))
    return out


def test_a_blink_and_a_glance_while_one_eyes_markers_are_lost_show_on_both_eyes():
    """The left upper lid's and pupil's markers are lost for 2.5 s (longer than gap filling fills,
    as a fourth-performer draw lost its left lid over a blink): the left eye blinks and glances as
    it did with its markers seen, where before it eased to rest and missed both."""
    cues = (Cue("blink", 2.5, 0.25), Cue("gaze", 3.0, 1.0, x=0.8, y=-0.6))
    for code, moved, missed in _lost_over(cues, ("LID_L_UP", "PUPIL_L"), ("ELU", "PLH", "PLV")):
        assert moved > 0.05 and missed < 0.1 * moved, (code, moved, missed)


def test_live_a_blink_while_a_lid_marker_is_held_shows_as_the_other_eyes():
    """Live, a marker lost for up to half a second is held at its last place: the left upper lid's
    marker, lost for 0.4 s over a blink, held the lid open while the right eye blinked. Its
    partner was measured, so the lid follows it (``pair``), as deep as with the marker seen."""
    cues = (Cue("blink", 2.5, 0.2),)
    syn = synthesize(seconds=4.0, rate=60.0, noise_mm=0.0, performance=Performance(4.0, cues), seed=4)
    take = syn.take
    mapping, markerset = choose_mapping(take)
    profile = calibrate(mapping, prepare(take, markerset), (0.0, 1.0))
    lost = (take.times >= 2.3) & (take.times < 2.7)
    positions = take.positions.copy()
    positions[lost, take.index("LID_L_UP")] = np.nan
    elu = MOTOR_CODES.index("ELU")
    depths = []
    for frames in (take.positions, positions):
        live = LiveMapper(mapping, markerset, profile, take.labels, take.rate)
        values = np.array([live.step(frames[f], float(take.times[f]))[0] for f in range(take.frames)])
        depths.append(values[take.times < 2.2, elu].mean() - values[lost, elu].min())
    assert depths[0] > 0.5 and abs(depths[1] - depths[0]) < 0.1 * depths[0], depths


def test_offline_a_blink_that_gap_filling_missed_shows_as_the_other_eyes():
    """Offline, a fill the gap filler regressed from noisy markers blinked half or a fifth as deep
    (the third performer lost a lid over a blink: 0.72 seen, 0.18 filled). Here the left upper
    lid's samples over a blink are a fill that missed it (held open) and are marked filled; its
    partner was measured, so the lid follows it (``pair``), as deep as with the marker seen."""
    cues = (Cue("blink", 2.5, 0.2),)
    syn = synthesize(seconds=4.0, rate=60.0, noise_mm=0.0, performance=Performance(4.0, cues), seed=4)
    take = syn.take
    mapping, markerset = choose_mapping(take)
    prepared = prepare(take, markerset)
    profile = calibrate(mapping, prepared, (0.0, 1.0))
    stable, column = prepared.stable, prepared.columns["LID_L_UP"]
    lost = (take.times >= 2.3) & (take.times < 2.7)
    missed = stable.local.copy()
    missed[lost, column] = stable.local[np.flatnonzero(lost)[0] - 1, column]  # held open: the blink missed
    filled = np.zeros(missed.shape[:2], bool)
    filled[lost, column] = True
    elu = MOTOR_CODES.index("ELU")
    depths = []
    for local, made in ((stable.local, None), (missed, filled)):
        moved = Stabilised(local, stable.rotation, stable.translation, stable.ok, stable.reference)
        values = map_stabilised(moved, prepared.columns, take.times, take.rate, mapping, profile, filled=made).values
        depths.append(values[take.times < 2.2, elu].mean() - values[lost, elu].min())
    assert depths[0] > 0.5 and abs(depths[1] - depths[0]) < 0.1 * depths[0], depths


def test_a_raised_brow_whose_markers_are_lost_rises_with_the_other():
    """The right brow's three markers are lost for 2.5 s (longer than gap filling fills: the far
    brow of a head turned away) while both brows rise: the right brow rises with the left, where
    before it eased to rest and missed the raise."""
    cues = (Cue("expression", 2.0, 2.5, name="surprise", strength=1.0),)
    for code, moved, missed in _lost_over(cues, ("BROW_R_LAT", "BROW_R_CEN", "BROW_R_MED"), ("BRL", "BRC", "BRM")):
        assert moved > 0.1 and missed < 0.2 * moved, (code, moved, missed)


@pytest.mark.parametrize("left_made_up, expected", [
    (False, 0.9),  # the left outer brow measured: the right one takes its move plus its centre's lead
    (True, 0.6),  # both made up: the right keeps its fill
])
def test_a_brow_made_up_by_cleaning_follows_the_other_as_far_as_its_own_brow_does(left_made_up, expected):
    """Steady frames where the right outer brow was made up by cleaning (a fill that rose a quarter
    as far as it should: the fourth performer's far outer brow, lost for 1.5 s as the head turned,
    filled from the markers seen then, read a raise of that brow alone at 0.62 for 0.88) while
    the right brow's centre rose alone (0.9, the left brow at rest, neutrals 0.5): the made-up part
    is taken as a lost one, its partner's move plus how far its brow's centre moved beyond the other
    centre, 0.9 (it kept its fill, 0.6, before: ``made_up = false``); where its partner was made up
    too, it keeps its fill. The right upper lid, made up, takes the left lid's move."""
    mapping, _ = choose_mapping(synthesize(seconds=0.1, rate=60.0).take)
    face = np.full(len(MOTOR_CODES), 0.5)
    face[MOTOR_CODES.index("ELU")], face[MOTOR_CODES.index("ERU")] = 0.6, 0.7
    neutral = extended_neutral(face)  # with the parameters beyond the 21 (HT...)
    values = np.tile(neutral, (120, 1))
    brl, bll, brc, eru, elu = (MOTOR_CODES.index(c) for c in ("BRL", "BLL", "BRC", "ERU", "ELU"))
    values[:, brl], values[:, brc], values[:, eru], values[:, elu] = 0.6, 0.9, 0.3, 0.9
    made_up = np.zeros_like(values, dtype=bool)
    made_up[:, [brl, eru]] = True
    made_up[:, bll] = left_made_up
    out = MotorRules(mapping, 60.0, face).apply(values, np.arange(120) / 60.0, made_up)[-1]
    assert out[brl] == pytest.approx(expected, abs=1e-6) and out[bll] == pytest.approx(0.5, abs=1e-6)
    assert out[eru] == pytest.approx(0.9 - 0.6 + 0.7, abs=1e-6)


def test_a_solved_brow_whose_own_marker_was_filled_is_made_up_though_a_marker_it_nudges_was_seen():
    """The solver's confidence in the right outer brow is its basis's motion on the markers that
    counted: its own marker filled (quality 0.5) and the upper lid it lifts 0.2 mm a share seen
    made it 0.5002, which read as measured, so the made-up brow kept its fill. A solved motor
    whose own sources were all made up (the rules' confidence) is made up: at most 0.5."""
    mapping, _ = choose_mapping(synthesize(seconds=0.1, rate=60.0).take)
    basis = np.array([[[0.0, 10.0, 0.0], [0.0, 0.2, 0.0]]])  # (K=1, M=2, 3): the brow, the lid
    solver = Solver(("BRL",), ("BROW_R_LAT", "LID_R_UP"), np.zeros((2, 3)), basis, basis, 0.1)
    local = np.array([[[0.0, 5.0, 0.0], [0.0, 0.1, 0.0]]])  # half its way up
    quality = np.array([[FILLED_QUALITY, 1.0]])
    r = [rule.code for rule in mapping.rules].index("BRL")
    combined, sure = np.zeros((1, len(mapping.rules))), np.ones((1, len(mapping.rules)))
    sure[0, r] = FILLED_QUALITY  # its rule's one source, filled
    shares, confidence = solved_shares(solver, mapping, local, {"BROW_R_LAT": 0, "LID_R_UP": 1}, quality,
                                       combined, sure)
    assert shares[0, r] == pytest.approx(0.5, abs=1e-3)
    assert confidence[0, r] == pytest.approx(FILLED_QUALITY) and made_up(confidence[:, r]).all()
    sure[0, r] = 1.0  # measured: the solver's own confidence stands
    assert solved_shares(solver, mapping, local, {"BROW_R_LAT": 0, "LID_R_UP": 1}, quality, combined,
                         sure)[1][0, r] > FILLED_QUALITY


@pytest.mark.parametrize("left, right, expected", [
    ((0.9, 0.9, 0.9), (None, 0.5, 0.5), 0.5),  # the left brow raised alone: the right one rests
    ((0.9, 0.9, 0.9), (None, 0.9, 0.9), 0.9),  # both raised: the lost part rises with the rest
    ((0.5, 0.5, 0.9), (None, 0.5, 0.9), 0.5),  # both inner parts raised, the outer ones still
    ((None, 0.5, 0.5), (None, 0.7, 0.5), 0.7),  # its partner lost too: its own brow's centre
])
def test_a_lost_brow_part_follows_the_other_brow_as_far_as_its_own_brow_does(left, right, expected):
    """The right outer brow lost (the far brow of a turned head) with the rest of its brow seen:
    it took the left outer brow's move whole, and a raise of the left brow alone raised it by 0.4
    (fourth performer live, bench seed 2: BRL at r 0.44). It now takes its partner's move plus how
    far its brow's centre moved beyond the other centre, or, with its partner lost too, its own
    centre's move (``loss.near``; every brow motor's neutral 0.5 here)."""
    mapping, _ = choose_mapping(synthesize(seconds=0.1, rate=60.0).take)
    face = np.full(len(MOTOR_CODES), 0.5)
    values = np.tile(extended_neutral(face), (30, 1))
    for codes, parts in ((("BLL", "BLC", "BLM"), left), (("BRL", "BRC", "BRM"), right)):
        for code, value in zip(codes, parts, strict=True):
            values[:, MOTOR_CODES.index(code)] = np.nan if value is None else value
    out = MotorRules(mapping, 60.0, face).apply(values, np.arange(30) / 60.0)[-1]
    assert out[MOTOR_CODES.index("BRL")] == pytest.approx(expected, abs=1e-6)
