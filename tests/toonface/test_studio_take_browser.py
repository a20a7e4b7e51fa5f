"""The studio with a real take open, in headless Chromium (issue 69, item 4): Pause keeps the
cursor where it was, the staves that move are in sight, and each box says what it is for."""

import shutil

import pytest
from browser import studio_page, wait_for

from toonface.studio.session import StudioSession

pytestmark = [pytest.mark.slow, pytest.mark.realdata]
READY = "window.editor && window.editor.state && document.querySelectorAll('#staves svg').length > 21"


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    from tests.conftest import REALDATA

    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared recording is absent ({take})")
    folder = tmp_path_factory.mktemp("studio")
    shutil.copy(take, folder)
    session = StudioSession("classic", animation=str(folder / take.name), folder=folder)
    with studio_page(session, READY, 1400, 1000) as driver:
        yield driver, session


def _play_from_the_start(driver) -> None:
    driver.execute_script("window.studio.send({op: 'cursor', t: 0})")
    wait_for(driver, "window.editor.state.cursor === 0")
    driver.find_element("id", "play").click()


def test_pause_keeps_the_cursor_where_playback_was(page):
    """Every frame redrew every staff of the mapped take (hundreds of knots), and the page took a
    click seconds late: Pause at 3.2 s landed at 26.5 s, the end. On a loaded machine frames still
    reach the page late (CI: 0.9 s), so Pause says where the page showed the cursor."""
    driver, session = page
    _play_from_the_start(driver)
    wait_for(driver, "window.editor.state.cursor > 1.5", timeout=20)
    # read in the same turn of the page's loop as Pause is pressed: no frame comes between
    shown = driver.execute_script("const shown = window.editor.state.cursor;"
                                  "document.getElementById('pause').click(); return shown")
    wait_for(driver, "!window.editor.state.playing")
    assert not session.editor.playing
    assert session.editor.cursor == pytest.approx(shown, abs=1e-9), (shown, session.editor.cursor)
    assert driver.execute_script("return window.editor.state.cursor") == pytest.approx(session.editor.cursor)


def test_a_page_held_up_draws_the_newest_frame_not_every_frame_it_missed(page):
    """Frames that queued while the page was busy are not drawn one by one (each a redraw of the
    face), so the page shows the server's time again at its next paint."""
    driver, session = page
    _play_from_the_start(driver)
    wait_for(driver, "window.editor.state.cursor > 0.2", timeout=20)
    before = driver.execute_script("const s = window.studio; const t = performance.now();"
                                   "while (performance.now() - t < 1500) {}"  # busy: the frames queue
                                   "return [s.received, s.frames]")
    wait_for(driver, f"window.studio.received > {before[0] + 20}", timeout=20)
    driver.find_element("id", "pause").click()
    wait_for(driver, "!window.editor.state.playing")
    received, drawn = driver.execute_script("return [window.studio.received, window.studio.frames]")
    assert received - before[0] > 20 and drawn - before[1] < received - before[0] - 15, (before, received, drawn)


def test_the_groups_that_move_come_first_and_the_still_ones_last(page):
    """The take's groups in the order of how far their motors move: the jaw and the lids first,
    the pupils (this take has no pupil markers) last, said still; all open, to key as before."""
    driver, _ = page
    groups = driver.execute_script(
        "return [...document.querySelectorAll('#staves details.staves')].map(d => [d.querySelector('summary')"
        ".textContent, d.open])")
    titles = [title for title, _ in groups]
    assert titles[0] in ("Mouth", "Eyelids") and titles[-1] == "Gaze (still)", groups
    assert all(is_open for _, is_open in groups)
    top = driver.execute_script("return document.querySelector('#staves svg[data-code=\"MB\"]')"
                                ".getBoundingClientRect().top")
    assert top < 1000  # MB in sight in a 1000-pixel window (it was far below the fold)


def test_each_box_says_what_it_is_for(page):
    driver, _ = page
    label = driver.execute_script("return document.getElementById('export').closest('label').textContent.trim()")
    assert label.startswith("Write to")
    assert driver.execute_script("return document.getElementById('export').placeholder") == "out.csv or out.mp4"
