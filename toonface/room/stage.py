"""A room's stage for browser viewers: its streams decoded once, on the server, and each
performer's face drawn once a frame for every browser viewer.

A browser has no decoder of the stream's wire and no rig, so the server is the room's one receiver
for its pages: a :class:`~stream.receiver.StreamReceiver` fed the performers' packets (its jitter
buffer and concealment, as ``toonface receive`` has) whose faces are drawn as
:func:`toon.svg.geometry_svg` draws them for the studio (the same SVG; the page shows it with the
studio's own drawing module, ``draw.js``). A drawing is some 20 kB, so a viewer is sent only its
lines that changed since the frame before (a talking mouth: 1.5 to 2 kB deflated), deflated once
for all viewers; a viewer that joins is sent whole drawings, and one that fell behind and skipped
frames the lines that changed since the drawings it last had (:meth:`Stage.since`), so that it
catches up at the cost of one frame.

The stage acknowledges the packets it reads to their performer (a performer seen only by
browsers is still answered). A stream sealed with a key the room does not hold cannot be drawn:
the page is told so.
"""

from __future__ import annotations

import json
import time
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from player.motion import SecondaryMotion
from stream.framing import StreamKey
from stream.playout import Playout
from stream.receiver import StreamReceiver, readout
from toon import MOTOR_CODES, Face, FaceRig
from toon.svg import geometry_svg

#: Frames a second drawn for browser viewers.
VIEW_FPS = 30.0
#: A performer unheard this long leaves the stage.
GONE_SECONDS = 10.0
#: Coordinates' decimals in the drawings (face units).
DECIMALS = 1
#: Jitter margin of the stage's buffers (ms), as ``receive``'s default.
JITTER_MS = 4.0


class _Replies:
    """The stage receiver's "socket": its acknowledgements and keyframe requests go to the
    performer of the stream they name (``sender`` is ``("room", stream id)``)."""

    def __init__(self, reply: Callable[[int, bytes], None]) -> None:
        self.reply = reply

    def sendto(self, data: bytes, sender: tuple[str, int]) -> None:
        self.reply(sender[1], data)

    def getsockname(self) -> tuple[str, int]:
        return ("room", 0)

    def close(self) -> None:
        pass


@dataclass
class _Drawn:
    """One performer's last drawing, as lines."""

    lines: list[str] = field(default_factory=list)
    motion: SecondaryMotion | None = None  # the face's swinging parts, as a native viewer swings them
    quality: dict = field(default_factory=dict)  # its last frame's


class Stage:
    """The room's performers drawn for browser viewers (see the module docstring).

    Parameters
    ----------
    face : Face
        The face every performer is drawn on.
    reply : callable
        ``reply(stream id, bytes)`` sends an acknowledgement or request to that stream's performer.
    key : bytes or StreamKey, optional
        The streams' shared secret, where they are sealed and the room holds it.
    size : (width, height)
        The drawings' size in pixels.
    clock : callable
        Seconds, the clock the performers stamp with on this machine.
    """

    def __init__(self, face: Face, reply: Callable[[int, bytes], None], key: bytes | StreamKey | None = None,
                 size: tuple[int, int] = (512, 512), clock: Callable[[], float] = time.perf_counter) -> None:
        self.rig = FaceRig(face)
        neutral = face.neutral()
        self.keyed = key is not None
        self.receiver = StreamReceiver(("room", 0), self._playout(neutral), key, clock=clock,
                                       more=lambda: self._playout(neutral), link=_Replies(reply))
        self.size, self.clock = size, clock
        self.drawn: dict[int, _Drawn] = {}
        self.said: str | None = None  # the last frame's
        #: Each performer's clock less this server's (s), where its link told it (toonface.room.clocks).
        self.offsets: dict[int, float] = {}

    @staticmethod
    def _playout(neutral: Any) -> Playout:
        return Playout(neutral, "linear", margin=JITTER_MS / 1000)

    def feed(self, datagram: bytes, stream: int) -> None:
        """A performer's packet, as it came."""
        self.receiver.feed(datagram, ("room", stream))

    def frame(self) -> tuple[dict, dict]:
        """This frame for the viewers who had the last (only the lines that changed) and for those
        who did not (whole drawings): two messages ``{"type": "stage", "performers": [...],
        "gone": [...]}``, each performer ``{"id", "lines": {index: line}}`` or ``{"id", "svg"}``,
        with its ``quality`` (:func:`stream.receiver.readout`, and ``values``: the motors and
        parameters drawn, by code), and ``said``, a line where packets do not open."""
        now = self.clock()
        changed, whole = [], []
        here = set()
        stats = self.receiver.counters_by_stream()
        for stream, values, silent, extra in self.receiver.performers(now):
            if silent > GONE_SECONDS:
                continue
            here.add(stream)
            face = self.rig.face
            drawn = self.drawn.setdefault(stream, _Drawn(motion=SecondaryMotion(face) if face.physics else None))
            extra = {code: value for code, value in extra.items() if code in face.extra_codes}
            if drawn.motion is not None:
                extra = drawn.motion.extra_at(now, values, extra)
            svg = geometry_svg(self.rig.geometry(values, extra), self.size, DECIMALS)
            lines = svg.split("\n")
            quality = {**readout(stats[stream]), "values": {**{c: round(float(v), 4) for c, v in zip(
                MOTOR_CODES, values, strict=True)}, **{c: round(float(v), 4) for c, v in extra.items()}}}
            if stream in self.offsets:  # its stamps' clock is known: the delay from capture, whatever the clocks
                latency = self.receiver.lanes[stream].playout.latency(-self.offsets[stream])
                quality["latency_ms"] = None if latency is None else round(latency * 1000, 1)
            changed.append(_patch(stream, drawn.lines, lines, quality))
            whole.append({"id": stream, "svg": svg, "quality": quality})
            drawn.lines, drawn.quality = lines, quality
        gone = sorted(set(self.drawn) - here)
        for stream in gone:
            del self.drawn[stream]
        said = self.receiver.diagnosis()
        if said is not None and not self.keyed:  # the room server is what needs the key here, not the page
            said = said.split(":")[0] + (": the room server holds no key to draw it with: start it with --key-file "
                                         "(the sender's), or open the page without ?draw=server, with the &key= that "
                                         "send prints (the page then opens the stream itself)")
        self.said = said
        return ({"type": "stage", "performers": changed, "gone": gone, "said": said},
                {"type": "stage", "performers": whole, "gone": gone, "said": said, "whole": True})

    def lines(self) -> dict[int, list[str]]:
        """The drawings of the last frame, as lines by stream (what a viewer sent it has)."""
        return {stream: drawn.lines for stream, drawn in self.drawn.items()}

    def since(self, had: dict[int, list[str]]) -> dict:
        """The last frame for a viewer whose page has the drawings ``had`` (:meth:`lines` of the
        frame it was last sent): the lines that changed since, whole drawings of performers it
        lacks, and those it has that are gone; as :meth:`frame`'s messages."""
        performers = [_patch(stream, had.get(stream, []), drawn.lines, drawn.quality)
                      for stream, drawn in self.drawn.items()]
        return {"type": "stage", "performers": performers, "gone": sorted(set(had) - set(self.drawn)),
                "said": self.said}

    def close(self) -> None:
        """Release the receiver."""
        self.receiver.close()


def _patch(stream: int, old: list[str], lines: list[str], quality: dict) -> dict:
    """A performer's drawing ``lines`` for a page that has ``old``: the lines that changed (by
    index), or the whole drawing where the two differ in length (none: a newcomer)."""
    if old and len(old) == len(lines):
        return {"id": stream, "lines": {i: line for i, (was, line) in enumerate(zip(old, lines, strict=True))
                                        if was != line}, "quality": quality}
    return {"id": stream, "svg": "\n".join(lines), "quality": quality}


def packed(message: dict) -> bytes:
    """A stage message as the page reads it: JSON, deflated (zlib; the page's
    ``DecompressionStream("deflate")``)."""
    return zlib.compress(json.dumps(message, separators=(",", ":")).encode(), 6)
