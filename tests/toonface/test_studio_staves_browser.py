"""The staves an animator can read (issue 46): a value axis and a grid on every staff, the knot
picked shown with its time and value and moved by typing them, and a take opened as fewer knots
the looser the "within" the user sets (Simplify opens it again)."""

import shutil
from pathlib import Path

import pytest
from browser import chromium, studio_server, wait_for
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.keys import Keys

from toonface.studio.guard import Folder
from toonface.studio.session import StudioSession

pytestmark = pytest.mark.slow
TAKE = Path(__file__).resolve().parents[3] / "shared" / "realdata" / "facial" / "animface" / "JawMoCap.csv"


def test_a_take_opens_simplified_and_a_picked_knot_is_typed_in(tmp_path):
    if not TAKE.is_file():
        pytest.skip(f"the shared take is absent ({TAKE})")
    shutil.copy(TAKE, tmp_path)
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    count = "Object.values(window.editor.state.knots).reduce((n, k) => n + k.length, 0)"
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state")
        driver.execute_script("editor.open('JawMoCap.csv')")
        tight = wait_for(driver, f"{count} > 0 && {count}", timeout=60)
        staff = driver.find_element("css selector", '#staves svg[data-code="MB"]')
        assert len(staff.find_elements("css selector", "line.grid")) >= 3 + 20  # 0, 0.5, 1 and 26 seconds
        axis = driver.find_element("css selector", '.staff[data-code="MB"] .axis').text.split()
        assert axis == ["1", "0"]
        tolerance = driver.find_element("id", "tolerance")
        tolerance.clear()
        tolerance.send_keys("0.05")
        driver.find_element("id", "simplify").click()
        loose = wait_for(driver, f"{count} < {tight} && {count}", timeout=60)
        seconds = session.editor.animation.duration
        per_motor = loose / 21
        assert per_motor < tight / 21 and per_motor < 2 * seconds  # a few dozen a motor, not hundreds
        knot = driver.find_element("css selector", '#staves svg[data-code="MB"] circle[data-index="1"]')
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", knot)
        ActionChains(driver).click(knot).perform()
        wait_for(driver, "!document.getElementById('knot-edit').hidden")
        assert driver.find_element("id", "knot-name").text == "MB knot 2"
        t, v = session.editor.animation.knots["MB"][1]
        assert float(driver.find_element("id", "knot-t").get_attribute("value")) == pytest.approx(t, abs=1e-3)
        value = driver.find_element("id", "knot-v")
        value.send_keys(Keys.CONTROL, "a")  # select what it shows, and type over it
        value.send_keys("0.75\n")
        wait_for(driver, "Math.abs(window.editor.state.knots.MB[1][1] - 0.75) < 1e-9")
        assert session.editor.animation.knots["MB"][1] == pytest.approx((t, 0.75))


def test_a_box_drawn_across_staves_selects_its_time_on_the_staves_it_crosses(tmp_path):
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    with studio_server(session) as url, chromium(1366, 900) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state && document.querySelectorAll('#staves svg').length > 20")
        first = driver.find_element("css selector", '#staves svg[data-code="BRL"]')
        third = driver.find_element("css selector", '#staves svg[data-code="BRM"]')
        zoom, width = driver.execute_script("return [window.editor.zoom, arguments[0].getBoundingClientRect().width]",
                                            first)
        start = -width / 2 + 1.0 * zoom  # 1 s into the first staff
        ActionChains(driver).move_to_element_with_offset(first, start, 0).key_down(Keys.SHIFT).click_and_hold() \
            .move_to_element_with_offset(third, start + 1.5 * zoom, 0).release().key_up(Keys.SHIFT).perform()
        wait_for(driver, "window.editor.selection !== null")
        selection = driver.execute_script("return window.editor.selection")
        chosen = driver.execute_script("return [...document.querySelectorAll('#staves input.choose:checked')]"
                                       ".map(b => b.dataset.code)")
    assert selection == pytest.approx([1.0, 2.5], abs=2 / zoom)
    assert chosen == ["BRL", "BRC", "BRM"]  # the three it crossed, in order


def _webm(source: Path, out: Path, seconds: float) -> Path:
    """The first ``seconds`` of ``source`` as VP8 in WebM, a video any browser plays."""
    import av

    with av.open(str(source)) as given, av.open(str(out), "w") as made:
        stream = made.add_stream("libvpx", rate=25)
        stream.width, stream.height, stream.pix_fmt = 360, 288, "yuv420p"
        for frame in given.decode(video=0):
            if frame.time is not None and frame.time >= seconds:
                break
            for packet in stream.encode(frame.reformat(360, 288, "yuv420p")):
                made.mux(packet)
        for packet in stream.encode(None):
            made.mux(packet)
    return out


def test_the_performers_video_plays_beside_the_face_in_step_with_the_cursor(tmp_path):
    clip = TAKE.parents[2] / "video" / "grid" / "bbaf2n.mpg"
    if not clip.is_file():
        pytest.skip(f"the shared GRID clip is absent ({clip})")
    _webm(clip, tmp_path / "me.webm", 2.0)
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state")
        assert driver.execute_script("return document.getElementById('performer-video').hidden")
        driver.execute_script("editor.open('me.webm')")
        wait_for(driver, "Object.keys(window.editor.state.knots).length > 0", timeout=90)  # its face tracked
        wait_for(driver, "!document.getElementById('performer-video').hidden && "
                         "document.getElementById('performer-video').readyState >= 1", timeout=30)
        duration = driver.execute_script("return document.getElementById('performer-video').duration")
        driver.execute_script("studio.send({op: 'cursor', t: 1.2})")
        wait_for(driver, "Math.abs(document.getElementById('performer-video').currentTime - 1.2) < 0.05")
        driver.execute_script("studio.send({op: 'new', seconds: 5})")  # not from a video: the view goes
        wait_for(driver, "document.getElementById('performer-video').hidden")
    assert duration == pytest.approx(2.0, abs=0.15)


def test_a_knot_ticked_to_ease_curves_its_segment_on_the_staff_and_on_the_face(tmp_path):
    """Knots stay linear by default; "ease to the next" on a picked knot eases its segment: the
    staff draws the curve, the face shows the eased value, untick and it is linear again."""
    from toon import animation as an

    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    session.editor.animation = an.Animation({"MB": ((0.0, 0.1), (1.0, 0.1), (3.0, 0.9), (4.0, 0.9))}, 4.0)
    line = "document.querySelector('#staves svg[data-code=\"MB\"] polyline.curve').points.numberOfItems"
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state && window.editor.state.knots.MB")
        straight = driver.execute_script(f"return {line}")
        knot = driver.find_element("css selector", '#staves svg[data-code="MB"] circle[data-index="1"]')
        driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", knot)
        ActionChains(driver).click(knot).perform()
        wait_for(driver, "!document.getElementById('knot-edit').hidden")
        assert not driver.find_element("id", "knot-ease").is_selected()  # linear by default
        driver.find_element("id", "knot-ease").click()
        wait_for(driver, "window.editor.state.knots.MB[1][2] === true")
        curved = driver.execute_script(f"return {line}")
        driver.execute_script("window.studio.send({op: 'cursor', t: 1.5})")
        wait_for(driver, "Math.abs(window.studio.last.values.MB - 0.225) < 1e-6")  # 0.1 + 0.8 * smoothstep(0.25)
        driver.find_element("id", "knot-ease").click()
        wait_for(driver, "window.editor.state.knots.MB[1].length === 2")
        wait_for(driver, "Math.abs(window.studio.last.values.MB - 0.3) < 1e-6")  # linear again
        last = driver.find_element("css selector", '#staves svg[data-code="MB"] circle[data-index="3"]')
        ActionChains(driver).click(last).perform()
        wait_for(driver, "document.getElementById('knot-name').textContent === 'MB knot 4'")
        assert not driver.find_element("id", "knot-ease").is_enabled()  # the last knot starts no segment
    assert curved == straight + 15  # the eased segment drawn through 15 points between its knots
    assert session.editor.animation.knots["MB"][1] == (1.0, 0.1)
