"""The studio's Animation Editor (CharToon 3.3): an animation being edited, with undo and redo.

Every edit is one of :mod:`toon.animation`'s operations, the ones ``toonface anim`` runs on
files, so the page's staves and the command line give the same knots. The editor adds what an
interactive editor needs around them: a cursor whose time the face shows, a clipboard, playback
of the whole or of a selection (looped or not), and up to :data:`UNDO_LEVELS` levels of undo and
redo.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from common import InputError
from toon import MOTOR_CODES, MotorTrack, load_track, save_track
from toon import animation as an
from toon import animation_file as af
from toon.animation import MAX_DURATION, Animation
from toonface.studio.history import History

#: How many edits can be undone.
UNDO_LEVELS = 200
#: A new animation's length, seconds.
NEW_SECONDS = 5.0
#: How far (of the 0..1 range) knots made from a motor track may stray from its values.
TRACK_TOLERANCE = 0.01


class AnimationEditor:
    """Knots per motor, a cursor, a clipboard, playback and undo.

    Parameters
    ----------
    neutral : ndarray, shape (21,)
        The face's rest pose: a motor without knots rests there, and values scale about it.
    animation : Animation, optional
        What to start from (an empty :data:`NEW_SECONDS` animation by default).
    path : Path, optional
        The file it came from, where :meth:`save` writes unless told otherwise.
    """

    def __init__(self, neutral: np.ndarray, animation: Animation | None = None, path: Path | None = None,
                 declared: dict[str, float] | None = None, life: bool | None = None) -> None:
        self.neutral = np.asarray(neutral, dtype=np.float64)
        #: The life layer on a take opened here (:mod:`mapping.life`; None: on for a voice alone).
        self.life = life
        #: The face's parameters beyond the 21 and their rests: staves the page may edit too.
        self.declared: dict[str, float] = dict(declared or {})
        self.animation = animation if animation is not None else Animation({}, NEW_SECONDS)
        self.path = path
        #: The performer's video the animation was tracked from, shown beside the face in step.
        self.video: Path | None = None
        #: The take behind the knots, where its file left its units or rate unsaid (:func:`asked`):
        #: what was read, for the page to show and ask again; None for anything else.
        self.take: dict | None = None
        self.cursor = 0.0
        self.clipboard: Animation | None = None
        self.history: History[Animation] = History(UNDO_LEVELS)
        self._playing: tuple[float, float, float, bool] | None = None  # (started at, from, to, loop)

    # -- edits (each undoable) -------------------------------------------------------------------
    def _change(self, new: Animation) -> None:
        if new.duration > MAX_DURATION:  # a paste far away or a stretch by 1e6 asked for days of frames
            raise ValueError(f"the animation would last {new.duration:g} s; an animation lasts at most "
                             f"{MAX_DURATION:g} s")
        if new == self.animation:
            return
        self.history.push(self.animation)
        self.animation = new
        self.cursor = min(self.cursor, new.duration)

    def add_knot(self, code: str, time: float, value: float) -> None:
        self._change(an.insert_knot(self.animation, self._code(code), time, value))

    def move_knot(self, code: str, index: int, time: float, value: float) -> None:
        self._change(an.move_knot(self.animation, self._code(code), index, time, value))

    def delete_knot(self, code: str, index: int) -> None:
        self._change(an.delete_knot(self.animation, self._code(code), index))

    def ease_knot(self, code: str, index: int, ease: bool) -> None:
        """The segment from knot ``index`` to the next eased, or linear again (undoable)."""
        self._change(an.set_ease(self.animation, self._code(code), index, ease))

    def cut(self, codes: list[str], start: float, end: float) -> None:
        """Cut the slice of ``codes`` into the clipboard (what follows moves earlier)."""
        edited, clip = an.cut(self.animation, self._codes(codes) or tuple(self.animation.knots),
                              *self._span(start, end))
        self.clipboard = clip
        self._change(edited)

    def copy(self, codes: list[str], start: float, end: float) -> None:
        """Copy the slice of ``codes`` into the clipboard (not an edit: nothing to undo)."""
        self.clipboard = an.copy(self.animation, self._codes(codes) or tuple(self.animation.knots),
                                 *self._span(start, end))

    def paste(self, at: float, onto: list[str] | None = None) -> None:
        """The clipboard at ``at``; ``onto``: the motors receiving the clip's, paired in the motors'
        order (the right brow's lateral, central, medial onto the left's), else the clip's own."""
        if self.clipboard is None:
            raise ValueError("nothing to paste: cut or copy a slice first")
        clip_codes = sorted(self.clipboard.knots, key=an.code_order)
        pairs = None
        if onto:
            targets = sorted(self._codes(onto), key=an.code_order)
            if len(targets) != len(clip_codes):
                raise ValueError(f"the clip holds {len(clip_codes)} motors ({', '.join(clip_codes)}); "
                                 f"choose as many to paste onto, not {len(targets)}")
            pairs = dict(zip(clip_codes, targets, strict=True))
        self._change(an.paste(self.animation, self.clipboard, max(0.0, float(at)), pairs))

    def scale_time(self, codes: list[str], start: float, end: float, factor: float) -> None:
        self._change(an.scale_time(self.animation, self._codes(codes) or None, *self._span(start, end),
                                   float(factor)))

    def scale_value(self, codes: list[str], start: float, end: float, factor: float) -> None:
        self._change(an.scale_value(self.animation, self._codes(codes) or None, *self._span(start, end),
                                    float(factor), self.neutral))

    def flip(self, codes: list[str], start: float, end: float) -> None:
        self._change(an.flip(self.animation, self._codes(codes) or None, *self._span(start, end)))

    def insert(self, clip: Animation) -> None:
        """``clip`` (a motion or an expression as knots) at the cursor, in place of what its motors
        did for its length (:func:`toon.animation.paste`); undoable."""
        self._change(an.paste(self.animation, clip, self.cursor))

    def set_duration(self, seconds: float) -> None:
        """A new length; knots beyond it are dropped (undoable)."""
        seconds = float(seconds)
        if not 0 < seconds <= MAX_DURATION:
            raise ValueError(f"a duration is 0..{MAX_DURATION:g} s, got {seconds:g}")
        knots = {c: tuple(k for k in ks if k[0] <= seconds) for c, ks in self.animation.knots.items()}
        self._change(Animation({c: ks for c, ks in knots.items() if ks}, seconds))

    def undo(self) -> bool:
        """Back one edit; False when there is none."""
        return self._restore(self.history.undo(self.animation))

    def redo(self) -> bool:
        """Forward one undone edit; False when there is none."""
        return self._restore(self.history.redo(self.animation))

    def _restore(self, state: Animation | None) -> bool:
        if state is None:
            return False
        self.animation = state
        self.cursor = min(self.cursor, state.duration)
        return True

    # -- files -------------------------------------------------------------------------------------
    def open(self, path: str, tolerance: float = TRACK_TOLERANCE, units: str | None = None,
             rate: float | None = None, shown: str | None = None) -> str:
        """Edit what ``path`` holds (undo starts afresh): an animation (``.toml``), a motor track
        (``.csv``, ``.npz``) as knots within ``tolerance`` (:func:`toon.animation.from_track`), or
        a take (``.c3d``, ``.trc``, a marker ``.csv`` or ``.npz``; or a talking-head video, its face
        tracked) cleaned and mapped first with the built-in mapping that matches it, read in
        ``units`` and at ``rate`` where given (``toonface map --units --rate``). Returns what was
        opened, in a line.

        A table that does not say its frame rate opens nothing: :attr:`take` then asks for it. One
        that does not say its units opens in those its size suggests, and :attr:`take` says which,
        for the page to offer others. ``shown`` is the path as the page gave it (to open it again).
        """
        from capture.csvfile import MissingRate
        from capture.sources import VIDEO_SUFFIXES

        source = Path(path)
        if source.suffix.lower() == ".toml":
            self.animation, self.path, said = af.load_animation(source), source, f"opened {source}"
            self.video, self.take = None, None
        else:
            try:
                track, what = _track(source, units, rate, self.life)
            except MissingRate as unsaid:
                self.take = {"name": source.name, "path": shown or str(source), "ask": ["rate"], "units": units,
                             "rate": None, "said": unsaid.message}
                return f"{source.name} does not say its frame rate: give it, then Open again"
            self.video = source if source.suffix.lower() in VIDEO_SUFFIXES else None
            self.take = asked(track, source, shown, rate)
            self.animation = an.from_track(track, tolerance)
            self.path = None  # saved as a new .toml, not over the track
            knots = sum(len(k) for k in self.animation.knots.values())
            said = (f"opened {source} ({what}): {knots} knots for {track.frames} frames x 21 motors, "
                    f"within {tolerance:g} of every value")
            if self.take is not None:
                said += f"; read in {self.take['units']} ({self.take['said']})"
        self.history.clear()
        self.cursor = 0.0
        return said

    def save(self, path: str | None = None) -> Path:
        """Write the animation (to ``path``, else where it came from); returns where."""
        target = Path(path) if path else self.path
        if target is None:
            raise InputError("say where to save: a new animation has no file yet")
        if target.suffix.lower() != ".toml":
            raise InputError("an animation is saved as .toml", target)
        self.path = af.save_animation(self.animation, target)
        return self.path

    def sample(self, path: str, rate: float) -> int:
        """The movie script: the animation sampled at ``rate`` into a motor track file; frames."""
        track = self.animation.sample(float(rate), self.neutral, self.declared)
        save_track(track, path)
        return track.frames

    # -- time ------------------------------------------------------------------------------------------
    def set_cursor(self, time: float) -> None:
        self.cursor = float(min(max(time, 0.0), self.animation.duration))

    def play(self, now: float, start: float | None = None, end: float | None = None, loop: bool = False) -> None:
        """Play from the cursor (or ``start``) to ``end`` (the end by default), again and again with ``loop``."""
        first, last = self._span(self.cursor if start is None else start, end)
        if self.cursor < first or self.cursor >= last:
            self.cursor = first
        self._playing = (now - (self.cursor - first), first, last, loop)

    def pause(self) -> None:
        self._playing = None

    @property
    def playing(self) -> bool:
        return self._playing is not None

    def advance(self, now: float) -> None:
        """Move the cursor to where playback is at ``now`` (seconds on the server's clock)."""
        if self._playing is None:
            return
        started, first, last, loop = self._playing
        elapsed = now - started
        span = last - first
        if loop and span > 0:
            self.cursor = first + elapsed % span
        elif elapsed >= span:
            self.cursor, self._playing = last, None
        else:
            self.cursor = first + elapsed

    def values(self) -> np.ndarray:
        """The motors at the cursor, ``(21,)``."""
        return np.array([float(self.animation.value(code, self.cursor, self.neutral)) for code in MOTOR_CODES])

    def extra_values(self) -> dict[str, float]:
        """The face's parameters beyond the 21 at the cursor, by code."""
        return {code: float(self.animation.value(code, self.cursor, declared=self.declared)) for code in self.declared}

    def describe(self) -> dict:
        """What the page's staves show."""
        clip = self.clipboard
        return {"duration": self.animation.duration, "cursor": self.cursor, "playing": self.playing,
                "knots": {code: [list(k) for k in knots] for code, knots in self.animation.knots.items()},
                "neutral": {**{code: float(v) for code, v in zip(MOTOR_CODES, self.neutral, strict=True)},
                            **self.declared},
                **self.history.counts(), "path": str(self.path) if self.path else None,
                "video": self.video.name if self.video else None, "take": self.take,
                "clipboard": None if clip is None else {"duration": clip.duration,
                                                        "motors": sorted(clip.knots, key=an.code_order)}}

    def _code(self, code: str) -> str:
        if code not in MOTOR_CODES and code not in self.declared:
            declared = f"; the face's parameters: {', '.join(self.declared)}" if self.declared else ""
            raise ValueError(f"unknown motor {code!r}{declared}")
        return code

    def _codes(self, codes: list[str] | None) -> tuple[str, ...]:
        return tuple(self._code(str(c)) for c in codes or ())

    def _span(self, start: float | None, end: float | None) -> tuple[float, float]:
        first = 0.0 if start is None else float(start)
        last = self.animation.duration if end is None else float(end)
        if not 0 <= first < last <= self.animation.duration + 1e-9:
            raise ValueError(f"a slice is 0 <= start < end <= {self.animation.duration:g} s, got {first:g}-{last:g}")
        return first, min(last, self.animation.duration)


def asked(track: MotorTrack, source: Path, shown: str | None, rate: float | None) -> dict | None:
    """What the page may ask again about the take ``track`` was mapped from: its units where its
    file did not say them (``from`` assumed, inferred or given), its rate where it was given; None
    for a track, a video or a take whose file said both."""
    units = track.meta.get("report", {}).get("units")
    if not isinstance(units, dict) or (units.get("from") in ("file", None) and rate is None):
        return None
    why = {"assumed": "the file does not say: read as millimetres", "given": "as given",
           "inferred": "the file does not say: inferred from the face's size"}.get(str(units["from"]),
                                                                                 f"as its {units['from']} says")
    ask = (["units"] if units["from"] != "file" else []) + (["rate"] if rate else [])
    return {"name": source.name, "path": shown or str(source), "ask": ask,
            "units": str(units["unit"]), "rate": track.rate, "said": why}


def _track(path: Path, units: str | None = None, rate: float | None = None,
           life: bool | None = None) -> tuple[MotorTrack, str]:
    """A motor track file, or a take (or a talking-head video, tracked) mapped on the fly, with the
    life layer where ``life`` says (as ``map --life``); and which it was. ``units`` and ``rate``
    are a take's where its file does not say them."""
    from capture import load_take
    from capture.csvfile import MissingRate
    from capture.sources import VIDEO_SUFFIXES
    from capture.takefile import load_take_or_video
    from toonface.pipeline import map_onto_face

    if path.suffix.lower() in (".csv", ".npz"):
        try:
            track = load_track(path)
            return track, "a motor track" + (f" with {', '.join(track.extra_codes)}" if track.extra_codes else "")
        except InputError as not_a_track:
            try:
                take = load_take(path, rate=rate, units=units)
            except MissingRate:
                raise
            except InputError:
                raise not_a_track from None
            return map_onto_face(take, life=life), "a take, mapped"
    if path.suffix.lower() in VIDEO_SUFFIXES:
        return map_onto_face(load_take_or_video(path, units), life=life), "a video, its face tracked and mapped"
    return map_onto_face(load_take(path, rate=rate, units=units), life=life), "a take, mapped"



