"""--start and --end on map, render, retarget, lipsync and export web (issue 69, item 5): the
whole input is read, the output keeps START to END with its own time from 0 there, and the sound
is cut alike; and ``anim knot`` refusing a typo'd motor, growing for a knot past the end."""

import base64
import io
import re

import av
import numpy as np
import pytest

from capture import save_take, synthesize
from tests.helpers.sounds import write_wav
from toon import load_track
from toonface.cli import main


@pytest.fixture
def take(tmp_path):
    path = tmp_path / "take.npz"
    save_take(synthesize(seconds=4.0, rate=30.0, seed=3).take, path)
    return path


def test_map_keeps_the_part_of_the_whole_takes_motors(take, tmp_path, capsys):
    whole, part = tmp_path / "whole.csv", tmp_path / "part.csv"
    assert main(["map", str(take), "-o", str(whole)]) == 0
    assert main(["map", str(take), "-o", str(part), "--start", "1", "--end", "2.5"]) == 0
    assert "1-2.5 s of the input" in capsys.readouterr().out
    all_of_it, kept = load_track(whole), load_track(part)
    assert kept.frames == 45 and kept.times[0] == 0.0  # frames 30-74, its own time from 0
    np.testing.assert_array_equal(kept.values, all_of_it.values[30:75])  # calibrated on the whole take


def test_a_trim_outside_the_input_or_backwards_is_one_line(take, tmp_path, capsys):
    out = str(tmp_path / "m.csv")
    assert main(["map", str(take), "-o", out, "--start", "2", "--end", "1"]) == 2
    assert "--end: 1 s is not after --start 2 s" in capsys.readouterr().err
    assert main(["map", str(take), "-o", out, "--start", "9"]) != 0
    err = capsys.readouterr().err
    assert "no frame from 9 s" in err and "lasts 4 s" in err and "Traceback" not in err
    assert not (tmp_path / "m.csv").exists()


def _audio(path) -> tuple[np.ndarray, int]:
    with av.open(str(path)) as movie:
        stream = movie.streams.audio[0]
        samples = np.concatenate([f.to_ndarray().mean(axis=0) for f in movie.decode(stream)])
        return samples, stream.rate


def test_render_cuts_the_sound_with_the_picture(take, tmp_path):
    motors, voice = tmp_path / "m.csv", tmp_path / "voice.wav"
    assert main(["map", str(take), "-o", str(motors)]) == 0
    rate = 16000
    t = np.arange(4 * rate) / rate
    write_wav(voice, np.where(t >= 2.0, 0.5 * np.sin(2 * np.pi * 440 * t), 0.0), rate)  # silent, then a tone at 2 s
    out = tmp_path / "part.mp4"
    assert main(["render", str(motors), "-o", str(out), "--size", "64", "--fps", "10", "--sound", str(voice),
                 "--start", "1.5", "--end", "3"]) == 0
    with av.open(str(out)) as movie:
        assert sum(1 for _ in movie.decode(video=0)) == 15
    sound, heard = _audio(out)
    level = [float(np.sqrt(np.mean(sound[int(a * heard):int(b * heard)] ** 2))) for a, b in ((0.05, 0.4), (0.6, 1.4))]
    assert level[0] < 0.02 and level[1] > 0.2  # the tone comes 0.5 s in: at 2 s of the voice
    assert abs(len(sound) / heard - 1.5) < 0.1


def test_lipsync_cues_of_a_part_are_the_wholes_from_there(tmp_path):
    voice = tmp_path / "voice.wav"
    rate = 16000
    t = np.arange(3 * rate) / rate
    syllables = (np.sin(2 * np.pi * 3 * t) > 0) & (t > 0.3) & (t < 2.7)  # six bursts of a buzz
    write_wav(voice, syllables * 0.4 * np.sign(np.sin(2 * np.pi * 150 * t)), rate)
    whole, part = tmp_path / "whole.tsv", tmp_path / "part.tsv"
    assert main(["lipsync", str(voice), "-o", str(whole), "--every-frame"]) == 0
    assert main(["lipsync", str(voice), "-o", str(part), "--every-frame", "--start", "1", "--end", "2"]) == 0

    def cues(path):
        rows = [line.split("\t") for line in path.read_text().splitlines()]
        return [(round(float(a), 2), b) for a, b in rows]

    kept = cues(part)
    assert kept[0][0] == 0.0 and kept[-1] == (1.0, "X")
    inside = [(round(a - 1.0, 2), b) for a, b in cues(whole) if 1.0 < a < 2.0]
    assert [c for c in kept if 0 < c[0] < 1.0] == inside  # every change inside the part, 1 s earlier


def test_export_web_embeds_the_parts_sound(take, tmp_path):
    motors, voice = tmp_path / "m.csv", tmp_path / "voice.wav"
    assert main(["map", str(take), "-o", str(motors)]) == 0
    write_wav(voice, 0.3 * np.sin(np.arange(4 * 16000) * 0.1), 16000)
    page = tmp_path / "p.html"
    assert main(["export", "web", str(motors), "-o", str(page), "--sound", str(voice), "--start", "1",
                 "--end", "2"]) == 0
    html = page.read_text()
    data = base64.b64decode(re.search(r"data:audio/webm;base64,([A-Za-z0-9+/=]+)", html)[1])
    with av.open(io.BytesIO(data)) as sound:
        seconds = sum(f.samples for f in sound.decode(audio=0)) / 48000
    assert abs(seconds - 1.0) < 0.05  # of the voice's 4 s


def test_anim_knot_refuses_a_typo_and_grows_for_a_late_knot(tmp_path, capsys):
    a, b = tmp_path / "a.toml", tmp_path / "b.toml"
    a.write_text('format = "toonface.animation/1"\nduration = 26.5\n[knots]\nMB = [[0, 0.1], [26.5, 0.6]]\n')
    assert main(["anim", "knot", str(a), "-o", str(b), "--motor", "XYZ", "--add", "1,0.5"]) == 2
    assert "unknown motor code(s) XYZ" in capsys.readouterr().err and not b.exists()
    assert main(["anim", "knot", str(a), "-o", str(b), "--motor", "XYZ", "--add", "1,0.5", "--new"]) == 0
    assert "XYZ = [[1.0, 0.5]]" in b.read_text()
    capsys.readouterr()
    assert main(["anim", "knot", str(a), "-o", str(b), "--motor", "MB", "--add", "30,0.9"]) == 0
    assert "now 30 s long (was 26.5 s)" in capsys.readouterr().err
    text = b.read_text()
    assert "duration = 30.0" in text and "[30.0, 0.9]" in text  # where it was put, not at 26.5 s
    assert main(["anim", "knot", str(a), "-o", str(b), "--motor", "MB", "--add", "-1,0.9"]) == 2
