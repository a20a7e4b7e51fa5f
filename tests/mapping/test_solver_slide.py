"""A head reference that slides with the skin, lost while the face moves (mapping.solver_slide):
a small head of seven references whose temples slide down and back as the jaw opens, a chin
and two lower lids. The head is fitted and bridged as cleaning fits and bridges it."""

from dataclasses import replace

import numpy as np
import pytest

from common.rotations import rigid_fit
from common.validate import Validator
from mapping.reference_bridge import bridge_references
from mapping.solver import Solver, learn_solver
from mapping.solver_slide import reference_shift, rigid_shift, slide_gain
from mapping.stabilise import to_head_frame

REFS = {"FOREHEAD": (0, 55, 8), "TEMPLE_R": (-66, 12, -28), "TEMPLE_L": (66, 12, -28), "NOSE_BRIDGE": (0, -6, 14),
        "NOSE_TIP": (0, -44, 32), "EYE_R_IN": (-15, 0, 10), "EYE_L_IN": (15, 0, 10)}
FACE = {"CHIN": (0, -90, 20), "LID_L": (30, -12, 15), "LID_R": (-30, -12, 15)}
LABELS = (*REFS, *FACE)
COLUMNS = {label: i for i, label in enumerate(LABELS)}
REST = np.array([*REFS.values(), *FACE.values()], dtype=float)
ROWS = list(range(len(REFS)))
CODES, OWN = ("MB", "EL", "ER"), (("CHIN",), ("LID_L",), ("LID_R",))
SLIDE = np.array([0.0, -0.5, -0.8])  # each temple, per unit of the jaw's share (mm)


def _world(motors: np.ndarray) -> np.ndarray:
    """Markers ``(F, M, 3)`` for motor shares ``(F, 3)`` (MB, EL, ER), the head still."""
    out = np.tile(REST, (len(motors), 1, 1))
    mb, el, er = motors.T
    out[:, COLUMNS["CHIN"]] += mb[:, None] * [0.0, -10.0, -3.0]
    for temple in ("TEMPLE_R", "TEMPLE_L"):
        out[:, COLUMNS[temple]] += mb[:, None] * SLIDE
    out[:, COLUMNS["LID_L"]] += el[:, None] * [0.0, 3.0, 0.0]
    out[:, COLUMNS["LID_R"]] += er[:, None] * [0.0, 3.0, 0.0]
    return out


def _local(world: np.ndarray) -> np.ndarray:
    """``world`` in the head fitted on the references it sees, bridged where one is lost."""
    shape = REST[ROWS]
    rot, trans, ok = rigid_fit(shape, world[:, ROWS])
    rot, trans = bridge_references(world[:, ROWS], shape, rot, trans, ok, edge=1)
    return to_head_frame(world, rot, trans)


def _learned() -> Solver:
    ramp = np.sin(np.linspace(0, 2 * np.pi, 80))  # each motor to both ends and back, alone
    sweep = np.zeros((3 * len(ramp), 3))
    for k in range(3):
        sweep[k * len(ramp):(k + 1) * len(ramp), k] = ramp
    local = _local(_world(sweep))
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), sweep, REST, tuple(REFS))
    assert solver is not None
    return solver


def test_the_sweep_teaches_what_the_jaw_does_to_the_references_in_the_head_fitted_on_all():
    solver = _learned()
    assert solver.references == tuple(REFS)
    opened, shut = _local(_world(np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])))[:, ROWS] - REST[ROWS]
    mb = solver.codes.index("MB")  # the departures in the fit on all, at either end
    np.testing.assert_allclose(solver.slide_up[mb], opened, atol=2e-3)  # the fit is a rotation: near linear
    np.testing.assert_allclose(solver.slide_down[mb], -shut, atol=2e-3)
    assert np.abs(opened[list(REFS).index("TEMPLE_L")]).max() > 0.3  # the fit shares out only part of it
    assert np.abs(solver.slide_up[[solver.codes.index("EL"), solver.codes.index("ER")]]).max() < 1e-9
    again = Solver.from_dict(solver.to_dict(), Validator("me.toml"))
    assert again.references == solver.references
    np.testing.assert_allclose(again.slide_up, solver.slide_up, atol=1e-6)
    older = {k: v for k, v in solver.to_dict().items() if k not in ("references", "slide_up", "slide_down")}
    assert Solver.from_dict(older, Validator("me.toml")).slide_up.shape == (3, 0, 3)  # a profile from before


def _jaw_with_a_temple_lost() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """300 frames: the jaw opens and shuts three times, the lids at rest; the left temple lost
    in the middle 100 (the jaw shut at both edges, open inside). Head-frame markers with it lost,
    the same with it seen throughout, and the frames without it."""
    motors = np.zeros((300, 3))
    motors[:, 0] = np.sin(np.linspace(0, 3 * np.pi, 300)) ** 2
    world = _world(motors)
    whole = _local(world)
    lost = np.zeros(300, bool)
    lost[100:200] = True
    world[lost, COLUMNS["TEMPLE_L"]] = np.nan
    return _local(world), whole, lost


def test_a_lost_temple_while_the_jaw_moves_is_not_read_as_the_lids_moving():
    """Read as the same face with the temple seen (where the jaw's own fit moves the lids by a
    few hundredths of a millimetre, the solver reads them as it reads them there)."""
    solver = _learned()
    local, whole, lost = _jaw_with_a_temple_lost()
    shares, _ = solver.solve(local, COLUMNS)
    seen, _ = solver.solve(whole, COLUMNS)
    np.testing.assert_allclose(shares, seen, atol=0.002)
    # the fault: the head fitted on the near temple alone turns with its slide, the bridge carries
    # only the shut jaw's difference at the edges, and the lids read as moving with the jaw
    still = replace(solver, references=(), slide_up=np.zeros((3, 0, 3)), slide_down=np.zeros((3, 0, 3)))
    before, _ = still.solve(local, COLUMNS)
    lids = [solver.codes.index("EL"), solver.codes.index("ER")]
    assert np.abs(before[lost][:, lids] - seen[lost][:, lids]).max() > 0.03
    np.testing.assert_array_equal(before[~lost], shares[~lost])  # frames that saw every reference: as they were


def test_slides_the_take_does_not_bear_out_are_not_taken_out():
    """References that do not slide, where the sweep taught them jitter as motion: the take's
    whole frames show no such motion, so nothing is taken out."""
    solver = _learned()
    motors = np.zeros((300, 3))
    motors[:, 0] = np.sin(np.linspace(0, 3 * np.pi, 300)) ** 2
    world = _world(motors)
    world[:, [COLUMNS["TEMPLE_R"], COLUMNS["TEMPLE_L"]]] = REST[[COLUMNS["TEMPLE_R"], COLUMNS["TEMPLE_L"]]]
    world[100:200, COLUMNS["TEMPLE_L"]] = np.nan
    local = _local(world)
    still = replace(solver, references=(), slide_up=np.zeros((3, 0, 3)), slide_down=np.zeros((3, 0, 3)))
    np.testing.assert_array_equal(solver.solve(local, COLUMNS)[0], still.solve(local, COLUMNS)[0])
    rng = np.random.default_rng(62)
    predicted = rng.normal(0.0, 0.3, (150, 2, 3))
    every = np.ones(150, bool)
    assert slide_gain(predicted, 0.5 * predicted + 3.0, every) == pytest.approx(0.5)  # 3 mm off rest is no slide
    jitter = 0.3 * predicted + rng.normal(0.0, 0.5, predicted.shape)  # in step, but explaining a tenth of it
    assert slide_gain(predicted, jitter, every) == 0.0 and slide_gain(predicted, jitter / 5.0, every) == 0.0
    assert slide_gain(predicted, 2.0 * predicted, every) == 1.0 and slide_gain(predicted, -predicted, every) == 0.0
    assert slide_gain(predicted, np.zeros((150, 2, 3)), every) == 0.0
    assert slide_gain(predicted, predicted, np.arange(150) < 99) == 0.0  # too few whole frames to bear them out


def test_the_small_rigid_motion_matches_a_full_rigid_fit_and_the_bridge_is_not_counted_twice():
    rest = REST[ROWS]
    rng = np.random.default_rng(62)
    departures = rng.normal(0.0, 0.3, (4, len(rest), 3))
    keep = np.ones(len(rest), bool)
    keep[list(REFS).index("TEMPLE_L")] = False
    w, t = rigid_shift(rest, departures, keep)
    rot, trans, _ = rigid_fit(rest[keep], (rest + departures)[:, keep])  # rest -> moved; ours moves back
    moved_back = rest + departures + np.cross(w[:, None], rest) + t[:, None]
    exact = np.einsum("fji,fkj->fki", rot, (rest + departures) - trans[:, None])  # the moved points fitted back
    np.testing.assert_allclose(moved_back[:, keep], exact[:, keep], atol=0.02)
    seen = np.ones((5, len(rest)), bool)
    seen[1:4] = keep  # a stretch of 3 frames between two whole ones
    steady = np.tile(departures[:1], (5, 1, 1))  # the slide as at the edges throughout: the bridge has it all
    assert np.abs(reference_shift(rest, steady, seen)).max() == pytest.approx(0.0, abs=1e-12)
    alone = reference_shift(rest, steady, np.tile(keep, (5, 1)))  # no frame seen whole: the bridge had none either
    np.testing.assert_allclose(alone, np.tile(np.hstack([w[0], t[0]]), (5, 1)), atol=1e-12)


def test_a_reference_lost_for_a_frame_inside_a_longer_loss_is_bridged_from_the_whole_loss():
    """A second reference lost for a frame inside the temple's loss: the bridge carries what the
    edges of the whole loss read into that frame too (:func:`mapping.reference_bridge.enclosing`),
    so a slide as at the edges throughout leaves nothing to take out there either; read as a
    stretch with no whole neighbour, the frame had its whole slide taken out again."""
    rest = REST[ROWS]
    departures = np.random.default_rng(62).normal(0.0, 0.3, (1, len(rest), 3))
    seen = np.ones((7, len(rest)), bool)
    seen[1:6, list(REFS).index("TEMPLE_L")] = False
    seen[3, list(REFS).index("NOSE_TIP")] = False
    shift = reference_shift(rest, np.tile(departures, (7, 1, 1)), seen)
    assert np.abs(shift).max() == pytest.approx(0.0, abs=1e-12)


def test_the_slide_the_bridge_faded_is_taken_out_where_it_faded():
    """The bridge fades what it carries into a stretch (:func:`mapping.reference_bridge.held`): a
    slide steady through the stretch is left, inside it, as much as the bridge let go of."""
    rest = REST[ROWS]
    departures = np.random.default_rng(62).normal(0.0, 0.3, (1, len(rest), 3))
    keep = np.ones(len(rest), bool)
    keep[list(REFS).index("TEMPLE_L")] = False
    seen = np.ones((7, len(rest)), bool)
    seen[1:6] = keep  # a stretch of 5 frames between two whole ones
    w, t = rigid_shift(rest, departures, keep)
    whole = np.hstack([w[0], t[0]])
    shift = reference_shift(rest, np.tile(departures, (7, 1, 1)), seen, fade=2.0)
    let_go = 1.0 - np.exp(-np.array([1.0, 2.0, 3.0, 2.0, 1.0]) / 2.0)  # 1, 2, 3 frames from the nearer edge
    np.testing.assert_allclose(shift[1:6], let_go[:, None] * whole, atol=1e-12)
    assert np.abs(shift[[0, 6]]).max() == 0.0
