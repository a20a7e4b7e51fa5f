"""What one studio page works on: a face, its motors, the Animator that moves them (test mode)
and the animation being edited (:mod:`toonface.studio.editor`).

The page is a view (STYLE.md 17): it shows what :meth:`StudioSession.frame` computes with
:mod:`toon` and sends back what the user did; every rule (a slider, a dragged control point,
an expression, a standard motion, the pointer steering the head) is applied here, so that the
same session can be driven from tests without a browser.

Coordinates on the wire are the SVG's (the face's units, y down), as the page's pointer gives
them; :meth:`frame` sends control points the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from player.animator import Animator, schedule
from player.motion import SecondaryMotion
from player.motions import GESTURES, motion_names, standard_motion
from toon import MOTOR_CODES, Face, FaceRig, load_face
from toon.animation import Animation, Knots, simplified_knots
from toon.expressions import Expression, load_expressions
from toon.face import ANGLE_MOTORS
from toon.formulas import head_turn
from toon.motors import MOTORS, STANDARD_EXTRAS, motor_index
from toon.svg import geometry_svg
from toonface.studio.editor import AnimationEditor
from toonface.studio.faces import FaceEditor
from toonface.studio.guard import Folder
from toonface.studio.sound import Sound
from toonface.studio.tuner import MappingTuner

#: The sliders' groups, in the page's order: (title, motor codes).
GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("Brows", ("BRL", "BRC", "BRM", "BLM", "BLC", "BLL")),
    ("Eyelids", ("ERU", "ERL", "ELU", "ELL")),
    ("Gaze", ("PRH", "PRV", "PLH", "PLV")),
    ("Mouth", ("MRH", "MRV", "MLH", "MLV", "MB")),
    ("Head", ("HH", "HV")),
)


class LiveSource(Protocol):
    """A stream of motor values the studio can show (:class:`stream.receiver.StreamReceiver`'s)."""

    name: str

    def values(self) -> np.ndarray:
        """The motors to show now, ``(21,)``."""

    def quality(self) -> dict:
        """The stream's counters for the page's readout."""


#: Seconds a looping expression rests at each end.
LOOP_PAUSE = 0.4
#: A motion inserted into the animation is kept within this of every value it takes (0..1).
INSERT_TOLERANCE = 0.005
#: Seconds a motion inserted may last at most.
INSERT_LONGEST = 10.0


@dataclass(frozen=True)
class Handle:
    """A control point the page lets the user drag: its name and the motors it moves (code, axis)."""

    point: str
    motors: tuple[tuple[str, str], ...]


class StudioSession:
    """One face, shown in test mode, at the animation's cursor, as a stream brings it or as a
    tuned take maps it (:attr:`showing`: ``"test"``, ``"animation"``, ``"live"`` or ``"tune"``).

    Parameters
    ----------
    face : str
        A built-in face's name or a face file.
    loop_time : float
        The Animator's loop, seconds (the page's frame rate while something moves).
    animation : str, optional
        A file for the Animation Editor to open (see :meth:`AnimationEditor.open`).
    folder : Folder, optional
        Where the pages' messages may read and write files; the working folder by default.
    life : bool, optional
        The life layer on a take the editor opens (``studio --life``; None: on for a voice alone).
    """

    def __init__(self, face: str = "classic", loop_time: float = 1 / 30, animation: str | None = None,
                 folder: Folder | None = None, life: bool | None = None) -> None:
        self.folder = folder if folder is not None else Folder.here()
        self.expressions: dict[str, Expression] = load_expressions()
        self.loop_time = loop_time
        self.face_name = face
        self._load(face)
        self.faces = FaceEditor(self.face)  # the face being designed (ToonFace's Editor)
        self.follow = False  # head and gaze follow the pointer
        self.editor = AnimationEditor(self.neutral, declared=self.face.extra_neutral(), life=life)
        if animation is not None:
            self.editor.open(animation)
        self.showing = "test"  # what the face shows (see the class docstring)
        self.sound: Sound | None = None  # under the staves, played with the animation, muxed into renders
        self.live: LiveSource | None = None  # a stream shown as it comes (toonface studio --receive)
        self.tuner: MappingTuner | None = None  # a take mapped again at each tuning of its mapping
        self._tune_start = 0.0  # the server's time at the tuned take's time 0 while it plays
        self._tune_paused: float | None = None  # the take's time where it was paused
        self._now = 0.0  # the server's clock at the last tick
        self.tune_motor = ""  # the motor whose curve the tuner shows
        self.looping: str | None = None  # an expression played to and from neutral until a slider moves
        self._back = False  # the looping expression's next move: back to neutral

    def _load(self, face: str | Face, values: np.ndarray | None = None, extra: dict[str, float] | None = None) -> None:
        """The face and what is made from it, its motors at ``values`` ``(21,)`` (its neutral if
        None) and its parameters beyond the 21 at ``extra``'s where it names them: each animator
        starts there, so no moment shows the new face at rest (the test thread of a page, or a
        frame, reading between two steps of a switch)."""
        self.face = load_face(face) if isinstance(face, str) else face
        self.rig = FaceRig(self.face)
        self.neutral = self.face.neutral()
        self.animator = Animator(self.neutral if values is None else np.clip(values, 0.0, 1.0), self.loop_time)
        rests = {**self.face.extra_neutral(), **(extra or {})}  # the face's parameters beyond the 21
        self.moved = Animator(np.clip([rests[c] for c in self.face.extra_codes], 0.0, 1.0), self.loop_time,
                              self.face.extra_codes)
        self.motion = SecondaryMotion(self.face)  # the face's physics, live: drag the head, the hair swings
        self.handles = tuple(Handle(p, tuple((m.code, m.axis) for m in MOTORS if m.point == p))
                             for p in self.face.points if any(m.point == p for m in MOTORS))

    def set_face(self, face: str | Face) -> None:
        """Show another face (a name or file, which the face editor starts from, or the face
        editor's latest) with the same motor values."""
        self._load(face, self.animator.values(), self.extra_values())
        if isinstance(face, str):
            self.face_name = face
            self.faces = FaceEditor(self.face)
        self.editor.neutral = self.neutral
        self.editor.declared = self.face.extra_neutral()
        if self.tuner is not None:
            self.tuner.retarget(self.neutral)

    @property
    def values(self) -> np.ndarray:
        """The motors the face shows now, ``(21,)``: the Animator's, the animation's at the cursor,
        or the live stream's."""
        if self.showing == "live" and self.live is not None:
            return self.live.values()
        if self.showing == "tune" and self.tuner is not None:
            return self.tuner.values_at(self.tune_time)
        return self.editor.values() if self.showing == "animation" else self.animator.values()

    def extra_values(self) -> dict[str, float]:
        """The face's parameters beyond the 21 shown now, by code: the animation's at the cursor, or
        as moved in test mode (a live stream and a tuned take show them at rest)."""
        if self.showing == "animation":
            return self.editor.extra_values()
        if self.showing in ("live", "tune"):
            return self.face.extra_neutral()
        return {code: float(v) for code, v in zip(self.moved.codes, self.moved.values(), strict=True)}

    def show_live(self, on: bool) -> None:
        """The face shows the live stream (with ``on``), or goes back to test mode from where it was."""
        if on:
            if self.live is None:
                raise ValueError("no stream to show: start the studio with --receive HOST:PORT")
            self.editor.pause()
            self.showing = "live"
        elif self.showing == "live":
            self._test_mode()

    def show_animation(self) -> None:
        """The face shows the animation at the cursor (after an edit, a move of the cursor, play)."""
        self.showing = "animation"

    def _test_mode(self) -> None:
        """The face back in test mode, from where the animation or the stream left it."""
        if self.showing != "test":
            self.editor.pause()
            self.animator.set_values(self.values)
            self.moved.jump(self.extra_values())
            self.showing = "test"

    def set_motor(self, code: str, value: float) -> None:
        """A slider: ``code`` (a motor or a parameter of the face) to ``value`` (clipped to [0, 1])
        at once; what was moving it lets go."""
        self._test_mode()
        self.looping = None
        (self.moved if code in self.moved.codes else self.animator).jump({code: value})

    def drag(self, point: str, x: float, y: float) -> None:
        """A control point dragged to ``(x, y)`` (SVG coordinates): its motors follow within their
        ranges, as in ToonFace's Editor; a turned head is turned back first."""
        handle = next((h for h in self.handles if h.point == point), None)
        if handle is None:
            raise KeyError(f"no control point {point!r} moves a motor")
        self._test_mode()
        values = self.animator.values()
        upright = self.rig.tilted(np.array([[x, -y]]), 1.0 - self.extra_values().get("HT", 0.5))[0]  # tilted back
        fx, fy = self._unturned(upright, values)
        for code, axis in handle.motors:
            lo, hi = self.face.ranges[code]
            if code in ANGLE_MOTORS:  # a pupil: its offset from rest is the eye's radius times sin(angle)
                rest = self.face.points[point][0 if axis == "x" else 1]
                offset = (fx if axis == "x" else fy) - rest
                sine = offset / self.face.eye_radius if self.face.eye_radius > 0 else 0.0
                coordinate = math.degrees(math.asin(min(1.0, max(-1.0, sine))))
            else:
                coordinate = fx if axis == "x" else fy
            if hi != lo:
                self.set_motor(code, (coordinate - lo) / (hi - lo))

    def look(self, x: float, y: float) -> None:
        """The pointer at ``(x, y)`` in [-1, 1] across the face view (x right, y down): with
        :attr:`follow` on, the head turns and the eyes look toward it."""
        if not self.follow:
            return
        self._test_mode()
        right, up = min(1.0, max(-1.0, x)), min(1.0, max(-1.0, -y))
        for code, amount in (("HH", right), ("HV", up), ("PRH", right), ("PLH", right), ("PRV", up), ("PLV", up)):
            rest = float(self.neutral[motor_index(code)])
            reach = (1.0 - rest) if amount > 0 else rest
            self.set_motor(code, rest + amount * reach)

    def play(self, name: str, now: float, loop: bool = False) -> None:
        """An expression or a standard motion (:mod:`player.motions`), started at ``now``; with
        ``loop``, played to and from neutral again and again (a face kept moving while it is edited)
        until a slider, a drag or *Neutral* stops it.

        Raises
        ------
        KeyError
            For a name that is neither.
        """
        self._test_mode()
        self.looping, self._back = (name, True) if loop else (None, False)
        motion = standard_motion(name, None, self.animator.values(), self.neutral, self.expressions,
                                 self.face.extra_neutral())
        for offset, moves in motion.steps:
            schedule((self.animator, self.moved), now + offset, moves)

    def insert_motion(self, name: str) -> str:
        """The expression or standard motion ``name`` into the animation at its cursor, as knots on
        the motors it moves: played by an Animator of this session's loop time from the values
        the animation has there, as test mode would play it, and kept within
        :data:`INSERT_TOLERANCE`. Returns what was done, in a line.

        Raises
        ------
        KeyError
            For a name that is neither.
        """
        editor = self.editor
        at = editor.cursor
        current = np.array([float(editor.animation.value(code, at, self.neutral)) for code in MOTOR_CODES])
        motion = standard_motion(name, None, current, self.neutral, self.expressions, self.face.extra_neutral())
        animator = Animator(current, self.loop_time)
        for offset, moves in motion.steps:
            schedule((animator,), offset, moves)
        rows = [animator.tick(0.0)]
        while animator.busy() and len(rows) * self.loop_time < INSERT_LONGEST:
            rows.append(animator.tick(len(rows) * self.loop_time))
        table = np.array([current, *rows])
        times = np.arange(len(table)) * self.loop_time
        knots: dict[str, Knots] = {}
        for i, code in enumerate(MOTOR_CODES):
            values = table[:, i]
            if np.ptp(values) > 1e-9:
                kept = simplified_knots(times, values, INSERT_TOLERANCE)
                knots[code] = tuple((float(times[k]), float(values[k])) for k in kept)
        if not knots:
            return f"{name} moves nothing from here"
        editor.insert(Animation(knots, float(times[-1])))
        return f"inserted {name} at {at:.2f} s ({times[-1]:.2f} s on {', '.join(knots)})"

    def reset(self) -> None:
        """Every motor back to the face's neutral, every pending move dropped."""
        self._test_mode()
        self.looping = None
        self.animator.set_values(self.neutral)
        rests = self.face.extra_neutral()
        self.moved.set_values(np.array([rests[c] for c in self.moved.codes]))

    def tick(self, now: float) -> bool:
        """One Animator loop (the looping expression's next move started when the last is done) and
        the animation's playback at ``now``; whether anything still moves."""
        if self.looping is not None and self.showing == "test" and not self.animator.busy():
            name = "neutral" if self._back else self.looping
            motion = standard_motion(name, None, self.animator.values(), self.neutral, self.expressions,
                                     self.face.extra_neutral())
            for offset, moves in motion.steps:  # a breath's pause at each end
                schedule((self.animator, self.moved), now + LOOP_PAUSE + offset, moves)
            self._back = not self._back
        self.animator.tick(now)
        self.moved.tick(now)
        self.editor.advance(now)
        self._now = now
        return self.busy()

    def driven(self, rate: float = 30.0) -> dict[str, list[list[float]]]:
        """What the face's physics does to the parameters it moves over the animation, sampled at
        ``rate``: per parameter, ``[[time, value], ...]`` (the staves show it, read-only)."""
        if not self.face.physics or self.editor.animation.duration <= 0:
            return {}
        track = self.editor.animation.sample(rate, self.neutral, self.editor.declared)
        motion = SecondaryMotion(self.face, track)
        table = track.table()
        curves: dict[str, list[list[float]]] = {}
        for k in range(track.frames):
            extra = motion.extra_at(k / rate, track.values[k], track.extra_at(table[k]))
            for param in motion.physics.params if motion.physics is not None else ():
                curves.setdefault(param, []).append([round(k / rate, 4), round(extra[param], 4)])
        return curves

    def clock_to(self, now: float) -> None:
        """The server's clock is at ``now`` (a message came): what changes now swings from now."""
        self._now = max(self._now, now)

    def busy(self) -> bool:
        """Whether the Animator has moves left or an expression loops, the animation is playing, a
        stream is shown or a tuned take plays."""
        tuning = self.showing == "tune" and self._tune_paused is None
        looping = self.looping is not None and self.showing == "test"
        return (self.animator.busy() or self.moved.busy() or self.editor.playing or self.showing == "live" or tuning
                or looping or (self.showing in ("test", "live") and self.motion.moving()))  # physics runs there

    def tune(self, tuner: MappingTuner, now: float) -> None:
        """Show ``tuner``'s take, mapped, playing in a loop from ``now``."""
        self.tuner = tuner
        self.editor.pause()
        self.showing = "tune"
        self._tune_start, self._tune_paused, self._now = now, None, now

    def tune_pause(self, now: float, paused: bool) -> None:
        """Pause the tuned take where it is, or play it on from there."""
        self._now = now
        if paused and self._tune_paused is None:
            self._tune_paused = self.tune_time
        elif not paused and self._tune_paused is not None:
            self._tune_start, self._tune_paused = now - self._tune_paused, None

    @property
    def tune_time(self) -> float:
        """Where in the tuned take the face is, seconds."""
        if self.tuner is None:
            return 0.0
        if self._tune_paused is not None:
            return self._tune_paused
        return (self._now - self._tune_start) % self.tuner.duration

    def frame(self, size: tuple[int, int] = (512, 512)) -> dict:
        """What the page draws now: ``svg`` (the face, as :mod:`toon.svg` exports it), ``values``
        (code to value) and ``points`` (name to SVG coordinates of the draggable control points)."""
        values, extra = self.values, self.extra_values()
        if self.showing in ("test", "live"):  # physics on what moves live (the animation's cursor jumps about)
            extra = self.motion.extra_at(self._now, values, extra)
        points = self.rig.control_points(values, extra)
        names = list(self.face.points)
        at = np.array([points[names.index(h.point)] for h in self.handles])
        turned = self.rig.tilted(self._turned(at, values), extra.get("HT", 0.5))  # where the page draws them
        return {"svg": geometry_svg(self.rig.geometry(values, extra), size), "showing": self.showing,
                "cursor": self.editor.cursor, "playing": self.editor.playing, "tune_time": self.tune_time,
                "values": {**{code: round(float(v), 6) for code, v in zip(MOTOR_CODES, values, strict=True)},
                           **{code: round(v, 6) for code, v in extra.items()}},
                "points": {h.point: [round(float(x), 4), round(float(-y), 4)]
                           for h, (x, y) in zip(self.handles, turned, strict=True)}}

    def describe(self) -> dict:
        """The page's fixed parts: motors (code, the name a designer reads, description, group),
        groups, expressions and motions."""
        names = {m.code: m.name for m in MOTORS} | {code: spec.name for code, spec in STANDARD_EXTRAS.items()}
        descriptions = {m.code: m.description for m in MOTORS}
        descriptions |= {code: STANDARD_EXTRAS[code].description for code in self.face.extra_codes
                         if code in STANDARD_EXTRAS}
        descriptions |= {p.code: p.description for p in self.face.params if p.description}
        groups = [*GROUPS, *([("Parameters", self.face.extra_codes)] if self.face.extra_codes else [])]
        return {"groups": [{"title": title, "motors": [{"code": c, "name": names.get(c) or c,
                                                        "description": descriptions.get(c, c)}
                                                       for c in codes]} for title, codes in groups],
                "expressions": [n for n in motion_names(self.expressions) if n not in GESTURES],
                "motions": list(GESTURES),
                "face": self.face_name, "viewbox": list(self.face.viewbox),
                "live": None if self.live is None else self.live.name}

    def _turned(self, points: np.ndarray, values: np.ndarray) -> np.ndarray:
        yaw, pitch = self.rig.head_degrees(values)
        return head_turn(points, self.face.feature_depth, np.array(self.face.head_pivot), yaw, pitch)

    def _unturned(self, point: np.ndarray, values: np.ndarray) -> tuple[float, float]:
        """The face point that :meth:`_turned` shows at ``point`` (depth: the features')."""
        yaw, pitch = (math.radians(a) for a in self.rig.head_degrees(values))
        px, py = self.face.head_pivot
        depth = self.face.feature_depth
        y = (point[1] - py - depth * math.sin(pitch)) / math.cos(pitch)
        x = (point[0] - px - (-y * math.sin(pitch) + depth * math.cos(pitch)) * math.sin(yaw)) / math.cos(yaw)
        return x + px, y + py
