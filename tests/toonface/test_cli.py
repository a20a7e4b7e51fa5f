"""The command line: entry points, --help, one-line errors, and the demo end to end."""

import importlib
import importlib.metadata
import importlib.util
import json
import re
import socket
import subprocess
import sys

import av
import click
import numpy as np
import pytest

from capture import Take, load_take, save_take, synthesize
from capture.performance import DEFAULT_EXPRESSIONS
from toon import MOTOR_CODES, builtin_faces, load_track, motor_index
from toonface.cli import cli, main
from toonface.pipeline import map_onto_face

SUBCOMMANDS = ["demo", "synth", "info", "track", "clean", "calibrate", "map", "render", "retarget", "score", "play",
               "anim", "send", "receive", "relay", "batch", "markerset", "studio", "lipsync", "export",
               "faces", "face", "room"]


def test_every_console_script_entry_point_imports():
    scripts = [ep for ep in importlib.metadata.entry_points(group="console_scripts") if ep.value.startswith("toonface")]
    assert [ep.name for ep in scripts] == ["toonface"]
    for ep in scripts:
        assert callable(ep.load())


def test_help_lists_the_subcommands(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for name in SUBCOMMANDS:
        assert f"  {name} " in out
    assert set(cli.commands) == set(SUBCOMMANDS)


@pytest.mark.parametrize("name", SUBCOMMANDS)
def test_each_subcommand_has_help(capsys, name):
    assert main([name, "--help"]) == 0
    assert "Usage: toonface " + name in capsys.readouterr().out


@pytest.mark.parametrize("argv, fragment", [
    (["nonsense"], "No such command 'nonsense'"),
    (["demo", "--bogus"], "No such option"),
    (["demo", "--size", "333"], "even size"),
    (["map"], "Missing argument 'TAKE'"),
    (["map", "missing.npz", "-o", "m.csv"], "missing.npz: no such file"),
    (["map", "t.xyz", "-o", "m.csv"], "unknown take format '.xyz'"),
    (["render", "missing.csv", "-o", "v.mp4"], "missing.csv: no such file"),
    (["render", "m.csv", "-o", "v.mp4", "--size", "big"], "expected N or WxH"),
    (["retarget", "t.npz", "-o", "v.mp4", "--neutral", "2:1"], "START < END"),
    (["demo", "--face", "nobody"], 'no built-in face "nobody"'),
    (["send", "--to", "127.0.0.1:7710"], "give a SOURCE"),
    (["send", "synthetic", "--vmc", "39539", "--to", "127.0.0.1:7710"], "give one of a SOURCE, --vmc and"),
    (["send", "--openseeface", "x:y", "--to", "127.0.0.1:7710"], "expected HOST:PORT"),
    (["send", "--vmc", "127.0.0.1:99999", "--to", "127.0.0.1:7710"], "port must be 0..65535"),
    (["play", "--vmc", "1:2:x", "--seconds", "1"], "expected HOST:PORT"),
    (["play", "--eye-contact", "--seconds", "1"], "eye contact is for a performer"),
    (["play", "--max-gap", "1", "--seconds", "1"], "filling lost markers is for a performer"),
])
def test_bad_input_is_one_line_and_nonzero(tmp_path, monkeypatch, capsys, argv, fragment):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    err = capsys.readouterr().err
    assert code != 0
    assert err.count("\n") == 1 and err.startswith("toonface: error: "), err
    assert fragment in err


def test_synth_map_render_chain(tmp_path, capsys):
    take, motors, video = tmp_path / "t.npz", tmp_path / "m.csv", tmp_path / "frames"
    assert main(["synth", "-o", str(take), "--seconds", "2", "--noise", "0"]) == 0
    assert (tmp_path / "t.truth.csv").is_file()
    assert main(["map", str(take), "-o", str(motors), "--neutral", "0:1", "--cutoff", "0", "--no-spikes"]) == 0
    truth, mapped = load_track(tmp_path / "t.truth.csv"), load_track(motors)
    np.testing.assert_allclose(mapped.values, truth.values, atol=2e-6)
    assert main(["render", str(motors), "-o", str(video), "--size", "64x48", "--fps", "15"]) == 0
    assert len(list(video.glob("frame_*.png"))) == 30
    assert load_take(take).frames == 60


def test_a_layout_no_preset_knows_is_refused_naming_the_file_and_the_way_on(tmp_path, capsys):
    """It named neither the file nor `markerset draft`, the command for a layout toonface has not seen."""
    syn = synthesize(seconds=1, noise_mm=0.0).take
    odd = tmp_path / "odd.npz"
    save_take(Take(syn.positions, tuple(f"M{i}" for i in range(syn.markers)), 30.0), odd)
    assert main(["map", str(odd), "-o", str(tmp_path / "m.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("toonface: error: odd.npz: no built-in mapping matches its 32 ")
    assert "(M0, M1, M2, M3, M4, M5...)" in err and "toonface markerset draft TAKE" in err
    assert not (tmp_path / "m.csv").exists()


def test_a_corrupt_track_writes_nothing(tmp_path, capsys):
    (tmp_path / "m.csv").write_text("time,BRL\n0,0\n")
    assert main(["render", str(tmp_path / "m.csv"), "-o", str(tmp_path / "v.mp4")]) == 2
    assert not (tmp_path / "v.mp4").exists()


@pytest.mark.slow
def test_demo_end_to_end(tmp_path):
    """The real command, in its own process: a 300-frame 512x512 H.264 file and its inputs."""
    out = tmp_path / "demo"
    result = subprocess.run([sys.executable, "-m", "toonface", "demo", "--out", str(out)],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "wrote video" in result.stdout and "render" in result.stdout
    with av.open(str(out / "demo.mp4")) as c:
        stream = c.streams.video[0]
        assert stream.codec_context.name == "h264"
        frames = [f.to_ndarray(format="rgb24") for f in c.decode(video=0)]
    assert len(frames) == 300 and frames[0].shape == (512, 512, 3)
    assert load_take(out / "take.npz").frames == 300
    assert load_track(out / "motors.csv").frames == 300 and load_track(out / "truth.csv").frames == 300
    # The face moves: frames during a blink, the smile and a head turn differ from the neutral one.
    neutral = frames[15].astype(int)
    for moving in (48, 90, 250):
        assert np.abs(frames[moving].astype(int) - neutral).max(axis=2).mean() > 1.0


@pytest.mark.slow
def test_bench_prints_one_json_figure_per_line():
    result = subprocess.run([sys.executable, "-m", "bench", "--quick", "render", "pipeline"],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    figures = [json.loads(line) for line in result.stdout.splitlines()]
    names = [f["name"] for f in figures]
    faces = builtin_faces()
    peers = [p for p in ("skia", "cairo") if importlib.util.find_spec(p)]  # skia-python, pycairo: make bench-deps
    kinds = ["fps", "gl_fps", *[f"{p}_fps" for p in peers], "picture_mad", "gl_ratio", *["peer_ratio"][:len(peers)]]
    per_face = [f"render.{kind}.{face}" for face in faces for kind in kinds]
    assert names == per_face + ["render.fps", *(["render.peer_ratio"] if peers else []), "pipeline.fps"]
    by_name = {f["name"]: f for f in figures}
    for f in figures:
        assert set(f) == {"name", "value", "unit", "goal", "higher_is_better", "detail"}
        assert f["value"] > 0
    for face in faces:  # a ratio is the median of the blocks' ratios: between their quartiles
        detail = by_name[f"render.gl_ratio.{face}"]["detail"]
        assert detail["q1"] - 1e-3 <= by_name[f"render.gl_ratio.{face}"]["value"] <= detail["q3"] + 1e-3
        assert detail["blocks"] == detail["frames"] // detail["block_frames"] * detail["passes"] == 2  # --quick
        assert by_name[f"render.picture_mad.{face}"]["value"] < 1.0
    assert by_name["render.fps"]["value"] == min(by_name[f"render.fps.{face}"]["value"] for face in faces)
    bad = subprocess.run([sys.executable, "-m", "bench", "nope"], capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2 and "unknown benchmark group" in bad.stderr


def test_map_reads_any_take_format_and_passes_the_table_options(tmp_path, capsys):
    take = synthesize(seconds=2, noise_mm=0).take
    csv = save_take(take, tmp_path / "t.csv")
    assert main(["map", str(csv), "-o", str(tmp_path / "m.csv")]) == 0
    trc = save_take(take, tmp_path / "t.trc")
    assert main(["map", str(trc), "-o", str(tmp_path / "m.csv"), "--rate", "30"]) == 2
    assert "carries its own rate" in capsys.readouterr().err


def test_synth_follows_a_script_or_a_calibrated_repertoire(tmp_path, capsys):
    script = tmp_path / "s.toml"
    script.write_text('format = "toonface.performance/1"\nseconds = 2.5\n'
                      '[[cue]]\nkind = "expression"\nname = "anger"\nstart = 0.5\nseconds = 1.5\n')
    assert main(["synth", "-o", str(tmp_path / "a.npz"), "--script", str(script), "--rate", "20"]) == 0
    truth = load_track(tmp_path / "a.truth.csv")
    assert truth.frames == 50 and truth.values[25, motor_index("BRM")] == pytest.approx(0.0, abs=1e-6)
    assert main(["synth", "-o", str(tmp_path / "b.npz"), "--calibration", "--seconds", "2", "--max-turn", "10",
                 "--expressions", "fear"]) == 0
    truth = load_track(tmp_path / "b.truth.csv")
    assert truth.frames == round((1 + 12 * 1.2 + 2) * 30)
    assert truth.values[:, motor_index("HH")].max() == pytest.approx(1.0)  # the calibration turns fully
    assert main(["synth", "-o", str(tmp_path / "c.npz"), "--expressions", "fear,smirk"]) == 2
    assert "not in the repertoire: smirk" in capsys.readouterr().err


def test_clean_rejects_spikes_fills_gaps_and_writes_a_take(tmp_path, capsys):
    syn = synthesize(seconds=4, rate=60, noise_mm=0.0)
    pos = syn.take.positions.copy()
    pos[100, 20] += 25.0  # a spike
    pos[150:170, 12] = np.nan  # a third of a second unseen
    source = save_take(type(syn.take)(pos, syn.take.labels, 60.0), tmp_path / "raw.npz")
    assert main(["clean", str(source), "-o", str(tmp_path / "clean.npz")]) == 0
    assert "1 spikes rejected, 21 samples filled, 0 still missing, head motion removed" in capsys.readouterr().out
    cleaned = load_take(tmp_path / "clean.npz")
    assert np.abs(cleaned.positions - syn.take.positions).max() < 1.0  # spike gone, gap bridged
    assert main(["clean", str(tmp_path / "missing.npz"), "-o", str(tmp_path / "x.npz")]) == 2


def test_clean_plain_smoothing_is_the_low_pass_alone(tmp_path):
    """--plain-smoothing reaches the cleaning: the take comes out as clean_take's without hold
    smoothing, and by default a still marker comes out steadier than that."""
    from mapping import CleanSettings
    from mapping.clean import clean_take

    syn = synthesize(seconds=4, rate=60, noise_mm=0.3)
    source = save_take(syn.take, tmp_path / "raw.npz")
    assert main(["clean", str(source), "-o", str(tmp_path / "plain.npz"), "--plain-smoothing"]) == 0
    assert main(["clean", str(source), "-o", str(tmp_path / "held.npz")]) == 0
    plain, held = load_take(tmp_path / "plain.npz"), load_take(tmp_path / "held.npz")
    np.testing.assert_allclose(plain.positions, clean_take(syn.take, CleanSettings(holds=False))[0].positions,
                               atol=1e-4)
    lid = syn.take.index("LID_R_LOW")  # at rest over the first second
    assert np.std(np.diff(held.positions[10:60, lid], axis=0)) < 0.7 * np.std(np.diff(plain.positions[10:60, lid],
                                                                                     axis=0))


def test_calibrate_map_with_the_profile_and_score(tmp_path, capsys):
    take, profile, motors, png = (tmp_path / n for n in ("t.npz", "p.toml", "m.csv", "s.png"))
    exact = ["--cutoff", "0", "--no-spikes"]
    assert main(["synth", "-o", str(take), "--seconds", "1", "--noise", "0", "--calibration"]) == 0
    assert main(["calibrate", str(take), "-o", str(profile), "--neutral", "0:1", "--range", "1:15.4", *exact]) == 0
    said = capsys.readouterr()
    assert "neutral 0-1 s, range percentiles 0.5-99.5 of 1-15.4 s" in said.out
    assert "head angles are read about the head's own axes, learnt from the range's head turns and nods, 0.0 " \
           "degrees from the head frame's" in said.err  # the synthetic head's markers sit where the set says
    assert main(["map", str(take), "-o", str(motors), "--profile", str(profile), *exact]) == 0
    truth = load_track(tmp_path / "t.truth.csv")
    np.testing.assert_allclose(load_track(motors).values, truth.values, atol=1e-6)
    capsys.readouterr()
    assert main(["score", str(motors), "-o", str(png), "--compare", str(tmp_path / "t.truth.csv"), "--text",
                 "--motors", "ERU,MB"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("ERU ") and lines[1].startswith(" MB ") and lines[2].startswith("wrote")
    import cv2
    assert cv2.imread(str(png)).shape == (2 * 48 + 36, 1200, 3)


def test_bad_mapping_and_profile_files_exit_2_naming_the_field(tmp_path, capsys):
    take = tmp_path / "t.npz"
    assert main(["synth", "-o", str(take), "--seconds", "2"]) == 0
    (tmp_path / "m.toml").write_text('format = "toonface.mapping/1"\nmarkerset = "toon32"\n'
                                     '[motor.ERU]\nsources = [{ marker = "LID_R_UP", axis = "q" }]\n')
    (tmp_path / "p.toml").write_text('format = "toonface.profile/1"\nmarkerset = "toon32"\n')
    capsys.readouterr()
    assert main(["map", str(take), "-o", str(tmp_path / "a.csv"), "--mapping", str(tmp_path / "m.toml")]) == 2
    assert "m.toml: motor.ERU.sources[0].axis: expected" in capsys.readouterr().err
    assert main(["map", str(take), "-o", str(tmp_path / "a.csv"), "--profile", str(tmp_path / "p.toml")]) == 2
    assert "p.toml: rest_rotation: missing" in capsys.readouterr().err
    assert not (tmp_path / "a.csv").exists()


def test_anim_edits_files_and_renders_a_knot_point_animation(tmp_path, capsys):
    a, clip, b, c, track = (str(tmp_path / n) for n in ("a.toml", "clip.toml", "b.toml", "c.toml", "m.csv"))
    (tmp_path / "a.toml").write_text('format = "toonface.animation/1"\nduration = 2.0\n[knots]\n'
                                     'BRL = [[0, 0.4], [1, 1.0], [2, 0.4]]\nMB = [[0, 0.1], [2, 0.6]]\n')
    assert main(["anim", "copy", a, "-o", clip, "--motors", "BRL", "--from", "0", "--to", "2"]) == 0
    assert main(["anim", "paste", a, clip, "-o", b, "--at", "0", "--onto", "BRL=BLL"]) == 0
    assert main(["anim", "scale", b, "-o", c, "--time", "2", "--motors", "MB"]) == 0
    assert main(["anim", "concat", c, a, "-o", c, "--fade", "0.5"]) == 0
    assert main(["anim", "sample", c, "-o", track, "--rate", "10"]) == 0
    sampled = load_track(track)
    assert sampled.duration == pytest.approx(5.5)  # 4 s (MB stretched) + 2 s - 0.5 s of fade
    np.testing.assert_allclose(sampled.column("BLL")[:21:5], [0.4, 0.7, 1.0, 0.7, 0.4])  # the copied brow
    assert main(["render", a, "-o", str(tmp_path / "frames"), "--size", "32", "--fps", "5"]) == 0
    assert len(list((tmp_path / "frames").glob("*.png"))) == 10
    assert main(["anim", "paste", a, clip, "-o", b, "--at", "0", "--onto", "BRL=XX"]) == 2
    assert "Invalid value for --onto: unknown motor code(s) XX" in capsys.readouterr().err  # it said --motors
    eased = str(tmp_path / "eased.toml")
    assert main(["anim", "knot", a, "-o", eased, "--motor", "BRL", "--ease", "0"]) == 0
    assert "BRL = [[0.0, 0.4, \"ease\"], [1.0, 1.0], [2.0, 0.4]]" in (tmp_path / "eased.toml").read_text()
    assert main(["anim", "sample", eased, "-o", track, "--rate", "4"]) == 0
    assert load_track(track).column("BRL")[1] == pytest.approx(0.4 + 0.6 * 0.15625)  # a quarter of the way: eased
    assert main(["anim", "knot", eased, "-o", eased, "--motor", "BRL", "--linear", "0"]) == 0
    assert "BRL = [[0.0, 0.4], [1.0, 1.0], [2.0, 0.4]]" in (tmp_path / "eased.toml").read_text()
    assert main(["anim", "knot", a, "-o", eased, "--motor", "BRL", "--ease", "2"]) == 2
    assert "last knot starts no segment" in capsys.readouterr().err


def test_help_imports_no_heavy_library():
    """--help of every subcommand loads none of the libraries that made start-up take seconds."""
    heavy = ["scipy", "cv2", "av", "moderngl", "distributed", "dask", "pysindy", "mapbox_earcut", "tqdm", "cairocffi"]
    code = ("import sys\nfrom toonface.cli import cli, main\n"
            "for name in [None, *cli.commands]:\n"
            "    assert main(([name] if name else []) + ['--help']) == 0\n"
            f"sys.stderr.write('loaded: ' + ' '.join(m for m in {heavy!r} if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert result.stderr.strip() == "loaded:"


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_the_live_mapper_loads_no_signal_library_until_a_filter_needs_one():
    """scipy.signal was a second of `send` and `play --source` start-up, for a filter most
    mappings never make."""
    code = ("import sys\nfrom toonface.send import build_mapper\nfrom capture.sources import synthetic_source\n"
            "source = synthetic_source(seconds=2)\nmapper = build_mapper(source)\n"
            "for frame in source.frames:\n    mapper.step_frame(frame)\n"
            "sys.stderr.write(str('scipy.signal' in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert result.stderr.strip() == "False"


@pytest.mark.parametrize("argv, fragment", [
    (["score", "{m}", "-o", "{out}/s.png", "--motors", "XX"],
     "Invalid value for --motors: unknown motor code(s) XX"),  # was: internal error: KeyError
    (["score", "{m}", "-o", "{out}/s.pdf"], "cannot write a picture as '.pdf' (formats: .png, .jpg"),
    (["face", "classic", "--sheet", "{out}/s.gif"], "cannot write a picture as '.gif'"),
    (["calibrate", "{t}", "-o", "{out}/p.yaml"], "cannot write a profile as '.yaml' (formats: .toml, .json)"),
    (["map", "{t}", "-o", "{out}/no/such/dir/m.csv"], "cannot write: no such folder"),  # it made the folders
    (["render", "{m}", "-o", "{out}/v.mp4", "--size", "100x"], "Invalid value for --size: expected N or WxH"),
    (["clean", "{t}", "-o", "{out}/c.npz", "--cutoff", "100"],
     "Invalid value for --cutoff: 100 Hz is not below half the take's 30 Hz frame rate"),
    (["anim", "scale", "{out}/none.toml", "-o", "{out}/x.toml", "--time", "x"], "(see 'toonface anim scale --help')"),
])
def test_rough_edges_are_refused_in_one_line(small_take, tmp_path, capsys, argv, fragment):
    args = [a.format(t=small_take / "t.npz", m=small_take / "m.csv", out=tmp_path) for a in argv]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("toonface: error: ") and fragment in err, err
    assert not [p for p in tmp_path.rglob("*") if p.is_file()]  # nothing written, no folder made


def test_outputs_are_written_in_the_format_their_name_says(small_take, tmp_path, capsys):
    assert main(["score", str(small_take / "m.csv"), "-o", str(tmp_path / "s.txt"), "--motors", "mb,HH"]) == 0
    lines = (tmp_path / "s.txt").read_text(encoding="utf-8").splitlines()
    assert [line.split()[0] for line in lines] == ["MB", "HH"]
    assert main(["face", "classic", "--sheet", str(tmp_path / "s.jpg"), "--size", "64"]) == 0
    assert (tmp_path / "s.jpg").read_bytes()[:3] == b"\xff\xd8\xff"  # JPEG, not PNG
    assert main(["calibrate", str(small_take / "t.npz"), "-o", str(tmp_path / "p.json")]) == 0
    doc = json.loads((tmp_path / "p.json").read_text())
    assert doc["format"] == "toonface.profile/1" and doc["markerset"] == "toon32"
    assert main(["map", str(small_take / "t.npz"), "-o", str(tmp_path / "m.csv"), "--profile",
                 str(tmp_path / "p.json")]) == 0
    assert main(["clean", str(small_take / "t.npz"), "-o", str(tmp_path / "c.npz")]) == 0  # default cutoff: fine


def test_a_busy_address_names_the_option_and_address(capsys):
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        assert main(["play", "--listen", f"127.0.0.1:{port}", "--seconds", "0.1", "--size", "32"]) == 2
    err = capsys.readouterr().err
    assert f"Invalid value for --listen: cannot listen on 127.0.0.1:{port}: Address already in use" in err


def _options():
    def walk(command, path):
        if isinstance(command, click.Group):
            for name, sub in command.commands.items():
                yield from walk(sub, [*path, name])
        else:
            for param in command.params:
                if isinstance(param, click.Option) and param.name != "help":
                    yield " ".join(path), param
    return list(walk(cli, []))


def test_every_option_s_help_default_is_its_real_default():
    """`map --help` said it calibrated on the take by default; it used the typical profile."""
    described = {}
    for where, option in _options():
        stated = re.search(r"\[default: ([^\]]*)\]", option.help or "")
        real = isinstance(option.default, (int, float, str)) and option.default != "" and not option.is_flag
        if real:  # a real default is shown by click itself, from the value the command gets
            assert option.show_default and not stated, f"{where} {option.opts}"
        elif stated:
            described[(where, option.opts[-1])] = stated.group(1)
    # defaults the help describes in words, against the values and behaviour they describe
    assert described[("synth", "--expressions")] == ",".join(DEFAULT_EXPRESSIONS)
    assert described[("score", "--motors")] == f"all {len(MOTOR_CODES)}"
    assert described[("map", "--profile")].startswith("the marker set's built-in typical profile")
    assert described[("calibrate", "--neutral")] == "first"  # it spoke of "a given profile's rest"


def test_map_without_a_profile_uses_the_typical_one_as_its_help_says(small_take):
    mapped = map_onto_face(load_take(small_take / "t.npz"))  # what `map` runs without --profile
    assert any("built-in typical profile for toon32" in note for note in mapped.meta["notes"])


def test_face_save_writes_a_file_that_draws_as_the_built_in_face(tmp_path, capsys):
    """`face NAME --save mine.json`: the animator's start for a face of their own."""
    from toon import FaceRig, load_face

    mine = tmp_path / "mine.json"
    assert main(["face", "cat", "--save", str(mine)]) == 0
    assert f"wrote {mine}" in capsys.readouterr().out
    built_in, saved = load_face("cat"), load_face(mine)
    pose = built_in.neutral() * 0.5 + 0.25
    a = FaceRig(built_in).geometry(pose, built_in.extra_neutral())
    b = FaceRig(saved).geometry(pose, saved.extra_neutral())
    assert len(a.items) == len(b.items)
    for x, y in zip(a.items, b.items, strict=True):
        assert np.allclose(x.vertices, y.vertices) and x.fill == y.fill
    assert main(["face", "cat", "--save", str(tmp_path / "mine.toml")]) == 2
    assert "expected a .json face file" in capsys.readouterr().err


def test_face_save_names_the_face_after_its_file(tmp_path, capsys):
    from toon import load_face

    assert main(["face", "cat", "--save", str(tmp_path / "mine.json")]) == 0
    assert load_face(str(tmp_path / "mine.json")).name == "mine"  # it kept "cat" (issue 69)
    assert "(mine, from cat:" in capsys.readouterr().out
    assert main(["face", "cat", "--save", str(tmp_path / "b.json"), "--name", "Whiskers"]) == 0
    assert load_face(str(tmp_path / "b.json")).name == "Whiskers"
    assert main(["face", "cat", "--name", "Whiskers"]) == 2  # a name for no file
