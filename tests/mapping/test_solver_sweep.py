"""What a range-of-motion sweep teaches the solver when a rule reads another group's motion as
more than its own motor's whole way (the small face of ``tests/helpers/small_face.py``)."""

import numpy as np
import pytest

from mapping.solver import learn_solver
from tests.helpers.small_face import CODES, COLUMNS, OWN, REST, face, rule_reading, sweep


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
