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
