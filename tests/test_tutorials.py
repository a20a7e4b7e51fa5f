"""The tutorials' shell blocks, every one, run as written on the shared recordings they name
(issue 47): each test runs all of its page's ``sh`` blocks in order, so a block added to a page
and left out of its test fails here, and checks what the page says they make."""

from __future__ import annotations

import json
import re
import shutil
import tomllib
from pathlib import Path

import av
import numpy as np
import pytest

from player.alpha_sinks import decode_rgba
from tests.helpers.pubsub import free_port
from tests.helpers.shell import blocks, run, running, substitute
from toon import MOTOR_CODES, load_track

pytestmark = [pytest.mark.slow, pytest.mark.realdata]


def _shared(realdata: Path, folder: Path, *names: str) -> None:
    for name in names:
        path = realdata / name
        if not path.is_file():
            pytest.skip(f"the shared recording is absent ({path})")
        shutil.copy(path, folder)


def _frames(path: Path) -> int:
    with av.open(str(path)) as movie:
        return sum(1 for _ in movie.decode(video=0))


def test_the_animator_s_tutorial_runs_as_written(realdata, tmp_path):
    _shared(realdata, tmp_path, "facial/animface/JawMoCap.csv", "video/grid/bbaf2n.mpg")
    page = blocks("tutorials/animator.md")
    assert len(page) == 5
    for block in page:
        run(block, tmp_path)
    jaw = load_track(tmp_path / "jaw.csv")
    for lid in ("ERU", "ELU"):  # "blinks four times": the lids shut four times (issue 69: they were squints)
        shut = np.diff(np.r_[0, (jaw.column(lid) <= 0.15).astype(int), 0])
        assert (shut == 1).sum() == 4, lid
    for face in ("wizard", "round", "mine"):  # 26.5 s at 30 frames a second, on each face
        assert abs(_frames(tmp_path / f"jaw-{face}.mp4") - 26.5 * 30) <= 2
    assert _frames(tmp_path / "jaw-open.mp4") == 4 * 30  # --start 5 --end 9
    assert json.loads((tmp_path / "mine.json").read_text())["format"] == "toonface.face/1"
    with av.open(str(tmp_path / "line.mp4")) as movie:
        assert movie.streams.audio and movie.streams.video  # the voice under the picture
    alpha = np.stack(decode_rgba(tmp_path / "line.webm"))[..., 3]  # the face over nothing
    assert len(alpha) == 74 and alpha.min() == 0 and alpha.max() == 255
    lottie = json.loads((tmp_path / "line.json").read_text())
    assert lottie["layers"] and abs(lottie["op"] - lottie["ip"] - 74) <= 1 and lottie["fr"] == 25
    page_html = (tmp_path / "line.html").read_text()
    assert "<svg" in page_html and "data:audio/webm;base64," in page_html
    cues = (tmp_path / "line.tsv").read_text().split()
    assert "A" in cues[1::2] and cues[1::2][-1] == "X"  # lips shut for "bin blue", at rest at the end
    assert (tmp_path / "line.dat").read_text().startswith("MohoSwitch1")


def test_the_batch_tutorial_runs_as_written(realdata, tmp_path):
    (tmp_path / "takes").mkdir()
    _shared(realdata, tmp_path / "takes", "facial/animface/JawMoCap.csv", "facial/animface/EyebrowsMoCap.csv")
    job = blocks("tutorials/batch.md", "toml")[0]
    assert tomllib.loads(job)["format"] == "toonface.batch/1"
    (tmp_path / "jobs.toml").write_text(job)
    dry_run, first, again, cluster = blocks("tutorials/batch.md")
    said = blocks("tutorials/batch.md", "text")
    listed = run(dry_run, tmp_path)
    assert listed.stdout == said[0]  # exactly as the page shows it
    table = run(first, tmp_path).stdout.splitlines()
    assert table[:2] == said[1].splitlines()[:2]  # the plan and the table's head, as the page shows them
    assert table[2].split()[:3] == said[1].splitlines()[2].split()[:3] == ["done", "4", "2492"]
    for take in ("JawMoCap", "EyebrowsMoCap"):
        for face in ("classic", "cat"):
            for suffix in (".mp4", ".csv", ".score.png", ".sheet.png"):
                assert (tmp_path / "out" / take / f"{face}{suffix}").is_file()
    assert "0 to make, 4 up to date" in run(again, tmp_path).stdout
    port = str(free_port())
    done = run(substitute(cluster, {"8786": port}), tmp_path)
    assert re.search(r"done\s+4\s+2492", done.stdout), done.stdout


def test_the_telepresence_tutorial_runs_as_written(realdata, tmp_path):
    _shared(realdata, tmp_path, "facial/animface/JawMoCap.csv")
    room, watch, perform, _, many = blocks("tutorials/telepresence.md")
    banner = blocks("tutorials/telepresence.md", "text")[0]
    port = {"7730": str(free_port())}
    with running(substitute(room, port), tmp_path, "camera ") as server:
        tokens = tomllib.loads((tmp_path / "rooms.toml").read_text())["rooms"]["demo"]
        names = {**port, "PERFORM_TOKEN": tokens["perform"], "WATCH_TOKEN": tokens["watch"]}
        assert server.output().strip() == substitute(banner, names).strip()  # the banner as the page shows it
        with running(substitute(watch, names), tmp_path, "receiving on room") as viewer:
            run(substitute(perform, names), tmp_path)
            assert "wrote seen.csv" in viewer.finish(30)  # at its --seconds, with what it showed
    seen = load_track(tmp_path / "seen.csv")
    mb = seen.values[:, MOTOR_CODES.index("MB")]
    assert seen.frames > 300 and np.ptp(mb) > 0.3  # the jaw opened on the viewer's face
    ports = {"7730": str(free_port()), "4222": str(free_port())}
    with running(substitute(many, ports), tmp_path, "room demo: camera") as servers:
        from toonface.web_hosts import reachable_addresses

        here = (reachable_addresses() or ["127.0.0.1"])[0]  # every interface: the address others reach
        banner = servers.output()
        assert (f"room server on ws://{here}:{ports['7730']}, 2 processes, rooms shared through "
                f"nats://127.0.0.1:{ports['4222']}") in banner  # both processes, one NATS, its token unsaid
        assert "without credentials" not in banner  # (NATS asks for its token: no warning)


def test_the_telepresence_tutorials_phone_section_runs_to_the_camera(tmp_path):
    """Issue 70, item 5: a phone on the LAN could not perform (plain http has no camera). The
    section's command serves https with a certificate of its own whose printed fingerprint is the
    one served; its camera link, the warning accepted (``--ignore-certificate-errors``), is a
    secure page that asks for the camera and, allowed, performs."""
    import ssl

    from browser import chromium, wait_for

    from bench.room_performer import FAKE_CAMERA, page_missing

    if why := page_missing():
        pytest.skip(why)
    phone = blocks("tutorials/telepresence.md")[3]
    port = str(free_port())
    with running(substitute(phone, {"7731": port}), tmp_path, "room phone: camera") as server:
        out = server.output()
        printed = re.search(r"fingerprint reads ([0-9A-F:]+)", out)[1]
        link = re.search(r"room phone: camera\s+(\S+)", out)[1]
        host = re.match(r"https://([^:/]+):", link)[1]
        served = ssl.PEM_cert_to_DER_cert(ssl.get_server_certificate((host, int(port))))
        import hashlib

        assert ":".join(f"{b:02X}" for b in hashlib.sha256(served).digest()) == printed
        assert (tmp_path / "phone-cert.pem").is_file() and (tmp_path / "phone-key.pem").stat().st_mode & 0o077 == 0
        with chromium(700, 900, (*FAKE_CAMERA, "--ignore-certificate-errors")) as browser:
            browser.get(link)
            wait_for(browser, "window.performer.ready || window.performer.error", timeout=60)
            assert browser.execute_script("return window.isSecureContext")
            assert browser.execute_script("return window.performer.error") is None  # past the camera's prompt
            wait_for(browser, "window.performer.sent > 5", timeout=30)  # and performing over wss://
