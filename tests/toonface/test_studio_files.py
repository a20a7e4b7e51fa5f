"""Files through the browser (issue 46): a file the page sends is kept in the studio's working
folder under a safe, free name, written whole or not at all; a request from another site's page,
a name without an extension or of a kind the studio does not open, and a file over the limit are
refused. Dropped on the page in Chromium, a take opens as knots and plays on the face."""

import asyncio
from pathlib import Path

import aiohttp
import pytest
from browser import drop_file, studio_server

from toonface.studio import files
from toonface.studio.guard import Folder
from toonface.studio.session import StudioSession

REALDATA = Path(__file__).resolve().parents[3] / "shared" / "realdata"


def test_a_name_is_made_safe_and_a_taken_one_gets_the_next_free_number(tmp_path):
    assert files.safe_name("../../etc/take one.csv") == "take one.csv"
    assert files.safe_name("C:\\Users\\me\\face$.json") == "face_.json"
    assert files.safe_name(".hidden.toml") == "hidden.toml"
    for bad in ("..", "noextension", "/", ""):
        with pytest.raises(ValueError):
            files.safe_name(bad)
    (tmp_path / "take.csv").write_text("x")
    (tmp_path / "take-2.csv").write_text("x")
    assert files.free_name(tmp_path, "take.csv") == tmp_path / "take-3.csv"
    assert files.free_name(tmp_path, "new.csv") == tmp_path / "new.csv"


def _post(url: str, name: str, body: bytes, origin: str | None) -> tuple[int, str]:
    async def go() -> tuple[int, str]:
        headers = {"Origin": origin} if origin else {}
        async with aiohttp.ClientSession() as session, session.post(f"{url}files/{name}", data=body,
                                                                    headers=headers) as response:
            return response.status, await response.text()

    return asyncio.run(go())


def test_a_file_from_the_page_is_kept_in_the_folder_and_nothing_else_is_written(tmp_path, monkeypatch):
    (tmp_path / "take.csv").write_text("the user's own")
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    with studio_server(session) as url:
        origin = url.rstrip("/").split("?")[0]
        status, text = _post(url, "take.csv", b"frame,t\n", origin)
        assert status == 200 and '"name": "take-2.csv"' in text and '"kind": "editor"' in text
        assert (tmp_path / "take-2.csv").read_bytes() == b"frame,t\n"
        assert (tmp_path / "take.csv").read_text() == "the user's own"  # never written over
        assert _post(url, "voice.wav", b"RIFF", origin)[1].count('"kind": "sound"') == 1
        assert _post(url, "take.csv", b"x", None)[0] == 403  # not from the page (no Origin)
        assert _post(url, "take.csv", b"x", "http://evil.example")[0] == 403
        assert _post(url, "notes.exe", b"x", origin)[0] == 400
        monkeypatch.setattr(files, "MAX_UPLOAD", 1000)
        assert _post(url, "big.csv", b"x" * 5000, origin)[0] == 413
    assert sorted(p.name for p in tmp_path.iterdir()) == ["take-2.csv", "take.csv", "voice.wav"]  # no partial left


def _working(tmp_path: Path) -> tuple[Path, StudioSession]:
    """A studio on the classic face whose folder is ``tmp_path/work`` (apart from the files a
    test drops on its page)."""
    work = tmp_path / "work"
    work.mkdir()
    return work, StudioSession("classic", folder=Folder(work.resolve()))


@pytest.mark.slow  # Chromium: make test runs it
def test_a_take_dropped_on_the_page_opens_as_knots_and_plays_on_the_face_in_two_page_actions(tmp_path):
    """The first of the issue's first-time tasks, as a person does it: drag a take onto the page
    (1), press Space (2). The studio page (docs/howto/studio.md) states the count."""
    from browser import chromium, wait_for

    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared take is absent ({take})")
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state && window.files")
        mouth = driver.execute_script("return window.studio.last.values.MB")
        # 1: the drop
        drop_file(driver, take)
        wait_for(driver, "Object.keys(window.editor.state.knots).length > 0", timeout=60)
        said = driver.find_element("id", "message").text
        # 2: Space plays it
        driver.find_element("tag name", "body").send_keys(" ")
        wait_for(driver, "window.editor.state.playing && window.editor.state.cursor > 0.5")
        wait_for(driver, f"Math.abs(window.studio.last.values.MB - {mouth}) > 0.02")  # the jaw moves the mouth
        recent = driver.execute_script("return [...document.getElementById('recent').options].map(o => o.text)")
    assert (tmp_path / "JawMoCap.csv").read_bytes() == take.read_bytes()
    assert "JawMoCap.csv" in said and "knots" in said
    assert recent == ["…", "JawMoCap.csv"]  # listed to open again


def test_the_animation_and_the_face_download_as_the_files_save_writes(tmp_path):
    import json

    from toon import animation as an
    from toon import animation_file as af

    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    session.editor.animation = an.insert_knot(session.editor.animation, "MB", 1.0, 0.8)

    async def get(url: str) -> tuple[int, str, str]:
        async with aiohttp.ClientSession() as client, client.get(url) as response:
            return response.status, response.headers.get("Content-Disposition", ""), await response.text()

    with studio_server(session) as url:
        status, disposition, text = asyncio.run(get(f"{url}download/animation.toml"))
        assert status == 200 and 'filename="animation.toml"' in disposition
        (tmp_path / "got.toml").write_text(text)
        assert af.load_animation(tmp_path / "got.toml") == session.editor.animation
        status, disposition, text = asyncio.run(get(f"{url}download/face.json"))
        assert status == 200 and json.loads(text) == session.face.to_dict() and ".json" in disposition
        assert asyncio.run(get(f"{url}download/rooms.toml"))[0] == 404


@pytest.mark.slow  # maps the shared 26 s take five times
def test_a_take_that_does_not_say_its_rate_or_units_is_asked_about(tmp_path):
    """A table without a time column opens nothing and asks for its rate; one in centimetres
    that does not say so opens in the units its size suggests and says which, to be changed;
    units the face's size refutes are refused naming the likely ones (issue 46)."""
    import numpy as np

    from common import InputError
    from toonface.studio.messages import apply

    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared take is absent ({take})")
    lines = take.read_text().splitlines()
    header = lines[0].split(",")
    drop = header.index("time_s")
    (tmp_path / "frames.csv").write_text("\n".join(",".join(c for i, c in enumerate(line.split(",")) if i != drop)
                                                   for line in lines) + "\n")
    (tmp_path / "jaw.csv").write_text(take.read_text())
    session = StudioSession("classic", folder=Folder(tmp_path.resolve()))
    before = session.editor.animation
    _, said = apply(session, {"op": "open", "path": "frames.csv"}, 0.0)
    asked = session.editor.describe()["take"]
    assert said == "frames.csv does not say its frame rate: give it, then Open again"
    assert asked["ask"] == ["rate"] and asked["path"] == "frames.csv" and "(--rate)" in asked["said"]
    assert session.editor.animation is before  # nothing opened
    _, said = apply(session, {"op": "open", "path": "frames.csv", "rate": 60}, 0.0)
    asked = session.editor.describe()["take"]
    assert asked["rate"] == 60 and asked["units"] == "cm" and asked["ask"] == ["units", "rate"]
    assert session.editor.animation.duration == pytest.approx(1590 / 60)
    _, said = apply(session, {"op": "open", "path": "jaw.csv"}, 0.0)
    asked = session.editor.describe()["take"]
    assert asked["units"] == "cm" and asked["ask"] == ["units"] and "inferred" in asked["said"]
    assert "read in cm (the file does not say: inferred from the face's size)" in said
    inferred = session.editor.animation
    with pytest.raises(InputError, match="give --units cm"):
        apply(session, {"op": "open", "path": "jaw.csv", "units": "m"}, 0.0)
    _, said = apply(session, {"op": "open", "path": "jaw.csv", "units": "cm"}, 0.0)
    assert session.editor.describe()["take"]["said"] == "as given"
    given = session.editor.animation  # the same take, the same units: the same knots
    assert given.knots.keys() == inferred.knots.keys()
    assert all(np.allclose(given.knots[c], inferred.knots[c]) for c in given.knots)
    apply(session, {"op": "save", "path": "jaw.toml"}, 0.0)
    apply(session, {"op": "open", "path": "jaw.toml"}, 0.0)
    assert session.editor.describe()["take"] is None  # an animation says all: nothing to ask


@pytest.mark.slow
def test_the_page_asks_for_the_rate_a_dropped_table_does_not_say_and_opens_it_given(tmp_path):
    """Dropped on the page, a table without a time column asks for its rate beside the staves;
    typed in and opened again, it opens as knots, and the page says the units it was read in."""
    from browser import chromium, wait_for

    take = REALDATA / "facial" / "animface" / "JawMoCap.csv"
    if not take.is_file():
        pytest.skip(f"the shared take is absent ({take})")
    lines = take.read_text().splitlines()
    drop = lines[0].split(",").index("time_s")
    frames = tmp_path / "source" / "frames.csv"
    frames.parent.mkdir()
    frames.write_text("\n".join(",".join(c for i, c in enumerate(line.split(",")) if i != drop) for line in lines))
    work, session = _working(tmp_path)
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state && window.files")
        assert not driver.find_element("id", "take-ask").is_displayed()
        drop_file(driver, frames)
        wait_for(driver, "!document.getElementById('take-ask').hidden", timeout=60)
        asked = driver.find_element("id", "take-said").text
        assert driver.find_element("id", "take-rate").is_displayed()
        assert driver.execute_script("return Object.keys(window.editor.state.knots).length") == 0
        driver.find_element("id", "take-rate").send_keys("60")
        driver.find_element("id", "take-reopen").click()
        wait_for(driver, "Object.keys(window.editor.state.knots).length > 0", timeout=60)
        said = driver.find_element("id", "take-said").text
        units = driver.execute_script("return document.getElementById('take-units').value")
        duration = driver.execute_script("return window.editor.state.duration")
    assert asked == "frames.csv does not say its frame rate:"
    assert said == "frames.csv read in cm at 60 Hz (the file does not say: inferred from the face's size):"
    assert units == "cm" and duration == pytest.approx(1590 / 60)


@pytest.mark.slow
def test_a_png_dropped_on_the_page_becomes_a_picture_in_the_face_that_moves_once_attached(tmp_path):
    """CharToon's scanned and hand-painted parts: a PNG dropped on the studio becomes an image
    component kept in the face file, drawn in the page's face; attached to the mouth, it moves
    as the mouth's corners do; saved, the face loads back with it."""
    import numpy as np
    from browser import chromium, wait_for
    from pictures import png_bytes

    from toon import load_face

    picture = np.zeros((40, 60, 4), np.uint8)
    picture[..., 0], picture[..., 3] = 200, 255
    source = tmp_path / "source"
    source.mkdir()
    (source / "moustache.png").write_bytes(png_bytes(picture))
    work, session = _working(tmp_path)
    with studio_server(session) as url, chromium(1366, 768) as driver:
        driver.get(url)
        wait_for(driver, "window.editor && window.editor.state && window.files && window.faces")
        drop_file(driver, source / "moustache.png")
        wait_for(driver, "window.studio.last.svg.includes('picture-0')", timeout=30)
        said = driver.find_element("id", "message").text
        spec = session.faces.doc["components"][-1]
        assert spec["kind"] == "image" and spec["src"].startswith("data:image/png;base64,")
        newest = len(session.faces.doc["components"]) - 1
        wait_for(driver, f"window.faces.selected === {newest}")  # chosen in the list, ready for Attach
        driver.execute_script(f"window.faces.edit({{action: 'attach', component: "
                              f"{len(session.faces.doc['components']) - 1}, feature: 'mouth'}})")
        wait_for(driver, "window.faces.doc.components.at(-1).points.every(p => p.slave)")
        placed = "window.studio.last.svg.split('\\n').find(l => l.includes('href=\"#picture-0\"'))"
        before = driver.execute_script(f"return {placed}")
        driver.execute_script("window.studio.send({op: 'motor', code: 'MRV', value: 1})")  # a corner up
        wait_for(driver, f"{placed} !== {before!r}")
        driver.execute_script("window.faces.edit({action: 'save', path: 'mine.json'})")
        wait_for(driver, "document.getElementById('message').textContent.startsWith('wrote')")
    assert "imported moustache.png as component" in said
    saved = load_face(work / "mine.json")
    assert np.array_equal(next(c for c in saved.components if c.kind == "image").picture.pixels, picture)
