"""The mapping tuner in headless Chromium: a take plays on the face, a gain set in the panel
changes the motor's curve, a source's range line dragged on its measured values changes the
profile, and the files it saves map the take as `toonface map` does."""

import numpy as np
import pytest
from browser import studio_page, wait_for
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.support.ui import Select
from studios import temp_folder

from capture import save_take, synthesize
from toon import load_track, motor_index
from toonface.cli import main
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow


def test_a_tuned_mapping_saved_from_the_page_maps_as_the_command(tmp_path):
    take = save_take(synthesize(seconds=4.0, rate=60.0).take, tmp_path / "take.npz")
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, "window.tuner && window.studio.frames > 0", 1400, 1000) as driver:
        driver.find_element("id", "tab-tuner").click()  # the tuner alone beside the face
        driver.find_element("id", "tune-take").send_keys(str(take))
        driver.find_element("id", "tune-open").click()
        wait_for(driver, "window.tuner.state && window.studio.last.showing === 'tune'")
        Select(driver.find_element("id", "tune-motor")).select_by_value("MB")
        wait_for(driver, "window.tuner.state.motor === 'MB' && window.tuner.state.curve.code === 'MB'")
        before = driver.execute_script("return window.tuner.state.curve.values")
        gain = driver.find_element("id", "tune-gain")
        gain.clear()
        gain.send_keys("1.6")
        driver.find_element("id", "tune-apply").click()
        wait_for(driver, "window.tuner.state.rules.MB.gain === 1.6")
        after = driver.execute_script("return window.tuner.state.curve.values")
        rest = session.neutral[motor_index("MB")]
        assert np.abs(np.array(after) - rest).max() > np.abs(np.array(before) - rest).max()
        assert driver.execute_script("return document.querySelectorAll('#tune-curve polyline.source').length") == 2
        for box, text in (("tune-curve-points", "0,0 0.5,0.2 1,1"), ("tune-smoothing", "4")):
            driver.find_element("id", box).clear()
            driver.find_element("id", box).send_keys(text)
        driver.find_element("id", "tune-apply").click()
        wait_for(driver, "window.tuner.state.rules.MB.curve && window.tuner.state.rules.MB.filter")
        assert session.tuner.doc["motor"]["MB"]["curve"] == [[0, 0], [0.5, 0.2], [1, 1]]
        assert session.tuner.doc["motor"]["MB"]["filter"] == {"kind": "butterworth", "cutoff": 4}
        # MB's sources as measured, in mm, under the performer's range: dragging a source's high line
        # up by 12 pixels moves that end of its range by 12 pixels' worth of millimetres
        units = driver.execute_script("return window.tuner.state.curve.units")
        assert set(units.values()) == {"mm"}
        key = next(iter(units))
        high = session.tuner.ready.profile.sources[key].high
        line = driver.find_element("css selector", f'#tune-raw line.raw-range.high[data-key="{key}"]')
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", line)  # clear of the sticky tabs
        line = driver.find_element("css selector", f'#tune-raw line.raw-range.high[data-key="{key}"]')
        per_pixel = driver.execute_script(f"const r = window.tuner.rows['{key}']; return r.span / r.height")
        ActionChains(driver).click_and_hold(line).move_by_offset(0, -6).move_by_offset(0, -6).release().perform()
        wait_for(driver, f"window.tuner.state.ranges['{key}'][2] !== {high}")
        moved = session.tuner.ready.profile.sources[key].high
        assert moved == pytest.approx(high + 12 * per_pixel, abs=1.5 * per_pixel)
        mapping, profile = tmp_path / "mine.toml", tmp_path / "me.toml"
        for box, button, path in (("tune-mapping-path", "tune-save-mapping", mapping),
                                  ("tune-profile-path", "tune-save-profile", profile)):
            driver.find_element("id", box).send_keys(str(path))
            driver.find_element("id", button).click()
            wait_for(driver, f"document.getElementById('message').textContent === 'wrote {path}'")
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []
    out = tmp_path / "motors.csv"
    assert main(["map", str(take), "-o", str(out), "--mapping", str(mapping), "--profile", str(profile)]) == 0
    np.testing.assert_allclose(load_track(out).values, session.tuner.track.values, atol=1e-6)


def test_a_rule_typed_and_not_applied_survives_the_panel_being_redrawn(tmp_path):
    # every tuner message redraws the rule's fields; one answering an earlier action (a range
    # dragged) while the user typed a gain put the old gain back, and Apply then sent nothing
    take = save_take(synthesize(seconds=2.0, rate=60.0).take, tmp_path / "take.npz")
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, "window.tuner && window.studio.frames > 0", 1400, 1000) as driver:
        driver.find_element("id", "tab-tuner").click()
        driver.find_element("id", "tune-take").send_keys(str(take))
        driver.find_element("id", "tune-open").click()
        wait_for(driver, "window.tuner.state && window.studio.last.showing === 'tune'")
        Select(driver.find_element("id", "tune-motor")).select_by_value("MB")
        wait_for(driver, "window.tuner.state.motor === 'MB'")
        gain = driver.find_element("id", "tune-gain")
        gain.clear()
        gain.send_keys("1.6")
        driver.execute_script("window.tuner.state = null;"
                              "window.studio.send({op: 'tune', action: 'motor', code: 'MB'})")
        wait_for(driver, "window.tuner.state !== null")  # the panel redrawn from the server's answer
        assert gain.get_attribute("value") == "1.6"
        driver.find_element("id", "tune-apply").click()
        wait_for(driver, "window.tuner.state.rules.MB.gain === 1.6")
        Select(driver.find_element("id", "tune-motor")).select_by_value("BLL")  # another motor: its own gain
        wait_for(driver, "window.tuner.state.motor === 'BLL'")
        assert float(gain.get_attribute("value")) == session.tuner.doc["motor"]["BLL"].get("gain", 1)
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []
