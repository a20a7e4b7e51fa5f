"""A voice through the same pipeline as any take (issue 40): map and retarget a sound file with
the voice mapping, its viseme sources in the mapping language."""

import av
import numpy as np
import pytest

from common import InputError
from mapping.mapfile import parse_mapping
from toon import MOTOR_CODES, load_track
from toonface.cli import main


@pytest.fixture
def voice(realdata, tmp_path):
    """GRID's bbaf2n ("bin blue at f two now") as a 16 kHz WAV: 0.9 s of silence, then speech."""
    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    if not clip.is_file():
        pytest.skip(f"{clip} is absent")
    path = tmp_path / "line.wav"
    with av.open(str(clip)) as source, av.open(str(path), "w") as target:
        stream = target.add_stream("pcm_s16le", rate=16000, layout="mono")
        resampler = av.AudioResampler(format="s16", layout="mono", rate=16000)
        for frame in source.decode(audio=0):
            for chunk in resampler.resample(frame):
                target.mux(stream.encode(chunk))
        target.mux(stream.encode(None))
    return path


@pytest.mark.realdata
def test_map_moves_the_mouth_from_a_voice_and_rests_in_its_silence(voice, tmp_path, capsys):
    assert main(["map", str(voice), "-o", str(tmp_path / "m.csv")]) == 0
    out, err = capsys.readouterr()
    assert "mapping voice, 5 motors mapped" in out
    assert "units: none (no markers" in err and "where nobody speaks" in err
    track = load_track(tmp_path / "m.csv")
    mb = track.values[:, MOTOR_CODES.index("MB")]
    rest = float(np.median(mb[:45]))  # room noise until 0.45 s; a breath at 0.54 s parts the lips (the video's too)
    assert np.ptp(mb[:45]) < 0.01 and mb[100:200].max() > rest + 0.3  # shut in silence, open in speech
    assert abs(mb[-20:].mean() - rest) < 0.02  # and back at rest after the last word
    corners = track.values[:, [MOTOR_CODES.index("MLH"), MOTOR_CODES.index("MRH")]]
    assert np.allclose(corners[:, 0], corners[:, 1]) and np.ptp(corners[:, 0]) > 0.1  # wide and round together
    others = [MOTOR_CODES.index(c) for c in ("BRL", "ERU", "PLH", "HH")]
    assert np.ptp(track.values[:, others], axis=0).min() > 0.003  # the life layer (issue 64) moves the rest
    assert main(["map", str(voice), "-o", str(tmp_path / "still.csv"), "--no-life"]) == 0
    still = load_track(tmp_path / "still.csv")
    assert np.ptp(still.values[:, others], axis=0).max() == 0.0  # the voice itself moves the mouth alone
    np.testing.assert_array_equal(still.values[:, MOTOR_CODES.index("MB")], mb)


@pytest.mark.realdata
def test_retarget_renders_the_voice_with_its_sound(voice, tmp_path):
    assert main(["retarget", str(voice), "-o", str(tmp_path / "line.mp4"), "--size", "128"]) == 0
    with av.open(str(tmp_path / "line.mp4")) as movie:
        kinds = sorted(s.type for s in movie.streams)
        frames = sum(1 for _ in movie.decode(video=0))
    assert kinds == ["audio", "video"] and abs(frames - 2.97 * 30) <= 2  # 30 frames a second by default


def test_a_viseme_source_is_a_mouth_shape_read_as_a_score():
    doc = {"format": "toonface.mapping/1", "name": "v", "markerset": "voice",
           "motor": {"MB": {"sources": [{"viseme": "D", "weight": 0.9}], "normalise": "score"}}}
    rule = parse_mapping(doc, "v.toml").rules[0]
    assert rule.sources[0].kind == "blendshape" and rule.sources[0].channel == "viseme_D"
    doc["motor"]["MB"]["sources"] = [{"viseme": "Q"}]
    with pytest.raises(InputError, match="mouth shapes A, B, C, D, E, F, G, H, X"):
        parse_mapping(doc, "v.toml")
    doc["motor"]["MB"]["sources"] = [{"viseme": "D", "axis": "y"}]
    with pytest.raises(InputError, match="axis"):
        parse_mapping(doc, "v.toml")


@pytest.mark.realdata
def test_a_voice_has_no_table_options(voice, capsys):
    assert main(["info", str(voice), "--rate", "30"]) == 2
    assert "a voice has no rate to give" in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.realdata
@pytest.mark.parametrize("suffix", [".tsv", ".json", ".xml"])
def test_rhubarb_cues_read_back_as_the_motors_they_came_from(voice, tmp_path, suffix):
    """From the phones heard, a frame is one shape: its cues are its motors exactly."""
    assert main(["lipsync", str(voice), "--listen", "phones", "-o", str(tmp_path / f"cues{suffix}"),
                 "--every-frame"]) == 0
    assert main(["map", str(voice), "--listen", "phones", "-o", str(tmp_path / "voice.csv"), "--no-life"]) == 0
    assert main(["map", str(tmp_path / f"cues{suffix}"), "-o", str(tmp_path / "cues.csv")]) == 0
    from_voice, from_cues = load_track(tmp_path / "voice.csv"), load_track(tmp_path / "cues.csv")
    assert from_cues.frames == from_voice.frames
    np.testing.assert_allclose(from_cues.values, from_voice.values, atol=1e-6)


@pytest.mark.slow
@pytest.mark.realdata
def test_cues_from_the_sound_are_its_mouth_to_the_nearest_shape(voice, tmp_path):
    """From the sound, a frame between two shapes weighs both; its cue is the heavier, so the
    cues read back follow the voice's own motors, a shape at a time."""
    assert main(["lipsync", str(voice), "-o", str(tmp_path / "cues.tsv"), "--every-frame"]) == 0
    assert main(["map", str(voice), "-o", str(tmp_path / "voice.csv"), "--no-life"]) == 0
    assert main(["map", str(tmp_path / "cues.tsv"), "-o", str(tmp_path / "cues.csv")]) == 0
    from_voice, from_cues = load_track(tmp_path / "voice.csv"), load_track(tmp_path / "cues.csv")
    mb = MOTOR_CODES.index("MB")
    voice_mb, cues_mb = from_voice.values[:, mb], from_cues.values[:, mb]
    assert np.corrcoef(voice_mb, cues_mb)[0, 1] > 0.95 and np.abs(voice_mb - cues_mb).mean() < 0.03  # 0.973, 0.015
    assert np.abs(voice_mb - cues_mb).max() > 0.01  # the voice's own mouth is not a shape at a time


def test_held_cues_sit_on_frames_and_hold_two_but_a_closure_which_keeps_one():
    from capture.cues import held_cues

    cues = [(0.0, 0.92, "X"), (0.92, 0.93, "A"), (0.93, 0.95, "C"), (0.95, 1.18, "B"), (1.18, 1.2, "F"),
            (1.2, 2.97, "X")]
    # at 24 fps: A (under a frame) keeps frame 22, C (none left) goes, F (one frame) joins B
    assert [(round(a * 24), round(b * 24), s) for a, b, s in held_cues(cues, 24)] == [
        (0, 22, "X"), (22, 23, "A"), (23, 29, "B"), (29, 71, "X")]
    assert held_cues([(0.0, 0.01, "B"), (0.01, 0.5, "X")], 24) == [(0.0, 0.5, "X")]  # a first flicker: the next
    after = [(0.0, 1.0, "X"), (1.0, 1.05, "A"), (1.05, 1.09, "B"), (1.09, 1.5, "D")]  # B a frame, after a closure
    assert [(round(a * 24), round(b * 24), s) for a, b, s in held_cues(after, 24)] == [
        (0, 24, "X"), (24, 25, "A"), (25, 36, "D")]
    assert held_cues([(0.0, 0.5, "X")], 24) == [(0.0, 0.5, "X")]


@pytest.mark.slow
@pytest.mark.parametrize("language", ["en-us", "de"])
def test_lipsync_cues_for_an_editor_never_flicker_and_keep_every_closure(language, tmp_path):
    """Issue 69: of 70 cues for an English espeak-ng sentence 27 were shorter than a 24 fps frame
    (52 of 104 in German), and the .dat switched shapes on consecutive frames."""
    from bench import espeak

    if not espeak.available():
        pytest.skip("espeak-ng is not installed (make install puts it there)")
    from sounds import write_wav

    from capture.cues import read_cues

    spoken = espeak.say(espeak.SENTENCES[language][0], language)
    sound = write_wav(tmp_path / "said.wav", spoken.samples, spoken.rate)
    assert main(["lipsync", str(sound), "-o", str(tmp_path / "raw.tsv"), "--every-frame"]) == 0
    assert main(["lipsync", str(sound), "-o", str(tmp_path / "held.tsv")]) == 0
    assert main(["lipsync", str(sound), "-o", str(tmp_path / "held.dat")]) == 0
    raw, held = read_cues(tmp_path / "raw.tsv"), read_cues(tmp_path / "held.tsv")
    assert min(b - a for a, b, _ in raw) < 1 / 24  # as heard, some flicker
    frames = [round(b * 24) - round(a * 24) for a, b, _ in held[:-1]]  # (written to 10 ms, as Rhubarb's)
    assert all(f >= 2 or s == "A" for f, (_, _, s) in zip(frames, held, strict=False)) and min(frames) >= 1
    switches = [line.split() for line in (tmp_path / "held.dat").read_text().splitlines()[1:]]
    for (f0, s0), (f1, s1) in zip(switches, switches[1:], strict=False):
        assert int(f1) - int(f0) >= 2 or s0 == "A", (f0, s0, f1, s1)
    closures = sum(1 for _, _, s in raw if s == "A")
    assert sum(1 for _, _, s in held if s == "A") == closures  # every closed mouth kept


def test_cues_written_are_the_cues_read(tmp_path):
    from capture.cues import cues_text, read_cues

    cues = [(0.0, 0.92, "X"), (0.92, 0.99, "A"), (0.99, 1.18, "B"), (1.18, 2.97, "X")]
    folder = tmp_path
    for suffix in (".tsv", ".json", ".xml"):
        (folder / f"c{suffix}").write_text(cues_text(cues, suffix, "line.wav", "bin <blue> & at"))
        assert read_cues(folder / f"c{suffix}") == cues
    # Moho's switch data: the frame each cue starts on, counted from 1 (0.92 s is frame 23.08 at 24 fps)
    assert cues_text(cues, ".dat", fps=24) == "MohoSwitch1\n1 X\n23 A\n25 B\n29 X\n"
    assert cues_text(cues, ".dat", fps=10) == "MohoSwitch1\n1 X\n10 A\n11 B\n13 X\n"
    # a cue shorter than a frame, replaced on its frame by the shape shown before it: no switch (was "2 X" again)
    assert cues_text([(0.0, 0.1, "X"), (0.1, 0.12, "A"), (0.12, 0.5, "X")], ".dat", fps=10) == "MohoSwitch1\n1 X\n"
    (folder / "entity.xml").write_text('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaa">]><rhubarbResult/>')
    with pytest.raises(InputError, match="document type"):
        read_cues(folder / "entity.xml")
    (folder / "bad.tsv").write_text("0.00\tX\n0.50\tQ\n")
    with pytest.raises(InputError, match="line 2: expected start<TAB>shape"):
        read_cues(folder / "bad.tsv")
    (folder / "back.json").write_text('{"mouthCues": [{"start": 1, "end": 2, "value": "A"}, '
                                      '{"start": 0.5, "end": 3, "value": "X"}]}')
    with pytest.raises(InputError, match=r"mouthCues\[1\]: expected 0 <= start <= end"):
        read_cues(folder / "back.json")


@pytest.mark.slow
@pytest.mark.realdata
def test_the_words_given_are_aligned_and_are_for_a_voice_only(voice, tmp_path, capsys):
    text = tmp_path / "line.txt"
    text.write_text("bin blue at\nf two now\n")
    assert main(["map", str(voice), "--text", f"@{text}", "-o", str(tmp_path / "aligned.csv")]) == 0
    assert main(["map", str(voice), "-o", str(tmp_path / "heard.csv")]) == 0
    aligned, heard = (load_track(tmp_path / f"{n}.csv").values for n in ("aligned", "heard"))
    assert aligned.shape == heard.shape and np.abs(aligned - heard).max() > 0.05  # the words place the shapes
    capsys.readouterr()  # a word the dictionary lacks is spelled by espeak-ng's rules (issue 69: it was refused)
    assert main(["map", str(voice), "--text", "Bin blue, at F two... QQQ!", "-o", str(tmp_path / "x.csv")]) == 0
    assert "spelled by espeak-ng's rules (not in the pronouncing dictionary): qqq" in capsys.readouterr().err
    assert main(["lipsync", str(voice), "-o", str(tmp_path / "c.tsv")]) == 0
    assert main(["map", str(tmp_path / "c.tsv"), "--text", "hello", "-o", str(tmp_path / "y.csv")]) == 2
    assert "words (--text) are for a voice" in capsys.readouterr().err
    assert not (tmp_path / "y.csv").exists()


@pytest.mark.realdata
def test_render_carries_the_voice_a_track_was_lip_synced_from(voice, tmp_path, capsys):
    """The animator's route: cues, motors, then the motors rendered with their voice; a format
    that cannot carry sound and a file with none are refused before anything is drawn."""
    assert main(["lipsync", str(voice), "-o", str(tmp_path / "line.tsv")]) == 0
    assert main(["map", str(tmp_path / "line.tsv"), "-o", str(tmp_path / "line.csv")]) == 0
    capsys.readouterr()
    out = tmp_path / "line.webm"
    assert main(["render", str(tmp_path / "line.csv"), "-o", str(out), "--size", "64", "--fps", "25",
                 "--sound", str(voice)]) == 0
    assert "with the sound of line.wav" in capsys.readouterr().out
    with av.open(str(out)) as movie:
        audio, video = movie.streams.audio[0], movie.streams.video[0]
        frames = sum(1 for _ in movie.decode(video=0))
        assert audio.codec_context.name == "opus" and video.codec_context.name == "vp9"
    assert abs(frames - 2.97 * 25) <= 2
    for argv, said in (([str(tmp_path / "x.apng"), "--sound", str(voice)], "x.apng carries no sound"),
                       ([str(tmp_path / "x.mp4"), "--sound", str(tmp_path / "line.csv")], "line.csv: no sound in it")):
        assert main(["render", str(tmp_path / "line.csv"), "-o", *argv]) == 2
        assert said in capsys.readouterr().err
        assert not list(tmp_path.glob("x.*"))


@pytest.mark.realdata
def test_the_studio_opens_a_voice_alive_unless_told_no_life(voice, tmp_path, monkeypatch):
    """``studio line.wav`` maps the voice as ``map`` does: with the life layer, unless --no-life."""
    from toonface.studio.session import StudioSession

    monkeypatch.chdir(tmp_path)
    knots = {}
    for life in (None, False):
        editor = StudioSession("classic", animation=str(voice), life=life).editor
        knots[life] = {code: len(editor.animation.knots.get(code, ())) for code in ("PRH", "HV", "ERU", "MB")}
    assert knots[None]["MB"] > 2 and knots[False]["MB"] > 2  # the mouth either way
    assert all(knots[None][code] > 2 for code in ("PRH", "HV", "ERU"))  # eyes, breathing and blinks
    assert all(knots[False][code] <= 2 for code in ("PRH", "HV", "ERU"))  # still without it
