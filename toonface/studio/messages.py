"""What the studio's pages say: each message applied to the session (:func:`apply`).

A message is a JSON object with an ``op``: test mode (``motor``, ``drag``, ``look``, ``follow``,
``play``, ``reset``, ``face``, ``live``), the Animation Editor (:data:`EDITOR_OPS`), the sound
(``sound``, ``labels``, ``hear``: the words and phones a voice says) and the face editor
(``faceedit`` with an ``action``). A message the session cannot take raises, and the page is
told why in one line (:func:`reason`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from toon.animation import MAX_DURATION, Animation
from toonface.studio.editor import NEW_SECONDS, TRACK_TOLERANCE, AnimationEditor
from toonface.studio.guard import Folder, index, number
from toonface.studio.session import StudioSession
from toonface.studio.sound import Label, Sound, heard_labels, load_labels, load_sound
from toonface.studio.tuner import MappingTuner


def apply(session: StudioSession, message: object, now: float) -> tuple[str, str | None]:
    """Apply one message from a page to ``session``; returns what the pages must be sent again
    (``"described"``: another face, everything; ``"animation"``: the staves; ``"frame"``) and a
    line for the page that sent it (what was written), if any.

    Raises
    ------
    ValueError, KeyError, TypeError, IndexError, InputError
        For a message the session cannot take (said back to the page in one line).
    """
    if not isinstance(message, dict):
        raise TypeError("a message is a JSON object")
    op = message.get("op")
    session.clock_to(now)  # what the message changes happens now (the face's physics runs on this clock)
    if op in EDITOR_OPS:
        return "animation", _edit(session, op, message, now)
    if op == "faceedit":
        codes = session.face.extra_codes
        said = _edit_face(session, message)  # a parameter more or less: new sliders and staves
        return ("face" if session.face.extra_codes == codes else "described"), said
    if op == "tune":
        return "tune", _tune(session, message, now)
    if op == "sound":
        session.sound = load_sound(session.folder.inside(message["path"], "a sound"))
        return "sound", f"opened {session.sound.path} ({session.sound.duration:.1f} s of sound)"
    if op == "hear":
        return "sound", show_heard(session, hear(message, session.sound))
    if op == "labels":
        path = session.folder.inside(message["path"], "labels")
        if session.sound is None:
            raise ValueError("open a sound before its labels")
        labels = load_labels(path)
        session.sound = replace(session.sound, labels=labels)
        return "sound", f"opened {message['path']} ({len(labels)} labels)"
    if op == "motor":
        session.set_motor(str(message["code"]), number(message["value"]))
    elif op == "drag":
        session.drag(str(message["point"]), number(message["x"]), number(message["y"]))
    elif op == "look":
        session.look(number(message["x"]), number(message["y"]))
    elif op == "follow":
        session.follow = bool(message["on"])
    elif op == "play":
        session.play(str(message["name"]), now, bool(message.get("loop")))
    elif op == "reset":
        session.reset()
    elif op == "face":
        session.set_face(session.folder.name_or_inside(message["name"], "a face"))
        return "described", None
    elif op == "live":
        session.show_live(bool(message["on"]))
    else:
        raise ValueError(f"unknown op {op!r}")
    return "frame", None


#: Messages for the Animation Editor (:func:`_edit`).
EDITOR_OPS = ("knot", "slice", "paste", "undo", "redo", "cursor", "playback", "duration", "new", "open", "save",
              "sample", "insert")


def _edit(session: StudioSession, op: str, message: dict, now: float) -> str | None:
    """One Animation Editor message; the face then shows the animation at the cursor. Returns
    what was written, for a save or a movie script."""
    editor = session.editor
    said = None
    if op == "knot":
        action, code = message["action"], str(message["code"])
        if action == "add":
            editor.add_knot(code, number(message["t"]), number(message["v"]))
        elif action == "move":
            editor.move_knot(code, index(message["index"]), number(message["t"]), number(message["v"]))
        elif action == "delete":
            editor.delete_knot(code, index(message["index"]))
        elif action == "ease":
            editor.ease_knot(code, index(message["index"]), bool(message["ease"]))
        else:
            raise ValueError(f"unknown knot action {action!r}")
    elif op == "slice":
        action, codes = message["action"], list(message.get("codes") or [])
        span = (number(message["start"]), number(message["end"]))
        if action in ("cut", "copy", "flip"):
            getattr(editor, action)(codes, *span)
        elif action in ("scale_time", "scale_value"):
            getattr(editor, action)(codes, *span, number(message["factor"]))
        else:
            raise ValueError(f"unknown slice action {action!r}")
    elif op == "paste":
        editor.paste(number(message["at"]), message.get("onto") or None)
    elif op in ("undo", "redo"):
        getattr(editor, op)()
    elif op == "cursor":
        editor.pause()
        editor.set_cursor(number(message["t"]))
    elif op == "playback":
        if message["action"] == "play":
            start, end = message.get("start"), message.get("end")
            editor.play(now, None if start is None else number(start), None if end is None else number(end),
                        bool(message.get("loop")))
        else:
            editor.pause()
            if message.get("at") is not None:  # where the page showed the cursor when Pause was pressed
                editor.set_cursor(number(message["at"]))
    elif op == "duration":
        editor.set_duration(number(message["seconds"]))
    elif op == "new":
        seconds = number(message.get("seconds", NEW_SECONDS))
        if not 0 < seconds <= MAX_DURATION:
            raise ValueError(f"a duration is 0..{MAX_DURATION:g} s, got {seconds:g}")
        session.editor = AnimationEditor(session.neutral, Animation({}, seconds), declared=session.editor.declared,
                                         life=session.editor.life)
    elif op == "insert":
        said = session.insert_motion(str(message["name"]))
    elif op == "open":
        tolerance = number(message.get("tolerance", TRACK_TOLERANCE))
        if not 0.001 <= tolerance <= 0.5:
            raise ValueError(f"a take is simplified within 0.001..0.5 of each value, got {tolerance:g}")
        units = str(message["units"]) if message.get("units") else None
        rate = number(message["rate"]) if message.get("rate") not in (None, "") else None
        if rate is not None and not 1 <= rate <= 10000:
            raise ValueError(f"a take's frame rate is 1..10000 Hz, got {rate:g}")
        said = editor.open(str(session.folder.inside(message["path"])), tolerance, units, rate, str(message["path"]))
    elif op == "save":
        path = message.get("path")
        said = f"wrote {editor.save(str(session.folder.inside(path)) if path else None)}"
    elif op == "sample":
        rate = number(message.get("rate", 30.0))
        if not 1 <= rate <= 1000:
            raise ValueError(f"a movie script's rate is 1..1000 frames/s, got {rate:g}")
        target = session.folder.inside(message["path"])
        said = f"wrote {target} ({editor.sample(str(target), rate)} frames at {rate:g} Hz)"
    session.show_animation()
    return said


#: The face editor's actions (:class:`~toonface.studio.faces.FaceEditor`'s methods) and their
#: arguments (``?``: may be left out).
FACE_ACTIONS = {"move_point": ("name", "x", "y"), "set_range": ("code", "end", "value"),
                "move_vertex": ("polygon", "index", "x", "y"), "add_vertex": ("polygon", "after", "x", "y"),
                "delete_vertex": ("polygon", "index"), "add_polygon": ("x", "y"),
                "move_component_point": ("component", "index", "x", "y", "part"),
                "new_component": ("kind", "x", "y", "size?"),
                "add_component_point": ("component", "part", "after", "x", "y"),
                "delete_component_point": ("component", "part", "index"),
                "set_point_kind": ("component", "part", "index", "kind", "master?"),
                "attach": ("component", "feature"),
                "group": ("indices", "name?"), "ungroup": ("index",),
                "insert_from_library": ("library", "use", "controls?", "dx?", "dy?"),
                "list_library": ("library",),
                "set_background": ("color",), "rename": ("name",),
                "set_param": ("code", "neutral?", "description?", "point?", "dx?", "dy?"),
                "delete_param": ("code",),
                "set_driver": ("name", "param", "inputs", "frequency", "damping", "swing?", "gain?"),
                "delete_driver": ("name",)}
#: What the face editor does to a polygon or a component as a unit: ``VERB_polygon`` or ``VERB_component``.
UNIT_ACTIONS = {"move": ("dx", "dy"), "scale": ("factor",), "flip": ("axis",), "duplicate": ("dx", "dy"),
                "delete": ()}


def _edit_face(session: StudioSession, message: dict) -> str | None:
    """One face editor message; the face shown becomes the edited one (its motors kept)."""
    faces, action = session.faces, str(message.get("action"))
    verb, _, kind = action.rpartition("_")
    said = None
    if action in FACE_ACTIONS:
        arguments = {key.rstrip("?"): _argument(key.rstrip("?"), message[key.rstrip("?")])
                     for key in FACE_ACTIONS[action] if not key.endswith("?") or key.rstrip("?") in message}
        if "library" in arguments:
            arguments["library"] = session.folder.name_or_inside(arguments["library"], "a library")
        getattr(faces, action)(**arguments)
    elif verb in UNIT_ACTIONS and kind in ("polygon", "component"):
        getattr(faces, verb)(kind, index(message[kind]), *[_argument(key, message[key]) for key in UNIT_ACTIONS[verb]])
    elif action in ("set_style", "set_component"):  # a polygon's or a component's fields
        kind = "polygon" if action == "set_style" else "component"
        faces.restyle(kind, index(message[kind]), **dict(message.get("fields") or {}))
    elif action in ("undo", "redo"):
        getattr(faces, action)()
    elif action == "copy":
        faces.copy_item(str(message["kind"]), index(message["index"]))
        said = f"copied {message['kind']} {message['index']}"
    elif action == "paste":
        faces.paste_item()
    elif action == "open":
        name = session.folder.name_or_inside(message["name"], "a face")
        faces.open(name)
        session.face_name = name
        said = f"editing a copy of {message['name']}"
    elif action == "save":
        said = f"wrote {faces.save(session.folder.inside(message['path']))}"
    elif action == "import_picture":
        path = session.folder.inside(message["path"], "a picture")
        picture = faces.import_artwork(path)[0]
        said = (f"imported {path.name} as component {picture}: move its corners, attach it (Attach), or give it "
                "a layer below 0 to put it behind the face")
    elif action == "import_svg":
        path = session.folder.inside(message["path"], "a drawing")
        notes: list[str] = []
        made = faces.import_artwork(path, notes)
        said = f"imported {len(made)} components from {path.name}: attach each to the face's points (Attach)"
        if notes:
            said += "; " + "; ".join(notes)
    elif action == "save_to_library":
        written = faces.save_to_library(index(message["index"]), session.folder.name_or_inside(message["library"]),
                                        str(message["name"]),
                                        str(message.get("description", "")))
        said = f"wrote {message['name']} to {written}"
    else:
        raise ValueError(f"unknown face action {action!r}")
    session.set_face(faces.face)
    return said


def _tune(session: StudioSession, message: dict, now: float) -> str | None:
    """One mapping tuner message: open a take, change a rule or a range, pause, save."""
    action = message.get("action")
    if action == "open":
        return show_tuner(session, open_tuner(message, session.neutral, session.folder), now)
    tuner = session.tuner
    if tuner is None:
        raise ValueError("open a take to tune first")
    if action == "motor":
        code = str(message["code"])
        if code not in tuner.describe()["motors"]:
            raise ValueError(f"the mapping does not drive {code!r}")
        session.tune_motor = code
    elif action == "rule":
        tuner.set_rule(str(message["code"]), str(message["field"]), message.get("value"))
    elif action == "range":
        tuner.set_range(str(message["key"]), *(number(message[end], end) for end in ("neutral", "low", "high")))
    elif action in ("pause", "play"):
        session.tune_pause(now, action == "pause")
    elif action == "save_mapping":
        return f"wrote {tuner.save_mapping(session.folder.inside(message['path']))}"
    elif action == "save_profile":
        return f"wrote {tuner.save_profile(session.folder.inside(message['path']))}"
    else:
        raise ValueError(f"unknown tuner action {action!r}")
    return None


def hear(message: dict, sound: Sound | None) -> tuple[Label, ...]:
    """What the open sound says (a ``hear`` message, its words in ``text`` if given): the slow part
    (the phones are recognised), which the server runs off its event loop."""
    if sound is None:
        raise ValueError("open a sound before hearing what it says")
    text = message.get("text")
    return heard_labels(sound, " ".join(str(text).split()) if text and str(text).split() else None)


def show_heard(session: StudioSession, labels: tuple[Label, ...]) -> str:
    """Put what was heard under the staves; returns what the page is told."""
    if session.sound is None:
        raise ValueError("the sound was closed meanwhile")
    session.sound = replace(session.sound, labels=labels)
    words = sum(1 for label in labels if label.row == 0)
    phones = sum(1 for label in labels if label.row == 1)
    shapes = sum(1 for label in labels if label.row == 2)
    said = f"heard {words} words and {phones} phones" if words else f"heard {phones} phones"
    return f"{said}; {shapes} mouth shapes"


def open_tuner(message: dict, neutral: np.ndarray, folder: Folder) -> MappingTuner:
    """The take a tuner ``open`` message names (inside ``folder``), mapped onto a face whose rest
    is ``neutral``: the slow part (a video is tracked first), which the server runs off its event loop."""
    mapping = message.get("mapping")
    return MappingTuner(str(folder.inside(message["take"], "a take")), neutral,
                        folder.name_or_inside(mapping, "a mapping") if mapping else None,
                        str(message.get("units")) if message.get("units") else None)


def show_tuner(session: StudioSession, tuner: MappingTuner, now: float) -> str:
    """Play an opened tuner's take on the face; returns what the page is told."""
    session.tune(tuner, now)
    session.tune_motor = tuner.describe()["motors"][0]
    return f"tuning {tuner.ready.mapping.name} on {tuner.path} ({tuner.duration:.1f} s)"


def _argument(key: str, value: object) -> object:
    """A face action's argument as its method takes it: an index, a name, a number, a list of
    indices (``indices``) or a renaming of control points (``controls``)."""
    if key in ("polygon", "component", "index", "after"):
        return index(value, key)
    if key == "indices":
        if not isinstance(value, list):
            raise TypeError("indices: expected a list of component indices")
        return [index(i, key) for i in value]
    if key == "controls":
        if not isinstance(value, dict):
            raise TypeError('controls: expected an object like {"M": "BLM"}')
        return {str(k): str(v) for k, v in value.items()}
    if key in ("name", "code", "end", "axis", "color", "part", "kind", "master", "library", "use", "point",
               "description", "param", "inputs", "feature"):
        return str(value)
    return number(value, key)


def reason(exc: Exception) -> str:
    """A refused message's one line for the page."""
    if isinstance(exc, KeyError):
        return f"unknown or missing {exc.args[0]!r}"
    return str(exc)


