"""Several performers on one screen: each remote performer on a face of its own, in one picture.

A receiver hears several streams (each with its own stream id, :mod:`stream.wire`); every loop,
:meth:`Ensemble.frame` takes each performer's newest values and how long ago its last packet came
and draws them together (:func:`toon.stage.stage`). Each performer's face is mixed as a single
live face is (:mod:`player.providers`): tracking over an idle face, so a performer whose sender
goes quiet passes to idle after ``lost_after``, and after ``gone_after`` fades out over
``fade_out`` seconds and leaves the picture, without stopping the others; one that comes back
takes a place again. Where the performers sit and on which faces is a ``toonface.performers/1``
file (:func:`load_seats`); by default each newcomer takes the next cell of an even grid, on the
receiver's face. One performer alone, with no seats given, is drawn exactly as a single face.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from common import read_versioned
from common.validate import Validator, at
from player.motion import SecondaryMotion
from player.providers import Mixer, Providers
from toon import Face, FaceRig, Geometry, load_face
from toon.params import DrawnExtras
from toon.stage import grid, stage

log = logging.getLogger(__name__)

FORMAT = "toonface.performers/1"


@dataclass(frozen=True)
class Seat:
    """Where a performer (by stream id) sits: a face and a cell ``(left, top, right, bottom)`` as
    fractions of the picture (top left 0, 0)."""

    stream: int
    face: str
    cell: tuple[float, float, float, float]


def load_seats(path: str | os.PathLike) -> list[Seat]:
    """The seats of a ``toonface.performers/1`` file: ``[[performer]]`` tables with ``id``,
    ``face`` and ``cell``. Errors name the file and the field."""
    doc = read_versioned(path, FORMAT, "performers")
    check = Validator(path)
    check.fields(doc, {"format", "performer"}, "", "a performers file")
    raw = doc.get("performer", [])
    check.require(isinstance(raw, list) and bool(raw), "expected [[performer]] tables", "performer")
    seats = []
    for i, spec in enumerate(raw):
        where = at("performer", i)
        check.fields(spec, {"id", "face", "cell"}, where, "a performer")
        cell = check.numbers(spec.get("cell"), 4, at(where, "cell"))
        check.require(all(0 <= v <= 1 for v in cell) and cell[0] < cell[2] and cell[1] < cell[3],
                      "expected [left, top, right, bottom], fractions of the picture, left < right, top < bottom",
                      at(where, "cell"))
        seats.append(Seat(check.integer(spec.get("id"), at(where, "id"), 0, 0xFFFF),
                          check.text(spec.get("face", "classic"), at(where, "face"), empty=False),
                          tuple(cell)))  # type: ignore[arg-type]
    ids = [s.stream for s in seats]
    check.require(len(ids) == len(set(ids)), "a stream id is seated twice", "performer")
    return seats


@dataclass
class Member:
    """A performer being shown: its face, its mix, its newest values and their age, and its
    parameters beyond the 21 (those its face draws)."""

    stream: int
    rig: FaceRig
    mixer: Mixer
    values: np.ndarray
    age: float = 0.0
    extra: dict[str, float] = field(default_factory=dict)
    drawn: DrawnExtras | None = None
    motion: SecondaryMotion | None = None  # its face's physics, on its own frames


@dataclass
class Ensemble:
    """Performers drawn together on a ``size`` picture (see the module docstring).

    Parameters
    ----------
    face : Face
        The face of a performer with no seat.
    size : (width, height)
    providers : Providers
    seats : list of Seat
        With seats, only seated performers are shown, where and as the seats say; a performer
        with no seat is not drawn (a stage laid out by hand has no cell to spare), and each is
        said once (``say``) and kept in :attr:`hidden`.
    gone_after, fade_out : float
        Seconds of silence before a performer fades out, and how long fading takes.
    say : callable
        Takes a line for each performer that came and has no seat.
    """

    face: Face
    size: tuple[int, int]
    providers: Providers = field(default_factory=Providers)
    seats: list[Seat] = field(default_factory=list)
    gone_after: float = 5.0
    fade_out: float = 1.0
    members: dict[int, Member] = field(default_factory=dict)
    say: Callable[[str], None] = log.warning
    hidden: set[int] = field(default_factory=set)

    def __post_init__(self) -> None:
        self._seats = {seat.stream: seat for seat in self.seats}
        self._faces: dict[str, Face] = {}

    def _member(self, stream: int) -> Member:
        seat = self._seats.get(stream)
        face = self.face
        if seat is not None:
            if seat.face not in self._faces:  # each seated face read once, however often its performer comes back
                self._faces[seat.face] = load_face(seat.face)
            face = self._faces[seat.face]
        member = Member(stream, FaceRig(face), Mixer(face.neutral(), self.providers), face.neutral(),
                        drawn=DrawnExtras(face.extra_codes, face.name, lambda text: log.warning("%s", text)),
                        motion=SecondaryMotion(face) if face.physics else None)
        sure = np.ones(len(member.values))
        member.mixer.tracking = lambda: (member.values, sure, member.age)
        return member

    def frame(self, performers: list[tuple], t: float) -> Geometry | None:
        """The picture at ``t`` of ``performers`` (stream id, newest values ``(21,)``, seconds
        since their last packet, and, where the stream has any, its parameters beyond the 21 by
        code); None when nobody is there to show."""
        for stream, values, age, *more in performers:
            if self._seats and stream not in self._seats:
                if stream not in self.hidden:
                    self.hidden.add(stream)
                    self.say(f"stream {stream} has no seat in the performers file: it is not shown (seat it by its "
                             "id to show it)")
                continue
            if stream not in self.members and age < self.gone_after:
                self.members[stream] = self._member(stream)
            if stream in self.members:
                member = self.members[stream]
                member.values, member.age = values, age
                if more and member.drawn is not None:
                    member.extra = member.drawn.drawn(more[0])
        shown = []
        for stream, member in list(self.members.items()):
            opacity = 1.0 - max(member.age - self.gone_after, 0.0) / self.fade_out if self.fade_out > 0 else \
                float(member.age < self.gone_after)
            if opacity <= 0.0:
                del self.members[stream]  # gone: its place is given up
                continue
            values = member.mixer.step(t)
            extra = member.motion.extra_at(t, values, member.extra) if member.motion is not None else member.extra
            shown.append((member, min(opacity, 1.0), member.rig.geometry(values, extra)))
        if not shown:
            return None
        if len(shown) == 1 and not self._seats and shown[0][1] == 1.0:
            return shown[0][2]  # one performer alone: drawn as a single face
        width, height = self.size
        if self._seats:
            cells = [self._cell(self._seats[member.stream].cell) for member, _, _ in shown]
        else:
            cells = grid(len(shown), width, height)
        return stage([g for _, _, g in shown], cells, width, height, self.face.background,
                     [opacity for _, opacity, _ in shown])

    def _cell(self, fractions: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
        width, height = self.size
        left, top, right, bottom = fractions
        return (left * width, (1 - bottom) * height, right * width, (1 - top) * height)
