"""The issue's second first-time task, scripted in Chromium as a person clicks, in the number of page
actions the studio page (docs/howto/studio.md) states: add a blink and a raised brow to a motor
track and render it (6 actions: drop the track, choose blink, Insert, double-click high on a
brow's staff, type the video's name, Render MP4). The first task (drop a take and play it: 2) is
in test_studio_files.py."""

import numpy as np
import pytest
from browser import chromium, drop_file, studio_server, wait_for
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.support.ui import Select

from toon import MotorTrack, motor_index, save_track, standard_neutral
from toonface.studio.guard import Folder
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow


def _studio(tmp_path):
    """A studio on the classic face whose folder is ``tmp_path/studio`` (the files a task drops
    on its page come from elsewhere)."""
    folder = tmp_path / "studio"
    folder.mkdir()
    return StudioSession("classic", folder=Folder(folder.resolve()))


def test_a_blink_and_a_raised_brow_added_to_a_track_and_rendered_in_six_page_actions(tmp_path):
    import av

    rng = np.random.default_rng(3)
    frames = 60  # two seconds of a talking mouth at 30 frames/s
    values = np.tile(standard_neutral(), (frames, 1))
    values[:, motor_index("MB")] = 0.2 + 0.3 * np.abs(np.sin(np.arange(frames) / 4)) + rng.normal(0, 0.005, frames)
    track = tmp_path / "talk.csv"
    save_track(MotorTrack(np.clip(values, 0, 1), 30.0), track)
    session = _studio(tmp_path)
    actions = 0
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state && "
                         "document.getElementById('insert-name').options.length > 3")
        drop_file(driver, track)
        actions += 1
        wait_for(driver, "(window.editor.state.knots.MB || []).length > 2", timeout=30)
        Select(driver.find_element("id", "insert-name")).select_by_value("blink")
        driver.find_element("id", "insert").click()
        actions += 2
        wait_for(driver, "(window.editor.state.knots.ERU || []).length >= 3")
        brow = driver.find_element("css selector", '#staves svg[data-code="BLM"]')
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", brow)
        ActionChains(driver).move_to_element_with_offset(brow, 60, -15).double_click().perform()  # high, past 1 s
        actions += 1
        wait_for(driver, "(window.editor.state.knots.BLM || []).length === 1")
        name = driver.find_element("id", "export")
        name.send_keys("mine.mp4")
        driver.find_element("id", "render").click()
        actions += 2
        wait_for(driver, "document.getElementById('message').textContent.startsWith('wrote')", timeout=120)
    assert actions == 6  # docs/howto/studio.md: "add a blink and a raised brow to a track and render it: 6 ..."
    knots = session.editor.animation.knots
    assert min(v for _, v in knots["ERU"]) < 0.1  # the lid comes down: a blink
    assert knots["BLM"][0][1] > standard_neutral()[motor_index("BLM")] + 0.2  # the brow raised
    with av.open(str(tmp_path / "studio" / "mine.mp4")) as video:
        stream = video.streams.video[0]
        assert stream.frames >= 55 or float(stream.duration * stream.time_base) >= 1.9


DRAWING = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">
  <ellipse id="cheeks" cx="100" cy="120" rx="70" ry="30" fill="#f6b0a0" opacity="0.6"/>
  <path id="mouth" d="M70 150 Q100 175 130 150 Q100 162 70 150 Z" fill="#8a1c2c" stroke="#300" stroke-width="1.5"/>
</svg>"""


def test_an_svg_drawing_imported_and_its_mouth_attached_in_three_page_actions(tmp_path):
    """The third first-time task: drop the drawing (1), choose its mouth in the component list (2),
    Attach (to the mouth, the default) (3); then the drawn mouth opens with the face's."""
    from toon import FaceRig

    drawing = tmp_path / "mine.svg"
    drawing.write_text(DRAWING)
    session = _studio(tmp_path)
    actions = 0
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.faces && window.faces.doc && window.files")
        drop_file(driver, drawing)
        actions += 1
        wait_for(driver, "(window.faces.doc.components || []).some(c => c.name === 'mouth')", timeout=30)
        wait_for(driver, "document.getElementById('message').textContent.startsWith('imported')")
        said = driver.find_element("id", "message").text
        assert driver.execute_script("return document.getElementById('face-panel').open")  # the Face editor shows
        mouth = driver.execute_script("return window.faces.doc.components.findIndex(c => c.name === 'mouth')")
        driver.find_element("css selector", f'#polygon option[value="{mouth}"]').click()  # a click, not ctrl-click
        wait_for(driver, f"window.faces.selected === {mouth}")
        driver.find_element("id", "attach-component").click()
        actions += 2
        wait_for(driver, f"typeof window.faces.doc.components[{mouth}].points[0] === 'object' && "
                         f"!Array.isArray(window.faces.doc.components[{mouth}].points[0])")
    assert actions == 3  # docs/howto/studio.md: "import an SVG drawing and attach its mouth: 3 page actions"
    assert (tmp_path / "studio" / "mine.svg").is_file()
    face = session.faces.face
    spec = next(c for c in face.components if c.name == "mouth")
    assert {p.master for p in spec.points} >= {"ML", "MR"} and all(p.kind == "slave" for p in spec.points)
    rig, shut = FaceRig(face), face.neutral()
    wide = shut.copy()
    wide[motor_index("MB")] = 1.0
    drawn = [next(i.vertices for i in rig.geometry(v).items if i.name == "mouth") for v in (shut, wide)]
    assert drawn[1][:, 1].min() < drawn[0][:, 1].min() - 5  # its lower lip comes down as the mouth opens
    assert said.startswith("imported 2 components from mine.svg")  # the studio said what it made
