"""The face editor in headless Chromium: drags change the saved face as expected, a motor's range
changes the face at its extreme, an invalid edit is refused and loses nothing, and the edited face
renders offscreen as the page draws it."""


import numpy as np
import pytest
from browser import design_off, page_against_offscreen, studio_page, wait_for
from selenium.webdriver.common.action_chains import ActionChains
from studios import temp_folder

from toon import FaceRig, load_face, motor_index
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow
READY = "window.faces && window.faces.doc && window.studio.frames > 0"


@pytest.fixture
def page():
    session = StudioSession("classic", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        driver.execute_script("document.getElementById('face-panel').open = true;"
                              "document.getElementById('slider-panel').open = false;"
                              "document.getElementById('design').click()")
        wait_for(driver, "!document.getElementById('shape').classList.contains('off')")
        yield driver, session


def _units_per_pixel(driver) -> float:
    return driver.execute_script("const m = document.getElementById('shape').getScreenCTM(); return 1 / m.a")


def test_dragging_a_vertex_and_a_control_point_changes_the_saved_face(page, tmp_path):
    from selenium.webdriver.support.ui import Select

    driver, session = page
    nose = next(i for i, p in enumerate(session.face.polygons) if p.name == "nose")
    Select(driver.find_element("id", "polygon")).select_by_value(str(nose))
    before = np.array(session.face.polygons[nose].vertices)
    vertex = driver.find_element("css selector", '#shape rect.vertex[data-index="0"]')
    ActionChains(driver).click_and_hold(vertex).move_by_offset(10, 0).move_by_offset(10, -10).release().perform()
    scale = _units_per_pixel(driver)
    pixel = 1.5 * scale  # where in its 8-pixel square the pointer took the vertex
    wait_for(driver, f"Math.abs(window.faces.doc.polygons[{nose}].vertices[0][0] - {before[0, 0] + 20 * scale})"
                     f" < {pixel}")
    after = np.array(session.face.polygons[nose].vertices)
    np.testing.assert_allclose(after[0], before[0] + [20 * scale, 10 * scale], atol=pixel)  # y up in face units
    np.testing.assert_array_equal(after[1:], before[1:])
    path = tmp_path / "mine.json"
    driver.find_element("id", "face-path").send_keys(str(path))
    driver.find_element("id", "face-save").click()
    wait_for(driver, f"document.getElementById('message').textContent.startsWith('wrote {path}')")
    assert load_face(path) == session.face


def test_a_range_end_changes_the_face_at_that_motors_extreme(page):
    from player.backends import open_renderer

    driver, session = page
    lo, hi = session.face.ranges["MB"]
    end = driver.find_element("css selector", '#shape rect.range-end[data-code="MB"][data-end="max"]')
    ActionChains(driver).click_and_hold(end).move_by_offset(0, 8).move_by_offset(0, 8).release().perform()
    scale = _units_per_pixel(driver)
    wait_for(driver, f"window.faces.doc.motors.MB[1] < {hi - 10 * scale}")
    assert session.face.ranges["MB"][0] == lo and session.face.ranges["MB"][1] == pytest.approx(hi - 16 * scale, abs=1)
    wide = session.neutral.copy()
    wide[motor_index("MB")] = 1.0
    with open_renderer((256, 256)) as renderer:
        old = renderer.render(FaceRig(load_face("classic")).geometry(wide)).astype(int)
        new = renderer.render(FaceRig(session.face).geometry(wide)).astype(int)
        rest = renderer.render(FaceRig(session.face).geometry(session.face.neutral())).astype(int)
        classic = load_face("classic")
        rest_old = renderer.render(FaceRig(classic).geometry(classic.neutral())).astype(int)
    at_extreme = np.abs(new - old).max(axis=2) > 40
    at_rest = np.abs(rest - rest_old).max(axis=2) > 40  # each at its own rest (point-attached parts follow the value)
    assert at_extreme.sum() > 200 and at_rest.sum() < at_extreme.sum() / 4  # the mouth opens further


def test_an_invalid_edit_is_refused_and_nothing_is_lost(page):
    driver, session = page
    face, undo = session.face, driver.execute_script("return window.faces.last.undo")
    end = driver.find_element("css selector", '#shape rect.range-end[data-code="MLV"][data-end="max"]')
    ActionChains(driver).click_and_hold(end).move_by_offset(0, 150).release().perform()  # below its minimum
    wait_for(driver, "document.getElementById('face-error').textContent.includes('motors.MLV')")
    assert session.face == face and driver.execute_script("return window.faces.last.undo") == undo
    corner = driver.find_element("css selector", '#shape circle.rest-point[data-name="ML"]')
    ActionChains(driver).click_and_hold(corner).move_by_offset(3, 0).release().perform()  # a good edit still goes
    wait_for(driver, f"window.faces.last.undo === {undo + 1}")


def test_the_edited_face_renders_offscreen_as_the_page_draws_it(page):
    driver, session = page
    frames = driver.execute_script("return window.studio.frames")
    driver.find_element("id", "grow").click()  # the selected polygon, larger
    wait_for(driver, f"window.faces.last.undo === 1 && window.studio.frames > {frames}")
    design_off(driver)
    difference = page_against_offscreen(driver, session)
    assert difference.mean() < 1.5 and np.mean(difference.max(axis=2) > 64) < 0.01


def test_vertices_are_added_deleted_and_a_polygon_moved_whole_with_the_mouse(page):
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select

    driver, session = page
    nose = next(i for i, p in enumerate(session.face.polygons) if p.name == "nose")  # a long first side
    Select(driver.find_element("id", "polygon")).select_by_value(str(nose))
    before = np.array(session.face.polygons[nose].vertices)
    first = driver.find_element("css selector", '#shape rect.vertex[data-index="0"]')
    second = driver.find_element("css selector", '#shape rect.vertex[data-index="1"]')
    middle = ((first.location["x"] + second.location["x"]) / 2 + first.size["width"] / 2,
              (first.location["y"] + second.location["y"]) / 2 + first.size["height"] / 2)
    outline = driver.find_element("css selector", "#shape polygon.outline-hit")
    box = outline.rect
    ActionChains(driver).move_to_element_with_offset(outline, middle[0] - box["x"] - box["width"] / 2,
                                                     middle[1] - box["y"] - box["height"] / 2).double_click().perform()
    wait_for(driver, f"window.faces.doc.polygons[{nose}].vertices.length === {len(before) + 1}")
    added = np.array(session.face.polygons[nose].vertices)
    np.testing.assert_allclose(added[2:], before[1:])  # the new vertex went between the first two
    assert np.linalg.norm(added[1] - (before[0] + before[1]) / 2) < 0.25 * np.linalg.norm(before[1] - before[0]) + 1
    ActionChains(driver).context_click(driver.find_element("css selector", '#shape rect.vertex[data-index="1"]')) \
        .perform()
    wait_for(driver, f"window.faces.doc.polygons[{nose}].vertices.length === {len(before)}")
    np.testing.assert_allclose(np.array(session.face.polygons[nose].vertices), before)
    scale = _units_per_pixel(driver)
    ActionChains(driver).key_down(Keys.SHIFT).click_and_hold(
        driver.find_element("css selector", '#shape rect.vertex[data-index="0"]')).move_by_offset(15, 0) \
        .move_by_offset(15, 0).release().key_up(Keys.SHIFT).perform()
    wait_for(driver, f"Math.abs(window.faces.doc.polygons[{nose}].vertices[2][0] - {before[2, 0] + 30 * scale}) < 1")
    np.testing.assert_allclose(np.array(session.face.polygons[nose].vertices) - before,
                               np.broadcast_to([30 * scale, 0.0], before.shape), atol=1.0)  # every vertex, alike


def test_a_face_file_is_named_in_the_face_list(tmp_path):
    from selenium.webdriver.support.ui import Select

    from toon import save_face

    path = save_face(load_face("wizard"), tmp_path / "mine.json")
    session = StudioSession(str(path), folder=temp_folder())
    with studio_page(session) as driver:
        assert Select(driver.find_element("id", "face")).first_selected_option.text == str(path)


def test_a_component_is_dragged_restyled_and_moved_whole(tmp_path):
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select

    session = StudioSession("round", folder=temp_folder())  # components only
    with studio_page(session, READY, 1400, 1000) as driver:
        driver.execute_script("document.getElementById('face-panel').open = true;"
                              "document.getElementById('slider-panel').open = false;"
                              "document.getElementById('design').click();"
                              "document.getElementById('target-component').click()")
        assert not driver.find_element("id", "kind-label").is_displayed()  # a polygon's field, not a component's
        assert driver.find_element("id", "layer-label").is_displayed()
        hair = next(i for i, c in enumerate(session.faces.doc["components"]) if c.get("name") == "hair_back")
        Select(driver.find_element("id", "polygon")).select_by_value(str(hair))
        before = np.array(session.faces.doc["components"][hair]["points"], dtype=float)
        scale = _units_per_pixel(driver)
        point = driver.find_element("css selector", '#shape rect.vertex[data-drag="cpoint"][data-index="0"]')
        ActionChains(driver).click_and_hold(point).move_by_offset(-10, 0).move_by_offset(-10, 0).release().perform()
        wait_for(driver, f"window.faces.doc.components[{hair}].points[0][0] < {before[0, 0] - 10 * scale}")
        after = np.array(session.faces.doc["components"][hair]["points"], dtype=float)
        np.testing.assert_allclose(after[0], before[0] + [-20 * scale, 0.0], atol=1.0)
        layer = driver.find_element("id", "layer")
        layer.clear()
        layer.send_keys("-7")
        driver.find_element("id", "apply-style").click()
        wait_for(driver, f"window.faces.doc.components[{hair}].layer === -7")
        point = driver.find_element("css selector", '#shape rect.vertex[data-drag="cpoint"][data-index="0"]')  # redrawn
        ActionChains(driver).key_down(Keys.SHIFT).click_and_hold(point).move_by_offset(0, 15).move_by_offset(0, 15) \
            .release().key_up(Keys.SHIFT).perform()
        wait_for(driver, f"window.faces.doc.components[{hair}].points[2][1] < {after[2, 1] - 20 * scale}")
        moved = np.array(session.faces.doc["components"][hair]["points"], dtype=float)
        np.testing.assert_allclose(moved - after, np.broadcast_to([0.0, -30 * scale], after.shape), atol=1.0)
        assert session.face.components[hair].layer == -7


def _hair_chosen(driver, session) -> int:
    from selenium.webdriver.support.ui import Select

    driver.execute_script("document.getElementById('face-panel').open = true;"
                          "document.getElementById('slider-panel').open = false;"
                          "document.getElementById('design').click();"
                          "document.getElementById('target-component').click()")
    hair = next(i for i, c in enumerate(session.faces.doc["components"]) if c.get("name") == "hair_back")
    Select(driver.find_element("id", "polygon")).select_by_value(str(hair))
    return hair


def _typed_as_a_document_comes_back(driver, field: str, text: str):
    """Type ``text`` into the field ``field`` without applying it, then let another edit's
    document come back (it redraws the panel); the field keeps ``text``. Returns the field."""
    box = driver.find_element("id", field)
    box.clear()
    box.send_keys(text)
    driver.execute_script("window.faces.edit({action: 'rename', name: 'renamed'})")
    wait_for(driver, "window.faces.doc.name === 'renamed' && !window.faces.waiting")
    assert box.get_attribute("value") == text
    return box


def test_a_style_typed_and_not_applied_survives_a_document_coming_back():
    # the echo of an earlier edit (a drag's last move, on a loaded machine) came back while the user
    # typed a layer; the panel was redrawn from the document and Apply sent the old layer
    session = StudioSession("round", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        hair = _hair_chosen(driver, session)
        layer = _typed_as_a_document_comes_back(driver, "layer", "-7")
        driver.find_element("id", "apply-style").click()
        wait_for(driver, f"window.faces.doc.components[{hair}].layer === -7")
        assert session.face.components[hair].layer == -7
        driver.execute_script("window.faces.edit({action: 'undo'})")  # applied: the field follows the document again
        wait_for(driver, f"window.faces.doc.components[{hair}].layer !== -7 && !window.faces.waiting")
        assert layer.get_attribute("value") == str(session.faces.doc["components"][hair].get("layer", 1))
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []


def test_an_outline_typed_and_not_applied_survives_a_document_coming_back():
    session = StudioSession("round", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        hair = _hair_chosen(driver, session)
        driver.execute_script("for (const d of document.querySelectorAll('details')) d.open = true")
        _typed_as_a_document_comes_back(driver, "hidden-segments", "1, 2")
        driver.find_element("id", "apply-outline").click()
        wait_for(driver, f"(window.faces.doc.components[{hair}].hidden || []).length === 2")
        assert session.faces.doc["components"][hair]["hidden"] == [1, 2]
        assert [e for e in driver.get_log("browser") if e["level"] == "SEVERE"] == []


def test_edits_made_while_one_is_in_flight_all_land_in_order():
    # a second edit replaced a waiting one: a style applied mid-drag dropped the drag's last move,
    # and a whole component dragged fast lost every move but the newest
    session = StudioSession("round", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        hair = _hair_chosen(driver, session)
        before = np.array(session.faces.doc["components"][hair]["points"], dtype=float)
        driver.execute_script(f"""
            const move = (dx) => window.faces.edit({{action: 'move_component', component: {hair}, dx, dy: 1}});
            move(4); move(3); move(2);
            window.faces.edit({{action: 'set_component', component: {hair}, fields: {{layer: -3}}}});
            move(1);""")
        wait_for(driver, f"window.faces.doc.components[{hair}].layer === -3 && !window.faces.waiting")
        moved = np.array(session.faces.doc["components"][hair]["points"], dtype=float)
        np.testing.assert_allclose(moved - before, np.broadcast_to([10.0, 4.0], before.shape), atol=1e-6)
        assert session.face.components[hair].layer == -3


def test_the_heads_range_is_edited_in_degrees(page):
    driver, session = page
    box = driver.find_element("id", "angle-HH-max")
    box.clear()
    box.send_keys("45\n")
    wait_for(driver, "window.faces.doc.motors.HH[1] === 45")
    assert session.face.ranges["HH"][1] == 45.0
    box = driver.find_element("id", "angle-HH-min")
    box.clear()
    box.send_keys("10\n")  # a range that does not run from negative to positive degrees: refused
    wait_for(driver, "document.getElementById('face-error').textContent.includes('motors.HH')")
    assert session.face.ranges["HH"][0] < 0


def test_a_new_polygon_from_the_panel_is_chosen_for_editing(page):
    driver, session = page
    count = len(session.face.polygons)
    driver.find_element("id", "add-polygon").click()
    wait_for(driver, f"window.faces.doc.polygons.length === {count + 1}")
    assert driver.find_element("id", "polygon").get_attribute("value") == str(count)
    assert driver.execute_script("return document.querySelectorAll('#shape rect.vertex').length") == 4
    assert session.face.polygons[count].kind == "free"


def test_copy_and_paste_from_the_panel(page):
    from selenium.webdriver.support.ui import Select

    driver, session = page
    nose = next(i for i, p in enumerate(session.face.polygons) if p.name == "nose")
    Select(driver.find_element("id", "polygon")).select_by_value(str(nose))
    count = len(session.face.polygons)
    driver.find_element("id", "copy-item").click()
    wait_for(driver, f"document.getElementById('message').textContent === 'copied polygon {nose}'")
    driver.find_element("id", "paste-item").click()
    wait_for(driver, f"window.faces.doc.polygons.length === {count + 1}")
    assert session.face.polygons[-1].name == "nose 2" and session.face.polygons[-1].vertices == \
        session.face.polygons[nose].vertices
    assert driver.find_element("id", "polygon").get_attribute("value") == str(count)


def test_another_pages_edit_does_not_send_this_pages_next_edit_before_its_own_is_done():
    # every page gets the face any page's edit made; a page waiting for its own edit took another's
    # face for its answer and sent the next one early, one more in flight than its drag merges allow
    import asyncio

    import aiohttp

    session = StudioSession("round", folder=temp_folder())
    with studio_page(session, READY, 1400, 1000) as driver:
        driver.execute_script("window.faces.waiting = true;"  # as if an edit of this page's were on its way
                              "window.faces.queue.push({action: 'rename', name: 'queued'})")
        origin = driver.execute_script("return location.origin")

        async def other_page() -> None:
            async with aiohttp.ClientSession() as client, client.ws_connect(
                    f"ws{origin[4:]}/ws", headers={"Origin": origin}) as ws:
                await ws.send_json({"op": "faceedit", "action": "rename", "name": "elsewhere"})
                while (await ws.receive_json(timeout=10)).get("type") != "answered":
                    pass

        asyncio.run(other_page())
        wait_for(driver, "window.faces.doc.name === 'elsewhere'")
        assert driver.execute_script("return [window.faces.waiting, window.faces.queue.length]") == [True, 1]
        assert session.face.name == "elsewhere"
        # nor does a refusal of something else this page asked for (only a refused face edit is one)
        driver.execute_script("window.studio.send({op: 'motor', code: 'nonsense', value: 0.5})")
        wait_for(driver, "document.getElementById('message').classList.contains('bad')")
        assert driver.execute_script("return [window.faces.waiting, window.faces.queue.length]") == [True, 1]
