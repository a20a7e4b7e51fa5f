"""A face's parameters beyond the 21 in a studio session (issue 42), without a browser: sliders,
the face editor's parameters, the staves' knots, and control points drawn and dragged on a
tilted head."""

import numpy as np
import pytest
from studios import temp_folder

from toon import motor_index
from toonface.studio.messages import apply
from toonface.studio.session import StudioSession


def test_a_tilted_head_s_control_points_are_drawn_where_its_features_are_and_drag_back():
    session = StudioSession("classic", folder=temp_folder())
    session.set_motor("MB", 0.4)
    session.set_motor("HT", 1.0)
    frame = session.frame()
    assert frame["values"]["HT"] == 1.0 and frame["values"]["UL"] == 0.0
    upright = session.rig.control_points(session.values)[list(session.face.points).index("MB")]
    drawn = np.array(frame["points"]["MB"]) * [1, -1]  # SVG y down
    np.testing.assert_allclose(drawn, session.rig.tilted(upright[None], 1.0)[0], atol=1e-3)
    assert np.abs(drawn - upright).max() > 10  # the head is turned 25 degrees: the point moved
    session.drag("MB", *frame["points"]["MB"])  # dropped where it is drawn: nothing changes
    assert session.values[motor_index("MB")] == pytest.approx(0.4, abs=1e-6)


def test_face_editor_messages_declare_a_parameter_and_the_page_is_described_again():
    session = StudioSession("round", folder=temp_folder())
    changed, _ = apply(session, {"op": "faceedit", "action": "set_param", "code": "EARS", "neutral": 0.5,
                                 "point": "BRL", "dx": 0, "dy": 10}, 0.0)
    assert changed == "described"  # new sliders and staves
    (move,) = session.face.params[-1].points
    assert move.at0 == (0.0, -10.0) and move.at1 == (0.0, 10.0)  # 10 up at 1 from its rest at 0.5
    assert [m["code"] for m in session.describe()["groups"][-1]["motors"]][-1] == "EARS"
    changed, _ = apply(session, {"op": "faceedit", "action": "set_param", "code": "EARS", "point": "BRL",
                                 "dx": 0, "dy": 4}, 0.0)
    assert changed == "face" and session.face.params[-1].points[0].at1 == (0.0, 4.0)
    apply(session, {"op": "knot", "action": "add", "code": "EARS", "t": 1.0, "v": 1.0}, 0.0)
    assert session.editor.animation.knots["EARS"] == ((1.0, 1.0),)
    with pytest.raises(ValueError, match="unknown motor 'TAIL'; the face's parameters: HT, UL, JS, CP, FRINGE, EARS"):
        apply(session, {"op": "knot", "action": "add", "code": "TAIL", "t": 1.0, "v": 1.0}, 0.0)
    with pytest.raises(Exception, match="neutral is 0.0"):
        apply(session, {"op": "faceedit", "action": "set_param", "code": "UL", "neutral": 0.3}, 0.0)
    assert "UL" in session.face.extra_codes  # refused: the face as it was
    changed, _ = apply(session, {"op": "faceedit", "action": "delete_param", "code": "EARS"}, 0.0)
    assert changed == "described" and "EARS" not in session.face.extra_codes


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_head_turned_by_a_slider_swings_the_hair_which_settles_and_the_driver_is_tuned_live():
    session = StudioSession("classic", folder=temp_folder())
    session.tick(0.0)
    assert session.frame()["values"]["HAIR"] == 0.5 and not session.busy()
    session.set_motor("HH", 0.9)  # a quick turn
    swings = []
    for k in range(1, 181):
        session.tick(k / 30)
        swings.append(session.frame()["values"]["HAIR"] - 0.5)
    assert max(np.abs(swings[:30])) > 0.1  # the hair swings behind the turn
    assert abs(swings[-1]) < 0.005 and not session.busy()  # and settles; nothing moves, the page rests
    changed, _ = apply(session, {"op": "faceedit", "action": "set_driver", "name": "hair", "param": "HAIR",
                                 "inputs": "HH:2 MB':0.05", "frequency": 3, "damping": 0.1, "swing": 1}, 0.0)
    (driver,) = session.face.physics
    assert changed == "face" and driver.frequency == 3 and driver.inputs[1].of == "velocity"
    with pytest.raises(Exception, match="expected one of"):
        apply(session, {"op": "faceedit", "action": "set_driver", "name": "x", "param": "NOPE", "inputs": "HH:1",
                        "frequency": 1, "damping": 0.2}, 0.0)
    apply(session, {"op": "faceedit", "action": "delete_driver", "name": "hair"}, 0.0)
    assert session.face.physics == ()


def test_the_staves_get_the_curve_the_physics_draws_from_the_animation():
    session = StudioSession("classic", folder=temp_folder())
    apply(session, {"op": "knot", "action": "add", "code": "HH", "t": 1.0, "v": 0.5}, 0.0)
    apply(session, {"op": "knot", "action": "add", "code": "HH", "t": 1.2, "v": 0.9}, 0.0)  # a quick turn
    curves = session.driven()
    (times, hair) = np.array(curves["HAIR"]).T
    assert times[1] - times[0] == pytest.approx(1 / 30, abs=1e-4) and times[-1] == pytest.approx(5.0 - 1 / 30, abs=1e-3)
    assert np.abs(hair[times < 1.0] - 0.5).max() < 1e-6  # still before the turn
    assert np.abs(hair[(times > 1.2) & (times < 2.2)] - 0.5).max() > 0.1  # it swings after it
    assert StudioSession("classic", folder=temp_folder()).driven()["HAIR"][0] == [0.0, 0.5]
