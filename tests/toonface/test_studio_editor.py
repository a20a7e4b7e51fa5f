"""The studio's Animation Editor without a browser: edits are toon.animation's (the same knots as
`toonface anim` on files), with undo, redo, a clipboard, playback and files."""

import numpy as np
import pytest
from studios import temp_folder

from toon import MOTOR_CODES, load_track, motor_index, standard_neutral
from toon import animation as an
from toon import animation_file as af
from toonface.cli import main
from toonface.studio.editor import UNDO_LEVELS, AnimationEditor
from toonface.studio.messages import apply
from toonface.studio.session import StudioSession


def _editor() -> AnimationEditor:
    editor = AnimationEditor(standard_neutral())
    for code, knots in {"BRL": [(0.5, 0.8), (1.5, 0.2), (3.0, 0.6)], "BRC": [(1.0, 0.9), (2.0, 0.3)],
                        "MB": [(0.0, 0.1), (2.5, 0.7), (4.0, 0.2)]}.items():
        for t, v in knots:
            editor.add_knot(code, t, v)
    return editor


def test_edits_undo_and_redo_step_by_step():
    editor = _editor()
    states = [editor.animation]
    editor.move_knot("BRL", 1, 2.0, 0.4)
    states.append(editor.animation)
    editor.move_knot("BRL", 1, 9.0, 0.4)  # kept between its neighbours
    assert editor.animation.knots["BRL"][1] == (3.0, 0.4)
    states.append(editor.animation)
    editor.delete_knot("MB", 0)
    states.append(editor.animation)
    editor.scale_value(["BRC"], 0.0, 5.0, 0.5)
    states.append(editor.animation)
    for state in reversed(states[:-1]):
        assert editor.undo() and editor.animation == state
    for state in states[1:]:
        assert editor.redo() and editor.animation == state
    assert not editor.redo()
    editor.undo()
    editor.add_knot("ERU", 1.0, 0.0)  # a new edit drops what could be redone
    assert not editor.redo()
    for _ in range(UNDO_LEVELS + 20):
        editor.add_knot("ERU", 1.0, float(np.random.default_rng(_).random()))
    assert sum(editor.undo() for _ in range(UNDO_LEVELS + 20)) == UNDO_LEVELS


def test_slices_are_toon_animations_operations():
    editor = _editor()
    start = editor.animation
    editor.copy(["BRL", "BRC"], 0.5, 2.0)
    clip = an.copy(start, ("BRL", "BRC"), 0.5, 2.0)
    assert editor.clipboard == clip and editor.animation == start  # copying is no edit
    editor.paste(2.5, ["BLL", "BLC"])  # the right brow's motion onto the left's
    assert editor.animation == an.paste(start, clip, 2.5, {"BRL": "BLL", "BRC": "BLC"})
    with pytest.raises(ValueError, match="2 motors"):
        editor.paste(0.0, ["BLL"])
    editor.undo()
    editor.cut(["MB"], 1.0, 2.0)
    edited, clip = an.cut(start, ("MB",), 1.0, 2.0)
    assert editor.animation == edited and editor.clipboard == clip
    editor.undo()
    editor.flip([], 0.0, 3.0)
    assert editor.animation == an.flip(start, None, 0.0, 3.0)
    editor.undo()
    editor.scale_time(["BRC"], 1.0, 2.0, 2.0)
    assert editor.animation == an.scale_time(start, ("BRC",), 1.0, 2.0, 2.0) and editor.animation.duration == 6.0
    with pytest.raises(ValueError, match="slice"):
        editor.flip([], 2.0, 1.0)
    with pytest.raises(ValueError, match="unknown motor"):
        editor.add_knot("XX", 1.0, 0.5)


def test_playback_moves_the_cursor_on_the_servers_clock():
    editor = _editor()
    editor.set_cursor(1.0)
    editor.play(now=100.0)
    editor.advance(101.5)
    assert editor.cursor == pytest.approx(2.5)
    assert editor.values()[motor_index("MB")] == pytest.approx(0.7)
    editor.advance(110.0)
    assert editor.cursor == 5.0 and not editor.playing  # stopped at the end
    editor.play(now=0.0, start=1.0, end=2.0, loop=True)
    editor.advance(2.25)
    assert editor.cursor == pytest.approx(1.25) and editor.playing


def test_files_round_trip_and_the_movie_script(tmp_path):
    editor = _editor()
    path = editor.save(str(tmp_path / "a.toml"))
    again = AnimationEditor(standard_neutral())
    again.open(str(path))
    assert again.animation == editor.animation
    frames = editor.sample(str(tmp_path / "a.csv"), 30.0)
    track = load_track(tmp_path / "a.csv")
    assert frames == track.frames == 150
    np.testing.assert_allclose(track.values[:, motor_index("MB")],
                               editor.animation.value("MB", np.arange(150) / 30.0), atol=1e-6)
    with pytest.raises(Exception, match="toml"):
        editor.save(str(tmp_path / "a.json"))


def test_the_server_drives_the_editor_and_the_face_shows_the_cursor():
    session = StudioSession("classic", folder=temp_folder())
    for message in ({"op": "knot", "action": "add", "code": "MB", "t": 1.0, "v": 0.9},
                    {"op": "knot", "action": "add", "code": "MB", "t": 3.0, "v": 0.1},
                    {"op": "cursor", "t": 1.0}):
        assert apply(session, message, 0.0) == ("animation", None)
    assert session.showing == "animation" and session.values[motor_index("MB")] == pytest.approx(0.9)
    apply(session, {"op": "slice", "action": "copy", "codes": ["MB"], "start": 0.0, "end": 3.0}, 0.0)
    apply(session, {"op": "paste", "at": 0.0, "onto": ["ERU"]}, 0.0)
    assert session.editor.animation.knots["ERU"] == an.copy(session.editor.animation, ("MB",), 0.0, 3.0).knots["MB"]
    apply(session, {"op": "playback", "action": "play", "loop": False}, 10.0)
    assert session.busy()
    session.tick(11.0)
    assert session.editor.cursor == pytest.approx(2.0)
    apply(session, {"op": "motor", "code": "HH", "value": 0.8}, 11.0)  # back to test mode, from where it was
    assert session.showing == "test" and not session.editor.playing
    assert session.values[motor_index("MB")] == pytest.approx(0.5)
    with pytest.raises(IndexError):
        apply(session, {"op": "knot", "action": "delete", "code": "MB", "index": 7}, 0.0)


def test_anim_knot_on_files_makes_the_editors_knots(tmp_path, capsys):
    editor = _editor()
    path = editor.save(str(tmp_path / "a.toml"))
    steps = [(["--add", "1.25,0.5"], lambda e: e.add_knot("BRC", 1.25, 0.5)),
             (["--move", "0:0.75,0.6"], lambda e: e.move_knot("BRC", 0, 0.75, 0.6)),
             (["--delete", "2"], lambda e: e.delete_knot("BRC", 2))]
    for args, edit in steps:
        assert main(["anim", "knot", str(path), "-o", str(path), "--motor", "brc", *args]) == 0
        edit(editor)
        assert af.load_animation(path) == editor.animation
    assert main(["anim", "knot", str(path), "-o", str(path), "--motor", "BRC", "--delete", "9"]) == 2
    assert main(["anim", "knot", str(path), "-o", str(path), "--motor", "BRC"]) == 2
    assert main(["anim", "knot", str(path), "-o", str(path), "--motor", "BRC", "--add", "x"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 3 and "has no knot 9" in err[0] and "one of --add" in err[1] and "TIME,VALUE" in err[2]
    assert sorted(editor.animation.knots, key=MOTOR_CODES.index) == ["BRL", "BRC", "MB"]


def test_a_track_or_a_take_opens_as_knots_and_the_command_agrees(tmp_path):
    from capture import save_take, synthesize
    from toon import save_track
    from toonface import map_onto_face

    take = synthesize(seconds=3.0, rate=60.0).take
    save_take(take, tmp_path / "take.npz")
    track = map_onto_face(take)
    save_track(track, tmp_path / "motors.csv")
    editor = AnimationEditor(standard_neutral())
    said = editor.open(str(tmp_path / "motors.csv"))
    expected = an.from_track(load_track(tmp_path / "motors.csv"), 0.01)
    assert editor.animation == expected and "a motor track" in said and editor.path is None
    assert main(["anim", "from-track", str(tmp_path / "motors.csv"), "-o", str(tmp_path / "a.toml")]) == 0
    assert af.load_animation(tmp_path / "a.toml") == expected
    assert "a take, mapped" in editor.open(str(tmp_path / "take.npz"))
    np.testing.assert_allclose(editor.animation.sample(60.0, standard_neutral()).values, track.values, atol=0.0101)
    with pytest.raises(Exception, match="no such file"):
        editor.open(str(tmp_path / "missing.csv"))
