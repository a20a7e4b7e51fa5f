"""The sweep-taught solver (mapping.solver) on a small face whose motors are known exactly: a
linear face, each motor moving its markers by a known amount per unit of share on each side of
rest, a smile that lifts the lower lid, a mirror pair of brows that lift the nose between them."""

import numpy as np
import pytest

from mapping.roles import mirror_pairs
from mapping.solver import MIN_CONFIDENCE, learn_solver
from tests.helpers.small_face import CODES, COLUMNS, MARKERS, OWN, REST
from tests.helpers.small_face import face as _face
from tests.helpers.small_face import motor_bases as _bases
from tests.helpers.small_face import rule_reading as _rule_reading
from tests.helpers.small_face import sweep as _sweep


def _learned():
    sweep = _sweep()
    local = _face(sweep)
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), _rule_reading(local), REST)
    assert solver is not None
    return solver


def test_the_sweep_teaches_each_motor_its_markers_on_each_side():
    solver = _learned()
    up, down = _bases()
    assert solver.codes == CODES
    order = [solver.markers.index(m) for m in MARKERS]
    np.testing.assert_allclose(solver.up[:, order], up, atol=1e-9)
    np.testing.assert_allclose(solver.down[:, order], down, atol=1e-9)
    assert solver.noise == pytest.approx(0.05)  # a noise-free sweep: its floor


def test_every_motor_is_solved_at_once_and_a_smile_is_not_a_lid_raise(monkeypatch):
    """Exact data, solved without the ridge (it pulls this face's small motors up to 0.045 towards rest)."""
    monkeypatch.setattr("mapping.solver_frames.RIDGE", 1e-9)
    solver = _learned()
    rng = np.random.default_rng(62)
    truth = rng.uniform(-1, 1, (200, len(CODES)))
    shares, confidence = solver.solve(_face(truth), COLUMNS)
    np.testing.assert_allclose(shares, truth, atol=0.01)
    assert (confidence == 1).all()
    smile = np.zeros((1, len(CODES)))
    smile[0, CODES.index("MR")] = 1.0
    assert _rule_reading(_face(smile))[0, CODES.index("ER")] == pytest.approx(0.5)  # what a rule sees
    shares, _ = solver.solve(_face(smile), COLUMNS)
    assert shares[0, CODES.index("MR")] == pytest.approx(1.0, abs=0.01)
    assert abs(shares[0, CODES.index("ER")]) < 0.01


def test_a_lost_marker_is_left_out_and_a_motor_with_none_of_its_markers_is_unseen():
    solver = _learned()
    truth = np.array([[0.3, -0.4, 0.6, 0.5, 0.2]])
    local = _face(truth)
    local[0, COLUMNS["LID_R"]] = np.nan
    shares, confidence = solver.solve(local, COLUMNS)
    er, mr = CODES.index("ER"), CODES.index("MR")
    assert np.isnan(shares[0, er]) and confidence[0, er] < MIN_CONFIDENCE
    assert shares[0, mr] == pytest.approx(0.5, abs=0.01)  # its mouth corner still says
    assert 0.9 < confidence[0, mr] < 1.0  # less the lid's part of the smile


def test_a_swapped_marker_is_down_weighted_not_believed():
    solver = _learned()
    truth = np.array([[0.0, 0.0, 0.0, 0.0, 0.4]])
    local = _face(truth)
    local[0, COLUMNS["LIP_LOW"], 1] -= 10.0  # a label swapped with a marker 10 mm lower
    shares, _ = solver.solve(local, COLUMNS)
    mb = CODES.index("MB")
    assert shares[0, mb] == pytest.approx(0.4, abs=0.05)
    # plain least squares on the jaw's own basis believes it: far off
    basis = solver.up[mb].ravel()
    plain = float(basis @ (local[0] - REST)[[COLUMNS[m] for m in solver.markers]].ravel() / (basis @ basis))
    assert abs(plain - 0.4) > 0.3


def test_a_mirror_pair_swept_together_keeps_its_own_side_and_shares_the_midline():
    solver = _learned()
    br, bl = solver.codes.index("BR"), solver.codes.index("BL")
    left, right, nose = (solver.markers.index(m) for m in ("BROW_L", "BROW_R", "NOSE"))
    assert np.allclose(solver.up[br, left], 0) and np.allclose(solver.up[bl, right], 0)
    # the nose between them rises 2 mm with both: half each
    assert solver.up[br, nose, 1] == pytest.approx(1.0) and solver.up[bl, nose, 1] == pytest.approx(1.0)


def _group_frames(code: str) -> np.ndarray:
    """The sweep's frames where ``code``'s group is held at its high end, ``(F,)`` bool."""
    sweep = _sweep()
    return sweep[:, CODES.index(code)] == 1.0


def test_a_label_swapped_in_the_sweep_does_not_teach_a_motor_to_move_it():
    sweep = _sweep()
    local = _face(sweep)
    swapped = np.flatnonzero(_group_frames("ER"))[:8]  # the brows swap labels while the lid is up
    local[swapped[:, None], [COLUMNS["BROW_R"], COLUMNS["BROW_L"]]] = local[swapped[:, None],
                                                                          [COLUMNS["BROW_L"], COLUMNS["BROW_R"]]]
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), _rule_reading(local), REST)
    assert solver is not None
    er = solver.codes.index("ER")
    brows = [solver.markers.index(m) for m in ("BROW_R", "BROW_L")]
    # believed, the swap is the lid's: 60 mm across in 8 of its 27 frames' worth of share, about 18 mm a share
    assert np.abs(solver.up[er, brows]).max() < 0.01
    assert solver.up[er, solver.markers.index("LID_R"), 1] == pytest.approx(3.0, abs=0.01)


def test_a_marker_that_is_another_motors_but_for_a_few_frames_is_not_taken():
    sweep = _sweep()
    local = _face(sweep)
    reading = _rule_reading(local)
    held = np.flatnonzero(_group_frames("BR"))[:6]
    reading[held, CODES.index("BR")] = 0.0  # a swap read by the right brow's rule: it seems still
    local[held, COLUMNS["BROW_R"]] = REST[COLUMNS["NOSE"]]  # ... its marker where the nose is
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), reading, REST)
    assert solver is not None
    bl, right = solver.codes.index("BL"), solver.markers.index("BROW_R")
    # the right brow's marker went to the left brow's motor in those 6 frames, and only in them
    assert np.allclose(solver.up[bl, right], 0.0) and np.allclose(solver.down[bl, right], 0.0)
    assert solver.up[bl, solver.markers.index("BROW_L"), 1] == pytest.approx(8.0, abs=0.01)


def test_a_marker_never_seen_on_one_side_of_its_motor_takes_the_other_side():
    sweep = _sweep()
    local = _face(sweep)
    seen = np.ones(local.shape[:2], bool)
    er = CODES.index("ER")
    seen[sweep[:, er] > 0, COLUMNS["LID_R"]] = False  # the lid's marker hidden whenever the lid is up
    reading = _rule_reading(_face(sweep))  # the rule's share from a filled guess of it
    solver = learn_solver(CODES, OWN, local, COLUMNS, seen, reading, REST)
    assert solver is not None
    lid = solver.markers.index("LID_R")
    np.testing.assert_allclose(solver.down[solver.codes.index("ER"), lid], (0.0, 1.0, 0.0), atol=1e-9)
    # through rest from the side it was seen on, not still (which left the lid unsolved on that side)
    np.testing.assert_allclose(solver.up[solver.codes.index("ER"), lid], (0.0, 1.0, 0.0), atol=1e-9)


def test_a_side_the_sweep_showed_without_its_marker_takes_the_mirror_motors():
    """The right brow's marker hidden whenever the brows were lowered (on a draw of the fourth
    performer, a lid's marker through all of its closing): through rest the brow's raise, 8 mm a
    share, stood for its lowering, 6; the left brow lowered in view, so the right takes its side,
    mirrored. The small face's codes have no mirror, so their learning shows the old way."""
    sweep = _sweep()
    local = _face(sweep)
    seen = np.ones(local.shape[:2], bool)
    seen[sweep[:, CODES.index("BR")] < 0, COLUMNS["BROW_R"]] = False
    reading = _rule_reading(local)
    paired = ("BRC", "BLC", "ERL", "MRH", "MB")  # the same motors under codes with mirrors (BRC <-> BLC)
    solver = learn_solver(paired, OWN, local, COLUMNS, seen, reading, REST)
    unpaired = learn_solver(CODES, OWN, local, COLUMNS, seen, reading, REST)
    assert solver is not None and unpaired is not None
    brow, nose = solver.markers.index("BROW_R"), solver.markers.index("NOSE")
    np.testing.assert_allclose(unpaired.down[CODES.index("BR"), brow], (0.0, 8.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(solver.down[paired.index("BRC"), brow], (0.0, 6.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(solver.down[paired.index("BRC"), nose], (0.0, 1.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(solver.up[paired.index("BRC")], unpaired.up[CODES.index("BR")], atol=1e-9)
    assert solver.notes == {"from_mirror": "BRC low"}
    assert solver.left_out() == ("; BRC low taken from the mirror motor's (the sweep never saw the motor's own "
                                 "markers there)")
    lowered = np.zeros((1, len(CODES)))
    lowered[0, :2] = -0.5
    shares, _ = solver.solve(_face(lowered), COLUMNS)
    assert shares[0, paired.index("BRC")] == pytest.approx(-0.5, abs=0.01)


def test_mirror_partners_are_paired_as_a_whole_and_an_unknown_rest_has_none():
    """A lid placed 2.5 mm off lies nearer the mirror image of the pupil beside the other lid
    than of that lid; paired as a whole, each lid gets the other."""
    rest = np.array([[-30.0, 6.0, 10.0], [-34.0, 2.0, 10.0], [33.0, 4.0, 10.0], [34.5, 1.5, 10.0],
                     [0.0, -60.0, 20.0], [0.0, 50.0, 10.0], [np.nan, np.nan, np.nan]])
    # lid R, pupil R, lid L, pupil L, chin, forehead, a marker never seen at rest
    image = rest[2] * (-1, 1, 1)  # the left lid's mirror image: nearer the right pupil than the right lid
    assert np.linalg.norm(rest[1] - image) < np.linalg.norm(rest[0] - image)
    assert mirror_pairs(rest).tolist() == [2, 3, 0, 1, 4, 5, -1]


def test_a_marker_unseen_on_one_side_is_scaled_as_the_motors_own_seen_ones():
    """The jaw's chin hidden while the jaw opened: through rest alone its clench (1 mm a share)
    stood for its opening (8), and an opening with the chin seen read as eight times as wide.
    Scaled by how far the jaw's own marker seen on both sides (the lower lip) reaches on each."""
    sweep = _sweep()
    local = _face(sweep)
    seen = np.ones(local.shape[:2], bool)
    mb = CODES.index("MB")
    seen[sweep[:, mb] > 0, COLUMNS["CHIN"]] = False
    solver = learn_solver(CODES, OWN, local, COLUMNS, seen, _rule_reading(local), REST)
    assert solver is not None
    k, chin = solver.codes.index("MB"), solver.markers.index("CHIN")
    ratio = np.hypot(8.0, 1.0) / 1.0  # the lower lip's reach up over down
    np.testing.assert_allclose(solver.up[k, chin], (0.0, -ratio, 0.0), atol=1e-6)
    jaw = np.zeros((1, len(CODES)))
    jaw[0, mb] = 0.6
    shares, _ = solver.solve(_face(jaw), COLUMNS)
    assert shares[0, k] == pytest.approx(0.6, abs=0.05)


def test_a_big_jaw_keeps_the_mouth_corners_it_pulls_down():
    """A marker a motor moves by under a tenth of its furthest one was dropped as the head fit's
    wobble: a jaw whose chin drops 41 mm lost the corners' 3 mm, and a jaw opening then read as
    the corners pulled down (the second performer's MRV at r 0.81)."""
    up, down = _bases()
    mb = CODES.index("MB")
    up[mb, COLUMNS["CHIN"]] = (0, -40, -10)
    up[mb, COLUMNS["LIP_LOW"]] = (0, -35, -5)
    up[mb, COLUMNS["MOUTH_R"]] = up[mb, COLUMNS["MOUTH_L"]] = (0, -3, 0)
    bases = (up, down)
    local = _face(_sweep(), bases)
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), _rule_reading(local, bases),
                          REST)
    assert solver is not None
    np.testing.assert_allclose(solver.up[solver.codes.index("MB"), solver.markers.index("MOUTH_R")], (0, -3, 0),
                               atol=1e-9)
    jaw = np.zeros((1, len(CODES)))
    jaw[0, mb] = 0.8
    shares, _ = solver.solve(_face(jaw, bases), COLUMNS)
    assert abs(shares[0, solver.codes.index("MR")]) < 0.01
    assert shares[0, solver.codes.index("MB")] == pytest.approx(0.8, abs=0.01)


def test_a_far_markers_wobble_in_a_small_motors_sweep_is_not_its_motion():
    """A head fit wobbles by a few tenths of a millimetre with whatever moves; in a lid's sweep
    (3 mm) a lip's 0.4 mm passed the lid's threshold (a tenth of 3 mm), and then speech read as
    the lid moving. A marker that is not the motor's own must move by 0.5 mm a share."""
    sweep = _sweep()
    local = _face(sweep)
    er = CODES.index("ER")
    local[:, COLUMNS["LIP_LOW"], 2] += 0.4 * np.abs(sweep[:, er])  # wobble with the lid, either way
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), _rule_reading(local), REST)
    assert solver is not None
    k, lip = solver.codes.index("ER"), solver.markers.index("LIP_LOW")
    assert np.allclose(solver.up[k, lip], 0.0) and np.allclose(solver.down[k, lip], 0.0)
    np.testing.assert_allclose(solver.down[k, solver.markers.index("LID_R")], (0, 1, 0), atol=1e-9)  # its own: kept
    speech = np.zeros((1, len(CODES)))
    speech[0, CODES.index("MB")] = 0.5
    speech_local = _face(speech)
    speech_local[0, COLUMNS["LIP_LOW"], 2] += 1.0  # the lip pushed out as it speaks
    shares, _ = solver.solve(speech_local, COLUMNS)
    assert abs(shares[0, k]) < 0.01


def test_a_head_reference_is_no_motors_but_its_rules():
    """The head frame is fitted on its references, so what one does in it is the fit's wobble: a
    nose tip wobbling 0.6 mm with a lid's sweep (past the 0.5 mm a marker not the motor's own
    needs) was taken as the lid's, and the lid then read the still nose as a lid held still (the
    third performer's seed 26, ERU r 0.78). Given as a reference it is no motor's."""
    sweep = _sweep()
    local = _face(sweep)
    local[:, COLUMNS["NOSE"], 2] += 0.6 * np.abs(sweep[:, CODES.index("ER")])
    seen = np.ones(local.shape[:2], bool)
    plain = learn_solver(CODES, OWN, local, COLUMNS, seen, _rule_reading(local), REST)
    fixed = learn_solver(CODES, OWN, local, COLUMNS, seen, _rule_reading(local), REST, references=("NOSE",))
    assert plain is not None and fixed is not None
    k, nose = plain.codes.index("ER"), plain.markers.index("NOSE")
    assert np.linalg.norm(plain.up[k, nose]) == pytest.approx(0.6, abs=1e-6)  # taken without the references
    assert not fixed.up[:, nose].any() and not fixed.down[:, nose].any()
    lid = plain.markers.index("LID_R")
    np.testing.assert_array_equal(fixed.down[k, lid], plain.down[k, lid])  # the lid's own: as before


def test_a_motor_the_markers_do_not_show_is_named_not_solved():
    sweep = _sweep()
    local = _face(sweep)
    local[:, COLUMNS["LID_R"]] = REST[COLUMNS["LID_R"]]  # a rig whose lid marker does not move with the lid
    reading = _rule_reading(_face(sweep))
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), reading, REST)
    assert solver is not None
    assert "ER" not in solver.codes and solver.unobservable == ("ER",)


@pytest.mark.slow  # a sweep calibrated and a take mapped twice through the CLI: make test runs it
def test_calibrate_solve_keeps_the_solver_in_the_profile_and_map_solves_with_it(tmp_path, capsys):
    """Issue 62: the solver lived in memory only; calibrate --solve now writes it into the profile
    and map --profile reads it back and solves with it, as calibrate(..., solve=True) in memory."""
    from dataclasses import replace

    from capture import save_take, synthesize
    from capture.performance import default_performance
    from mapping import calibrate, choose_mapping, load_profile, map_take, prepare
    from toon import load_track
    from toonface.cli import main

    sweep_end = 1.0 + 1.2 * 7  # bench.generators.OWN_SWEEP_END: the own performer's calibration segment
    syn = synthesize(seed=4, performance=default_performance(sweep_end + 2.0, calibration=True, seed=4))
    take, profile_path = tmp_path / "take.npz", tmp_path / "me.toml"
    save_take(syn.take, take)
    assert main(["calibrate", str(take), "--neutral", "0:1", "--range", f"1:{sweep_end:g}", "--solve",
                 "-o", str(profile_path)]) == 0
    assert "the solver learned" in capsys.readouterr().err
    mapping, markerset = choose_mapping(syn.take)
    memory = calibrate(mapping, prepare(syn.take, markerset), (0.0, 1.0), range_window=(1.0, sweep_end), solve=True)
    saved = load_profile(profile_path)
    assert saved.solver is not None and memory.solver is not None
    assert saved.solver.codes == memory.solver.codes and saved.solver.markers == memory.solver.markers
    np.testing.assert_allclose(saved.solver.up, memory.solver.up, atol=1e-6)
    assert main(["map", str(take), "--profile", str(profile_path), "-o", str(tmp_path / "solved.csv")]) == 0
    solved = load_track(tmp_path / "solved.csv").values
    np.testing.assert_allclose(solved, map_take(syn.take, profile=memory).values, atol=1e-4)
    assert np.abs(solved - map_take(syn.take, profile=replace(memory, solver=None)).values).max() > 0.01
    assert main(["calibrate", str(take), "--solve", "-o", str(tmp_path / "x.toml")]) == 2  # no sweep named


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    """The own performer's take with its calibration segment, and a profile with a solver learned from it."""
    from capture import synthesize
    from capture.performance import default_performance
    from mapping import calibrate, choose_mapping, prepare

    sweep_end = 1.0 + 1.2 * 7  # bench.generators.OWN_SWEEP_END
    syn = synthesize(seed=4, performance=default_performance(sweep_end + 2.0, calibration=True, seed=4))
    mapping, markerset = choose_mapping(syn.take)
    profile = calibrate(mapping, prepare(syn.take, markerset), (0.0, 1.0), range_window=(1.0, sweep_end), solve=True)
    assert profile.solver is not None
    return syn.take, mapping, markerset, profile


@pytest.mark.slow
def test_a_rest_from_the_take_keeps_the_solver(swept):
    """Issue 62: a profile whose rest was taken from the take (``map --neutral``, or a profile
    lacking a range) lost its solver without a word and mapped by the rules; it keeps it, about
    the take's own rest."""
    from dataclasses import replace

    from mapping import map_take
    from mapping.workflow import ready_take

    take, _, _, profile = swept
    solved = map_take(take, profile=profile).values
    again = map_take(take, profile=profile, neutral_window=(0.0, 1.0)).values  # the same rest, from the take
    rules = map_take(take, profile=replace(profile, solver=None), neutral_window=(0.0, 1.0)).values
    np.testing.assert_allclose(again, solved, atol=2e-3)
    assert np.abs(again - rules).max() > 0.01
    said = [n for n in ready_take(take, profile=profile, neutral_window=(0.0, 1.0)).notes if "solver" in n]
    assert len(said) == 1 and all(code in said[0] for code in profile.solver.codes), said
    assert not [n for n in ready_take(take, profile=replace(profile, solver=None)).notes if "solver" in n]


def test_a_solver_at_another_rest_reads_the_same_motion_from_there():
    """The solver about a rest moved (markers glued again a millimetre off) solves the same motion
    from there; a marker the new rest lacks keeps the sweep's."""
    solver = _learned()
    shares = np.array([[0.5, 0.5, 0.0, 0.6, 0.0], [0.0, 0.0, 0.3, 0.0, 0.8]])
    shift = np.array([1.0, -0.5, 0.3])
    moved = solver.at_rest({name: REST[COLUMNS[name]] + shift for name in MARKERS if name != "NOSE"}
                           | {"NOSE": np.full(3, np.nan)})
    np.testing.assert_array_equal(moved.rest[solver.markers.index("NOSE")], solver.rest[solver.markers.index("NOSE")])
    local = _face(shares) + shift
    local[:, COLUMNS["NOSE"]] -= shift  # the nose where it rested in the sweep
    got, _ = moved.solve(local, COLUMNS)
    np.testing.assert_allclose(got, shares[:, [CODES.index(c) for c in solver.codes]], atol=0.02)


@pytest.mark.slow
def test_the_live_mapper_solves_with_the_profiles_solver(swept):
    """Issue 62: the live mapper took its rest by a profile without the solver and mapped by the
    rules; frame by frame it now solves as offline mapping does (within the live cleaning's
    lag), about the rest it took."""
    from dataclasses import replace

    from mapping import map_take
    from mapping.stepwise import LiveMapper

    take, mapping, markerset, learned = swept
    assert learned.solver is not None
    # taught motion twice what the sweep showed, so that the solver's shares are half the rules'
    # (the solver learned from this clean sweep maps within 0.02 of the rules here)
    profile = replace(learned, solver=replace(learned.solver, up=2 * learned.solver.up, down=2 * learned.solver.down))
    rules_only = replace(profile, solver=None)

    def live(chosen) -> np.ndarray:
        mapper = LiveMapper(mapping, markerset, chosen, take.labels, take.rate, rest_seconds=1.0)
        return np.array([mapper.step(take.positions[k], float(take.times[k]))[0] for k in range(take.frames)])

    offline, offline_rules = map_take(take, profile=profile).values, map_take(take, profile=rules_only).values
    solved, rules = live(profile), live(rules_only)
    after = slice(int(2 * take.rate), None)  # past the rest and the filters' start
    # the motors where the solver maps otherwise than the rules
    differ = np.abs(offline_rules[after] - offline[after]).max(axis=0) > 0.2
    assert differ.sum() >= 4
    live_gap = np.abs(solved[after] - offline[after]).max(axis=0)[differ]  # the live cleaning's lag
    assert (live_gap < 0.5 * np.abs(rules[after] - offline[after]).max(axis=0)[differ]).all()


def test_a_motor_the_sweep_never_moved_is_named_as_such_not_as_unseen_by_the_markers():
    """A sweep without the mouth (the own performer's moves brows, lids and pupils) called the
    mouth's motors "unobservable", as if the markers could not show them; they were never swept.
    The profile keeps which is which, and the notes say it."""
    from common.validate import Validator
    from mapping.solver import Solver

    sweep = _sweep()
    sweep[:, [CODES.index("MR"), CODES.index("MB")]] = 0.0  # the mouth held at rest throughout
    local = _face(sweep)
    local[:, COLUMNS["LID_R"]] = REST[COLUMNS["LID_R"]]  # and a lid marker that does not move with the lid
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), _rule_reading(_face(sweep)), REST)
    assert solver is not None and solver.codes == ("BR", "BL")
    assert solver.unswept == ("MR", "MB") and solver.unobservable == ("ER",)
    assert solver.left_out() == "; MR, MB not moved alone by the sweep; ER not shown by the markers (left to the rules)"
    again = Solver.from_dict(solver.to_dict(), Validator("me.toml"))
    assert again.unswept == solver.unswept and again.unobservable == solver.unobservable
