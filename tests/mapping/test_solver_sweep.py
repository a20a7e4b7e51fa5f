"""What a range-of-motion sweep teaches the solver when a rule reads another group's motion as
more than its own motor's whole way (the small face of ``tests/helpers/small_face.py``)."""

import numpy as np
import pytest

from mapping.roles import mirror_pairs
from mapping.solver import learn_solver
from tests.helpers.small_face import CODES, COLUMNS, OWN, REST, face, motor_bases, rule_reading, sweep


def test_a_rule_read_past_its_end_while_another_group_moves_does_not_take_that_groups_markers():
    """The fourth performer's temples slide with the jaw, the head frame tilts with them, and a
    lower lid (3 mm of way) moved by 4.5 mm in it as the jaw opened in the sweep: its rule read
    1.5 of its way while the jaw's read 1.0, the jaw was not within 0.7 of the leader and so not
    moving, and the lid's motor learned the chin and lips (LIP_LOW_L 20 mm a share; the lid then
    read every opening of the mouth, r 0.43). A share past its end says no more than the end."""
    shares = sweep()
    local = face(shares)
    jaw = np.clip(shares[:, CODES.index("MB")], 0.0, None)
    local[:, COLUMNS["LID_R"], 1] += 4.5 * jaw  # the head frame's tilt, at the lid
    reading = rule_reading(local)
    assert reading[:, CODES.index("ER")].max() == pytest.approx(1.5)  # the lid read past its end
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), reading, REST)
    assert solver is not None
    er, mb = solver.codes.index("ER"), solver.codes.index("MB")
    for name in ("CHIN", "LIP_LOW", "MOUTH_L"):
        assert np.abs(solver.up[er, solver.markers.index(name)]).max() < 0.01, name  # the jaw's, not the lid's
    np.testing.assert_allclose(solver.up[mb, solver.markers.index("CHIN")], [0.0, -8.0, -2.0], atol=0.05)
    assert solver.up[er, solver.markers.index("LID_R"), 1] == pytest.approx(3.0, abs=0.5)


def test_a_motors_own_markers_pair_with_its_mirror_motors_where_their_placement_does_not():
    """The left brow's marker placed 12 mm out and 4 up of the right's mirror image (on a draw of
    the fourth performer, lower lids' mirror images 14 mm apart): no pair by geometry, but the two
    brows' own markers are each other's by their motors. The right brow's marker hidden while the
    brows were lowered, that side is still the left's mirrored (6 mm a share), not its raise
    through rest (8)."""
    shares = sweep()
    local = face(shares)
    reading = rule_reading(local)
    placed = np.array([12.0, 4.0, 3.0])
    local[:, COLUMNS["BROW_L"]] += placed
    rest = REST.copy()
    rest[COLUMNS["BROW_L"]] += placed
    assert mirror_pairs(rest)[COLUMNS["BROW_R"]] == -1
    seen = np.ones(local.shape[:2], bool)
    seen[shares[:, CODES.index("BR")] < 0, COLUMNS["BROW_R"]] = False
    paired = ("BRC", "BLC", "ERL", "MRH", "MB")  # the small face's motors under codes with mirrors
    solver = learn_solver(paired, OWN, local, COLUMNS, seen, reading, rest)
    assert solver is not None
    assert solver.notes == {"from_mirror": "BRC low"}
    brow = solver.markers.index("BROW_R")
    np.testing.assert_allclose(solver.down[paired.index("BRC"), brow], (0.0, 6.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(solver.up[paired.index("BRC"), brow], (0.0, 8.0, 0.0), atol=1e-9)


def test_a_mirror_motor_that_moves_the_same_way_across_is_not_mirrored():
    """Two pupils turn together: a right pupil's turn mirrored read every glance of the left
    backwards (PLH r 0.37 on a draw of the fourth performer). Here the brows swing out to the
    same side as they rise and fall; the right brow's lowering, its marker hidden, is the left's
    as it is (4 mm across a share), not mirrored (-4)."""
    up, down = motor_bases()
    for code, marker in (("BR", "BROW_R"), ("BL", "BROW_L")):
        up[CODES.index(code), COLUMNS[marker]] = (3.0, 8.0, 0.0)
        down[CODES.index(code), COLUMNS[marker]] = (4.0, 6.0, 0.0)
    shares = sweep()
    local = face(shares, (up, down))
    seen = np.ones(local.shape[:2], bool)
    seen[shares[:, CODES.index("BR")] < 0, COLUMNS["BROW_R"]] = False
    paired = ("BRC", "BLC", "ERL", "MRH", "MB")
    solver = learn_solver(paired, OWN, local, COLUMNS, seen, rule_reading(local, (up, down)), REST)
    assert solver is not None and solver.notes == {"from_mirror": "BRC low"}
    np.testing.assert_allclose(solver.down[paired.index("BRC"), solver.markers.index("BROW_R")], (4.0, 6.0, 0.0),
                               atol=1e-9)


def test_a_marker_a_mapping_says_shows_another_motor_is_that_motors_while_it_moves():
    """The third performer's lids rise 0.9 mm with the brow's centre, and its whole brow is swept
    at once: the lift went to the nearest of the brow's motors, or under the wobble's threshold to
    none, and every raised brow read as the lid opening (seed 2: ELU 3.0 % where the rules, which
    decouple the lid from the brow's centre as the mapping says, had 2.6). Here the left brow lifts the
    right lid 0.6 mm, and the right brow, swept with it, is nearer the lid: without the mapping's
    word the lift is the right brow's."""
    up, down = motor_bases()
    up[CODES.index("BL"), COLUMNS["LID_R"]] = (0.0, 0.6, 0.0)
    bases = (up, down)
    local = face(sweep(), bases)
    seen = np.ones(local.shape[:2], bool)
    reading = rule_reading(local, bases)
    couples = [(), (), ("BL",), (), ()]  # the lid's rule decouples the left brow
    plain = learn_solver(CODES, OWN, local, COLUMNS, seen, reading, REST)
    taught = learn_solver(CODES, OWN, local, COLUMNS, seen, reading, REST, couples=couples)
    assert plain is not None and taught is not None
    lid = plain.markers.index("LID_R")
    np.testing.assert_allclose(plain.up[CODES.index("BR"), lid], (0.0, 0.6, 0.0), atol=1e-9)  # the nearest mover's
    assert not plain.up[CODES.index("BL"), lid].any()
    np.testing.assert_allclose(taught.up[CODES.index("BL"), lid], (0.0, 0.6, 0.0), atol=1e-9)
    assert not taught.up[CODES.index("BR"), lid].any()
    raised = np.zeros((1, len(CODES)))
    raised[0, CODES.index("BL")] = 1.0
    er = CODES.index("ER")
    assert plain.solve(face(raised, bases), COLUMNS)[0][0, er] == pytest.approx(0.2, abs=0.01)  # read as the lid
    shares = taught.solve(face(raised, bases), COLUMNS)[0][0]
    assert abs(shares[er]) < 0.01 and shares[CODES.index("BL")] == pytest.approx(1.0, abs=0.01)


def test_a_side_that_moves_none_of_its_own_markers_is_not_learned():
    """A jaw's closing past rest in the third performer's sweep moved its own markers by under
    0.15 mm and a mouth corner (whose rule decouples the jaw) by 0.16: that side alone, the jaw
    read every frame's tenths of a millimetre at the corner as clenched far past its end (MB
    13 % where it had 1)."""
    up, down = motor_bases()
    mb = CODES.index("MB")
    down[mb] = 0.0
    down[mb, COLUMNS["CHIN"]] = (0.0, -0.1, 0.0)  # the rule still reads its low end
    down[mb, COLUMNS["MOUTH_R"]] = (0.0, 0.3, 0.0)
    bases = (up, down)
    local = face(sweep(), bases)
    couples = [(), (), (), ("MB",), ()]  # the corner's rule decouples the jaw
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), rule_reading(local, bases),
                          REST, couples=couples)
    assert solver is not None
    assert not solver.down[solver.codes.index("MB")].any()
    np.testing.assert_allclose(solver.up[solver.codes.index("MB"), solver.markers.index("MOUTH_R")], (0, -5, 0),
                               atol=1e-9)


def test_of_several_motors_a_mapping_names_moving_at_once_the_first_named_takes_the_marker():
    """``toon32`` lifts each upper lid with the three parts of its brow. A sweep that moves them
    at once cannot tell which carries the lift: shared among all named, each part's raise lifted
    the lid by a third, where the third performer lifts it with the centre alone. The first
    named takes it, as the rules' couplings do (:mod:`mapping.coupling`). Here both brows are
    named for the right lid and swept together: the left, named first, takes all 0.6 mm."""
    up, down = motor_bases()
    up[CODES.index("BL"), COLUMNS["LID_R"]] = (0.0, 0.6, 0.0)
    bases = (up, down)
    local = face(sweep(), bases)
    taught = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), rule_reading(local, bases),
                          REST, couples=[(), (), ("BL", "BR"), (), ()])
    assert taught is not None
    lid = taught.markers.index("LID_R")
    np.testing.assert_allclose(taught.up[CODES.index("BL"), lid], (0.0, 0.6, 0.0), atol=1e-9)
    assert not taught.up[CODES.index("BR"), lid].any()


@pytest.mark.parametrize(("lid_mm", "kept"), [(3.0, True), (10.0, False)])
def test_a_motor_keeps_a_marker_it_moves_by_a_real_share_of_what_the_markers_own_motor_does(lid_mm, kept):
    """The fourth performer's smile lifts a lower lid 0.7-0.8 mm a share, under a tenth of the
    mouth corner's 9 mm: dropped as a head fit's wobble, every smile read as the lid raised (ERL
    2.9 % on bench seed 3, 2.6 kept). To a lid that travels 3 mm that is a fifth of its way, and it stays; to one
    that travels 10 it is the wobble it was. Here the smile moves its corner 7.2 mm a share and
    lifts the lid 0.6 (under the 0.72 a tenth of the corner would ask)."""
    up, down = motor_bases()
    mr, er = CODES.index("MR"), CODES.index("ER")
    up[mr, COLUMNS["LID_R"]] = (0.0, 0.6, 0.0)
    up[er, COLUMNS["LID_R"]] = (0.0, lid_mm, 0.0)
    bases = (up, down)
    local = face(sweep(), bases)
    solver = learn_solver(CODES, OWN, local, COLUMNS, np.ones(local.shape[:2], bool), rule_reading(local, bases), REST)
    assert solver is not None
    lid = solver.markers.index("LID_R")
    np.testing.assert_allclose(solver.up[mr, lid], (0.0, 0.6 if kept else 0.0, 0.0), atol=1e-9)
    smile = np.zeros((1, len(CODES)))
    smile[0, mr] = 1.0
    shares = solver.solve(face(smile, bases), COLUMNS)[0][0]
    assert shares[er] == pytest.approx(0.0 if kept else 0.6 / lid_mm, abs=0.01)  # else the lift reads as the lid
    assert shares[mr] == pytest.approx(1.0, abs=0.01)
