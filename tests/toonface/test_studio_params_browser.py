"""A face's parameters beyond the 21 in the studio, in headless Chromium (issue 42): the face
editor declares one and attaches a control point to it, and its slider and its staff (knots added
with the mouse) move the face as the offscreen renderer draws it."""

import numpy as np
import pytest
from browser import studio_page, wait_for
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.support.ui import Select
from studios import temp_folder

from toon import FaceRig
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow
READY = "window.faces && window.faces.doc && window.editor && window.editor.state && window.studio.frames > 0"


def _mouth_top(session, values, extra) -> float:
    points = FaceRig(session.face).control_points(values, extra)
    return float(points[list(session.face.points).index("MT"), 1])


def test_the_face_editor_declares_a_parameter_its_slider_and_staff_move_the_face():
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        driver.execute_script("document.getElementById('face-panel').open = true;")
        driver.find_element("id", "fparam-code").send_keys("SNARL")
        wait_for(driver, "document.querySelector('#fparam-point option[value=\"MT\"]') !== null")  # points listed
        Select(driver.find_element("id", "fparam-point")).select_by_value("MT")
        dy = driver.find_element("id", "fparam-dy")
        dy.clear()
        dy.send_keys("20")
        driver.find_element("id", "fparam-set").click()
        wait_for(driver, "document.getElementById('motor-SNARL') !== null"
                         " && document.querySelector('#staves svg[data-code=\"SNARL\"]') !== null")
        assert session.face.extra_neutral()["SNARL"] == 0.0
        (move,) = session.face.params[-1].points
        assert (move.point, move.at0, move.at1) == ("MT", (0.0, 0.0), (0.0, 20.0))
        assert "SNARL, rests at 0: MT (0, 0) to (0, 20)" in driver.find_element("id", "fparam-list").text

        # the slider: the face's mouth top rises 20 units at 1, as the renderer's own rig says
        rest = _mouth_top(session, session.values, {})
        driver.execute_script("const s = document.getElementById('motor-SNARL'); s.value = 1;"
                              "s.dispatchEvent(new Event('input'))")
        wait_for(driver, "window.studio.last && window.studio.last.values.SNARL === 1")
        assert session.extra_values()["SNARL"] == 1.0
        assert _mouth_top(session, session.values, session.extra_values()) == pytest.approx(rest + 20)
        assert "SNARL" in driver.execute_script("return Object.keys(window.studio.last.values).join(' ')")

        # the staff: a knot by the mouse, and the animation at the cursor shows it
        staff = driver.find_element("css selector", '#staves svg[data-code="SNARL"]')
        ActionChains(driver).move_to_element_with_offset(staff, 0, -10).double_click().perform()
        wait_for(driver, "(window.editor.state.knots.SNARL || []).length === 1")
        (t, v), = session.editor.animation.knots["SNARL"]
        assert 0.6 < v <= 1.0
        session.editor.set_cursor(t)
        session.show_animation()
        assert session.extra_values()["SNARL"] == pytest.approx(v)
        track = session.editor.animation.sample(10.0, session.neutral, session.editor.declared)
        assert track.extra_codes == ("SNARL",) and np.allclose(track.extra[:, 0], v)

        # a parameter no point or component uses any more goes, with its slider
        driver.find_element("id", "fparam-code").clear()
        driver.find_element("id", "fparam-code").send_keys("SNARL")
        driver.find_element("id", "fparam-delete").click()
        wait_for(driver, "document.getElementById('motor-SNARL') === null")
        assert "SNARL" not in session.face.extra_codes
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert errors == []


def test_the_face_editor_tunes_a_driver_and_the_hair_swings_and_settles_live():
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        driver.execute_script("document.getElementById('face-panel').open = true;")
        driver.find_element("css selector", '#driver-list .driver[data-name="hair"]').click()
        assert driver.find_element("id", "driver-inputs").get_attribute("value") == "HH:1.2 HT:-0.6"
        frequency = driver.find_element("id", "driver-frequency")
        frequency.clear()
        frequency.send_keys("2.5")
        driver.find_element("id", "driver-set").click()
        wait_for(driver, "window.faces.doc.physics[0].frequency === 2.5")
        assert session.face.physics[0].frequency == 2.5
        assert "hair: HAIR swings HH:1.2 HT:-0.6 at 2.5 Hz" in driver.find_element("id", "driver-list").text
        driver.execute_script("const s = document.getElementById('motor-HH'); s.value = 0.9;"
                              "s.dispatchEvent(new Event('input'))")  # a quick turn of the head
        wait_for(driver, "Math.abs(window.studio.last.values.HAIR - 0.5) > 0.05")  # the hair swings
        wait_for(driver, "Math.abs(window.studio.last.values.HAIR - 0.5) < 0.005", timeout=30)  # and settles
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert errors == []
