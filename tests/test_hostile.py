"""Hostile files and messages (issue 67): each of the nine cases an outside tester found gives a
one-line error (exit 2) or a clean refusal within 5 s and under 500 MB, and a fuzz test of each
runs under a memory cap (:mod:`capped`), so a regression fails instead of swapping. The room
server's cases (6, 7, 8) are in ``tests/toonface/test_room_hostile.py``."""

from __future__ import annotations

import asyncio
import json
import os
import re
import signal
import struct
import subprocess
import time
from pathlib import Path

import aiohttp
import numpy as np
import pytest
from capped import capped_command, capped_memory, peak_mb, run_capped
from fuzzing import fuzz_settings
from hypothesis import given
from hypothesis import strategies as st
from scipy import sparse

from capture.cues import read_cues
from common import InputError
from common.limits import MAX_CUE_SECONDS, MAX_SVG_ELEMENTS, MAX_SVG_POINTS
from common.sound import decode_mono
from toon import MOTOR_CODES, MotorTrack, load_face, save_track
from toon.curves import REACH, SPLINE_STEPS, outline_operator
from toon.svg_import import svg_components

VIEWBOX = (-256.0, -256.0, 256.0, 256.0)


@pytest.fixture(scope="module")
def track(tmp_path_factory) -> Path:
    """A second of motors, to render and export."""
    folder = tmp_path_factory.mktemp("track")
    return save_track(MotorTrack(np.full((30, len(MOTOR_CODES)), 0.5), 30.0), folder / "m.csv")


def use_bomb(levels: int, fanout: int) -> str:
    """An SVG whose ``<use>`` elements repeat the level below ``fanout`` times, ``levels`` deep."""
    defs = ['<g id="l0"><path d="M0 0 L10 10 L0 10 Z" fill="red"/></g>']
    defs += [f'<g id="l{i}">' + f'<use href="#l{i - 1}"/>' * fanout + "</g>" for i in range(1, levels + 1)]
    return (f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><defs>{"".join(defs)}</defs>'
            f'<use href="#l{levels}"/></svg>')


def long_path(points: int) -> str:
    rng = np.random.default_rng(0)
    xy = rng.uniform(0, 100, (points, 2))
    d = "M0 0 " + " ".join(f"L{x:.2f} {y:.2f}" for x, y in xy) + " Z"
    return f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><path d="{d}" fill="red"/></svg>'


# 1 and 4: drawings -------------------------------------------------------------------------------

def test_a_drawing_of_nested_uses_is_refused_before_it_is_expanded():
    started = time.perf_counter()
    with capped_memory(), pytest.raises(ValueError, match=f"more than {MAX_SVG_ELEMENTS} elements"):
        svg_components(use_bomb(7, 10), VIEWBOX)  # 1.9 kB, ten million shapes
    with pytest.raises(ValueError, match="refers to itself"):
        svg_components('<svg><g id="a"><use href="#b"/></g><g id="b"><use href="#a"/></g></svg>', VIEWBOX)
    assert time.perf_counter() - started < 1.0
    assert len(svg_components(use_bomb(2, 3), VIEWBOX)) == 9  # a drawing that repeats a little is imported


def expanded_elements(levels: int, fanout: int) -> int:
    """The elements of :func:`use_bomb` with every ``<use>`` expanded, counted by hand: a level is
    its group and ``fanout`` uses, each holding the level below."""
    level = 2  # l0: its group and path
    defs = level
    for _ in range(levels):
        level = 1 + fanout * (1 + level)
        defs += level
    return 2 + defs + 1 + level  # svg, defs, its levels, and the use of the top one


@given(levels=st.integers(1, 12), fanout=st.integers(1, 12))
@fuzz_settings(60)
def test_fuzz_nested_uses_are_measured_exactly_and_refused_past_the_bound(levels, fanout):
    from toon.svg_size import check_svg_size

    with capped_memory():
        try:
            size = check_svg_size(use_bomb(levels, fanout))
        except ValueError:
            assert expanded_elements(levels, fanout) > MAX_SVG_ELEMENTS
        else:
            assert size.elements == expanded_elements(levels, fanout) <= MAX_SVG_ELEMENTS
            if fanout ** levels <= 64:  # imported whole (the drawing library is slow beyond)
                assert len(svg_components(use_bomb(levels, fanout), VIEWBOX)) == fanout ** levels


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_path_of_200_000_points_is_refused_and_curves_cost_memory_linear_in_their_points():
    started = time.perf_counter()
    with capped_memory(), pytest.raises(ValueError, match=f"more than {MAX_SVG_POINTS} points"):
        svg_components(long_path(200_000), VIEWBOX)
    assert time.perf_counter() - started < 5.0
    ring = np.column_stack([np.cos(np.linspace(0, 6.28, 200_001)), np.sin(np.linspace(0, 6.28, 200_001))])
    with capped_memory(1 << 30):
        straight, _ = outline_operator(ring, True, ())  # was a dense 200 001 x 200 001 identity (298 GiB)
        smooth, origin = outline_operator(ring[:20_000], True, ((0, 19_999),))
    assert sparse.issparse(straight) and straight.nnz == len(ring)
    assert smooth.shape == (20_000 * SPLINE_STEPS, 20_000) and len(origin) == 20_000 * SPLINE_STEPS
    assert smooth.nnz <= smooth.shape[0] * (2 * REACH + 2)


@pytest.mark.parametrize("closed", [True, False])
def test_a_long_smoothed_stretch_solved_in_windows_is_the_whole_solve(closed, monkeypatch):
    import toon.curves as curves

    points = np.cumsum(np.random.default_rng(1).normal(size=(300, 2)), axis=0)
    windowed, origin = outline_operator(points, closed, ((0, 299),))
    monkeypatch.setattr(curves, "WHOLE_POINTS", 10_000)
    whole, whole_origin = outline_operator(points, closed, ((0, 299),))
    assert np.array_equal(origin, whole_origin)
    assert np.abs((windowed - whole) @ points).max() < 1e-7 * np.ptp(points)
    assert windowed.nnz < whole.nnz / 5


# 2: pictures -------------------------------------------------------------------------------------

@pytest.mark.slow  # the command in a capped process (1 s each)
@pytest.mark.parametrize("kind", ["device", "fifo"])
def test_a_face_picture_that_never_ends_is_refused(tmp_path, track, kind):
    picture = tmp_path / "scan.png"
    if kind == "device":
        picture.symlink_to("/dev/zero")
    else:
        os.mkfifo(picture)
    doc = load_face("classic").to_dict()
    doc["components"] = [*doc.get("components", []), {"kind": "image", "name": "scan", "src": "scan.png",
                                                      "layer": 2, "points": [[-200, 200], [-100, 200], [-200, 100]]}]
    (tmp_path / "face.json").write_text(json.dumps(doc))
    run = run_capped(["render", str(track), "-o", "out.mp4", "--face", "face.json"], tmp_path)
    assert run.refused_in_one_line() and run.within_bounds(), run
    assert re.search(r"scan.png: a (character device|named pipe \(FIFO\)), not a file", run.stderr)
    assert not (tmp_path / "out.mp4").exists()


# 3: mouth cues -----------------------------------------------------------------------------------

CUES = {".tsv": "0.00\tA\n{end}\tX\n",
        ".json": '{{"mouthCues": [{{"start": 0, "end": 1, "value": "A"}}, '
                 '{{"start": 1, "end": {end}, "value": "X"}}]}}',
        ".xml": '<rhubarbResult><mouthCues><mouthCue start="0" end="1">A</mouthCue>'
                '<mouthCue start="1" end="{end}">X</mouthCue></mouthCues></rhubarbResult>'}


@pytest.mark.parametrize("suffix", sorted(CUES))
@pytest.mark.parametrize("end", ["1e10", "1e308", "300000"])
def test_mouth_cues_ending_after_a_day_are_refused(tmp_path, suffix, end):
    (tmp_path / f"cues{suffix}").write_text(CUES[suffix].format(end=end))
    with capped_memory(), pytest.raises(InputError, match="cues end within a day"):
        read_cues(tmp_path / f"cues{suffix}")


@pytest.mark.slow  # the command in a capped process (1 s each)
@pytest.mark.parametrize(("suffix", "end"), [(".tsv", "1e10"), (".json", "1e308"), (".xml", "300000")])
def test_map_refuses_cues_ending_after_a_day_in_one_line(tmp_path, suffix, end):
    (tmp_path / f"cues{suffix}").write_text(CUES[suffix].format(end=end))
    run = run_capped(["map", f"cues{suffix}", "-o", "m.csv"], tmp_path)
    assert run.refused_in_one_line() and run.within_bounds(), run
    assert "cues end within a day" in run.stderr


def test_cues_may_not_end_after_the_sound_they_came_with(tmp_path):
    path = tmp_path / "cues.json"
    path.write_text('{"metadata": {"duration": 2.0}, "mouthCues": [{"start": 0, "end": 3, "value": "A"}]}')
    with pytest.raises(InputError, match="after the sound's 2 s"):
        read_cues(path)
    path.write_text('{"metadata": {"duration": 3.01}, "mouthCues": [{"start": 0, "end": 3, "value": "A"}]}')
    assert read_cues(path) == [(0.0, 3.0, "A")]


@given(end=st.floats(0, 1e308, allow_nan=False), suffix=st.sampled_from(sorted(CUES)))
@fuzz_settings(60)
def test_fuzz_cue_ends_read_or_refused(tmp_path_factory, end, suffix):
    path = tmp_path_factory.mktemp("cues") / f"c{suffix}"
    path.write_text(CUES[suffix].format(end=repr(end)))
    with capped_memory():
        try:
            cues = read_cues(path)
        except InputError:
            assert end > MAX_CUE_SECONDS or end < 1
        else:
            assert cues[-1][1] <= MAX_CUE_SECONDS


# 5: sound ----------------------------------------------------------------------------------------

def write_wav(path: Path, rate: int, samples: np.ndarray, fmt: int = 1) -> Path:
    """A WAV of ``samples`` (int16 for format 1, float32 for format 3) whose header says ``rate``."""
    data = samples.astype(np.int16 if fmt == 1 else np.float32).tobytes()
    width = 2 if fmt == 1 else 4
    header = b"RIFF" + struct.pack("<I", 36 + len(data)) + b"WAVEfmt " + struct.pack(
        "<IHHIIHH", 16, fmt, 1, rate, rate * width, width, width * 8) + b"data" + struct.pack("<I", len(data))
    path.write_bytes(header + data)
    return path


@pytest.mark.slow  # the command in a capped process (1 s each)
@pytest.mark.parametrize("command", ["export", "lipsync"])
def test_a_sound_whose_header_says_1_hz_is_refused(tmp_path, track, command):
    write_wav(tmp_path / "slow.wav", 1, np.zeros(16_000))
    args = (["export", "web", str(track), "-o", "p.html", "--sound", "slow.wav"] if command == "export"
            else ["lipsync", "slow.wav", "-o", "c.tsv"])
    run = run_capped(args, tmp_path)
    assert run.refused_in_one_line() and run.within_bounds(), run
    assert "a sound at 1 Hz: the rates read are 4000 to 192000 Hz" in run.stderr


def test_a_sound_of_nan_and_infinity_is_refused(tmp_path):
    write_wav(tmp_path / "nan.wav", 16_000, np.array([np.nan, np.inf, -np.inf, 0.5] * 4000), fmt=3)
    with pytest.raises(InputError, match="not numbers"):
        decode_mono(tmp_path / "nan.wav")


@pytest.mark.slow  # the command in a capped process (1 s)
def test_lipsync_refuses_a_sound_of_nan_and_infinity_in_one_line(tmp_path):
    write_wav(tmp_path / "nan.wav", 16_000, np.array([np.nan, np.inf, -np.inf, 0.5] * 4000), fmt=3)
    run = run_capped(["lipsync", "nan.wav", "-o", "c.tsv"], tmp_path)
    assert run.refused_in_one_line() and run.within_bounds(), run
    assert "not numbers (NaN or infinity)" in run.stderr and not (tmp_path / "c.tsv").exists()


@given(rate=st.one_of(st.integers(1, 3999), st.integers(192_001, 2**31 - 1), st.integers(4000, 192_000)))
@fuzz_settings(30)
def test_fuzz_sound_rates_read_or_refused(tmp_path_factory, rate):
    path = write_wav(tmp_path_factory.mktemp("wav") / "s.wav", rate, np.zeros(4000))
    with capped_memory():
        try:
            samples, got, _ = decode_mono(path)
        except InputError as exc:
            assert not 4000 <= rate <= 192_000, exc
        else:
            assert 4000 <= rate <= 192_000 and got == rate and len(samples) == 4000


# 9 (and 1's SIGTERM): names, and a busy studio --------------------------------------------------

@pytest.mark.slow  # the command in a capped process (2 s)
def test_a_folder_named_like_a_builtin_face_or_marker_set_does_not_shadow_it(tmp_path, track):
    (tmp_path / "round").mkdir()
    (tmp_path / "face").write_text("a file called face\n")
    run = run_capped(["render", str(track), "-o", "out.mp4", "--face", "round", "--size", "64"], tmp_path)
    assert run.returncode == 0, run
    run = run_capped(["render", str(track), "-o", "out.mp4", "--face", "./round"], tmp_path)
    assert run.refused_in_one_line() and "round" in run.stderr


@pytest.mark.slow  # a studio started, a render begun (3 s)
def test_a_busy_studio_refuses_bombs_and_stops_on_sigterm_within_two_seconds(tmp_path):
    (tmp_path / "usebomb.svg").write_text(use_bomb(7, 10))
    (tmp_path / "long.svg").write_text(long_path(200_000))
    peak_file = tmp_path / ".peak"
    process = subprocess.Popen(capped_command(["-m", "toonface", "studio", "--listen", "127.0.0.1:0"], peak_file),
                               cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        assert process.stdout is not None
        address = re.search(r"http://(\S+?)/", process.stdout.readline()).group(1)  # type: ignore[union-attr]

        async def drive() -> tuple[list[str], float]:
            async with aiohttp.ClientSession() as session, session.ws_connect(
                    f"ws://{address}/ws", headers={"Origin": f"http://{address}"}) as ws:
                errors = []
                for name in ("usebomb.svg", "long.svg"):
                    started = time.perf_counter()
                    await ws.send_str(json.dumps({"op": "faceedit", "action": "import_svg", "path": name}))
                    errors.append(await _next_of(ws, "error"))
                    assert time.perf_counter() - started < 5.0
                await ws.send_str(json.dumps({"op": "render", "path": "long.mp4", "fps": 240}))
                while json.loads(await _next_of(ws, "rendering", whole=True))["frames"] < 10:
                    pass
                process.send_signal(signal.SIGTERM)
                started = time.perf_counter()
                await asyncio.to_thread(process.wait, 10)
                return errors, time.perf_counter() - started, peak_mb(peak_file)

        errors, stopped_in, peak = asyncio.run(drive())
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        process.stdout.close()  # type: ignore[union-attr]
    assert "more than" in errors[0] and "elements" in errors[0] and "points" in errors[1]
    assert stopped_in < 2.0 and not (tmp_path / "long.mp4").exists() and peak < 500


async def _next_of(ws: aiohttp.ClientWebSocketResponse, kind: str, whole: bool = False) -> str:
    """The next message of type ``kind`` (its ``message``, or the whole of it)."""
    while True:
        message = await ws.receive(timeout=10.0)
        data = json.loads(message.data)
        if data.get("type") == kind:
            return message.data if whole else str(data.get("message"))
