"""CharToon's component tools in headless Chromium: a component made from nothing is shaped point
by point with the mouse, its points re-kinded, its outline smoothed and partly hidden, a parameter
animated, an invalid value refused with the validator's message; components grouped, saved to a library and
inserted into another face; the face renders offscreen as the page draws it."""

import json

import numpy as np
import pytest
from browser import design_off, page_against_offscreen, studio_page, wait_for
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.support.ui import Select
from studios import temp_folder

from toon import load_face
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow
READY = "window.faces && window.faces.doc && window.studio.frames > 0"
LAST = "window.faces.doc.components.at(-1)"


def _open(driver) -> None:
    driver.execute_script("document.getElementById('face-panel').open = true;"
                          "document.getElementById('slider-panel').open = false;"
                          "document.getElementById('design').click();"
                          "document.getElementById('target-component').click()")
    wait_for(driver, "!document.getElementById('component-tools').hidden")


def _edits(driver) -> int:
    return driver.execute_script("return window.faces.last.undo")


def _click(driver, element_id: str) -> None:
    """Click a panel button and wait until the face has taken the edit."""
    count = _edits(driver)
    driver.find_element("id", element_id).click()
    wait_for(driver, f"window.faces.last.undo > {count}")


def _diamond(driver, index: int):
    return driver.find_element("css selector", f'#shape rect.vertex[data-drag="cpoint"][data-index="{index}"]')


def _new_polygon(driver, session) -> int:
    """Open the component tools and make a new polygon component; its index."""
    _open(driver)
    Select(driver.find_element("id", "new-kind")).select_by_visible_text("polygon")
    _click(driver, "new-component")
    return len(session.faces.doc["components"]) - 1


def test_a_component_made_from_nothing_is_shaped_rekinded_smoothed_and_animated(tmp_path):
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, READY, 1400, 1100) as driver:
        index = _new_polygon(driver, session)
        square = np.array(session.faces.doc["components"][index]["points"], dtype=float)
        assert square.shape == (4, 2)
        # a double-click halfway along side 0 adds a point there; a right-click deletes it
        first, second = _diamond(driver, 0).rect, _diamond(driver, 1).rect
        hit = driver.find_element("css selector", "#shape .outline-hit")
        box = hit.rect
        middle = ((first["x"] + second["x"]) / 2 + first["width"] / 2, (first["y"] + second["y"]) / 2
                  + first["height"] / 2)
        offset = (middle[0] - box["x"] - box["width"] / 2, middle[1] - box["y"] - box["height"] / 2)
        ActionChains(driver).move_to_element_with_offset(hit, *offset).double_click().perform()
        wait_for(driver, f"{LAST}.points.length === 5")
        added = np.array(session.faces.doc["components"][index]["points"], dtype=float)
        np.testing.assert_allclose(added[[0, 2, 3, 4]], square)
        np.testing.assert_allclose(added[1], (square[0] + square[1]) / 2, atol=2.0)
        ActionChains(driver).context_click(_diamond(driver, 1)).perform()
        wait_for(driver, f"{LAST}.points.length === 4")
        # clicking a point chooses it for the point row: made a slave of the jaw where it is
        ActionChains(driver).click(_diamond(driver, 2)).perform()
        assert Select(driver.find_element("id", "cpoint")).first_selected_option.get_attribute("value") == "points:2"
        Select(driver.find_element("id", "point-kind")).select_by_visible_text("slave")
        Select(driver.find_element("id", "point-master")).select_by_value("MB")
        _click(driver, "set-point")
        assert session.faces.doc["components"][index]["points"][2] == {"slave": "MB", "at": square[2].tolist()}
        driver.find_element("id", "smooth").send_keys("all")
        driver.find_element("id", "hidden-segments").send_keys("1")
        _click(driver, "apply-outline")
        spec = session.faces.doc["components"][index]
        assert spec["smooth"] is True and spec["hidden"] == [1]
        Select(driver.find_element("id", "param")).select_by_visible_text("scale")
        Select(driver.find_element("id", "param-motor")).select_by_value("MB")
        driver.find_element("id", "param-values").send_keys("1 1 1.5 1.5")
        _click(driver, "set-param")
        scale = session.faces.doc["components"][index]["scale"]
        assert scale["at1"] == [1.5, 1.5]
        np.testing.assert_allclose(scale["origin"], square.mean(axis=0))
        # an invalid value is refused, said beside the component (which stays chosen), and nothing is lost
        before, count = session.faces.doc, _edits(driver)
        field = driver.find_element("id", "hidden-segments")
        field.clear()
        field.send_keys("9")
        driver.find_element("id", "apply-outline").click()
        wait_for(driver, "document.getElementById('face-error').textContent.includes("
                         f"'components[{index}].hidden')")
        assert session.faces.doc == before and _edits(driver) == count
        # a refused edit chooses the item the validator names, here from the polygons' list
        driver.find_element("id", "target-polygon").click()
        driver.execute_script("window.faces.edit({action: 'set_component', component: arguments[0], "
                              "fields: {hidden: [7]}})", index)
        wait_for(driver, f"document.getElementById('target-component').checked && window.faces.selected === {index}")
        path = tmp_path / "made.json"
        driver.find_element("id", "face-path").send_keys(str(path))
        driver.find_element("id", "face-save").click()
        wait_for(driver, f"document.getElementById('message').textContent.startsWith('wrote {path}')")
        assert load_face(path) == session.face
        # at the jaw's extreme the new shape is grown and its slave point dropped: the page draws what
        # the offscreen renderer draws
        driver.execute_script("document.getElementById('slider-panel').open = true")
        slider = driver.find_element("id", "motor-MB")
        driver.execute_script("arguments[0].value = 1; arguments[0].dispatchEvent(new Event('input'))", slider)
        wait_for(driver, "window.studio.last.values.MB === 1")
        design_off(driver)
        difference = page_against_offscreen(driver, session)
        assert difference.mean() < 1.5 and np.mean(difference.max(axis=2) > 64) < 0.01


def test_components_are_grouped_moved_as_one_saved_to_a_library_and_inserted_into_another_face(tmp_path):
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, READY, 1400, 1100) as driver:
        _open(driver)
        for kind in ("ellipse", "polyline"):
            Select(driver.find_element("id", "new-kind")).select_by_visible_text(kind)
            _click(driver, "new-component")
        n = len(session.faces.doc["components"])
        listed = Select(driver.find_element("id", "polygon"))
        listed.select_by_value(str(n - 2))  # a multiple list: the second click adds to the choice
        assert [o.get_attribute("value") for o in listed.all_selected_options] == [str(n - 2), str(n - 1)]
        _click(driver, "group")
        group = session.faces.doc["components"][n - 2]
        assert group["kind"] == "composite" and [c["kind"] for c in group["components"]] == ["ellipse", "polyline"]
        units = driver.execute_script("const m = document.getElementById('shape').getScreenCTM(); return 1 / m.a")
        handle = driver.find_element("css selector", "#shape rect.unit")
        ActionChains(driver).click_and_hold(handle).move_by_offset(10, 0).move_by_offset(10, 0).release().perform()
        wait_for(driver, f"window.faces.doc.components[{n - 2}].transform.translate[0] > {15 * units}")
        np.testing.assert_allclose(session.faces.doc["components"][n - 2]["transform"]["translate"],
                                   [20 * units, 0.0], atol=1.0)
        library = tmp_path / "parts.json"
        driver.find_element("id", "library").clear()
        driver.find_element("id", "library").send_keys(str(library))
        driver.find_element("id", "entry-name").send_keys("pair")
        driver.find_element("id", "save-entry").click()
        wait_for(driver, f"document.getElementById('message').textContent === 'wrote pair to {library}'")
        entry = json.loads(library.read_text())["composites"]["pair"]["components"]
        assert [c["kind"] for c in entry] == ["ellipse", "polyline"]
        shifted = np.array(entry[0]["points"], dtype=float) - np.array(group["components"][0]["points"], dtype=float)
        np.testing.assert_allclose(shifted, np.broadcast_to([20 * units, 0.0], shifted.shape), atol=1.0)

        Select(driver.find_element("id", "face")).select_by_value("wizard")  # another face
        wait_for(driver, "window.faces.doc.name === 'wizard'")
        assert driver.find_element("id", "component-tools").is_displayed()  # still editing components
        count = len(session.faces.doc.get("components", []))
        driver.find_element("id", "list-library").click()
        wait_for(driver, "document.getElementById('library-entry').options.length === 1")
        _click(driver, "insert-entry")
        inserted = session.faces.doc["components"][count]
        assert inserted == {"kind": "composite", "name": "pair", "use": "pair", "library": str(library)}
        assert [c.kind for c in session.face.components[count].children] == ["ellipse", "polyline"]
        assert driver.execute_script("return window.faces.selected") == count


def test_a_point_kind_picked_and_not_set_survives_a_document_coming_back():
    # every document redrew the point row from the face; one answering an earlier edit while the
    # user picked a kind put the old kind back, and Set then sent that
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, READY, 1400, 1100) as driver:
        index = _new_polygon(driver, session)
        corner = session.faces.doc["components"][index]["points"][2]
        ActionChains(driver).click(_diamond(driver, 2)).perform()
        Select(driver.find_element("id", "point-kind")).select_by_visible_text("slave")
        Select(driver.find_element("id", "point-master")).select_by_value("MB")
        driver.execute_script("window.faces.edit({action: 'rename', name: 'renamed'})")
        wait_for(driver, "window.faces.doc.name === 'renamed' && !window.faces.waiting")
        assert Select(driver.find_element("id", "point-kind")).first_selected_option.text == "slave"
        assert driver.find_element("id", "point-master").get_attribute("value") == "MB"
        _click(driver, "set-point")
        assert session.faces.doc["components"][index]["points"][2] == {"slave": "MB", "at": corner}
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []
