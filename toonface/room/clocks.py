"""The room's clocks: how far each performer's clock is from the server's, so that a page far from
both can say how old the face it shows is.

A stream's packets are stamped on the performer's clock and a page shows them on its own; the
delay it sees is the true one plus the difference of the two clocks, which between machines can be
anything (the captions said "latency –" there). So the server asks each performer's link for its
clock every :data:`CLOCK_SECONDS` (``{"clock": ms}``, answered ``{"clock": ms, "at": ms}``: the
server's reading sent back, and the performer's, on the clock it stamps packets with), and answers
a page's own ``{"clock": ms}`` the same way with its own. Each asking side keeps the answer of the
shortest round trip and takes the other's reading as made halfway through it, as NTP does (within
half that round trip of the truth). The server tells the viewers each performer's clock less its
own (``{"clocks": {stream: ms}}``); a page's caption then says ``delay - (its offset - the
performer's)`` and the server's stage ``delay + the performer's``.

In a room shared by several server processes (:mod:`toonface.room.pubsub`), each process publishes
the offsets of the performers connected to it (``toonface.ROOM.c``), and the others tell their own
viewers and their stages those as well: the processes' clocks are taken as one (processes of one
machine share it; servers of a room on several machines should keep NTP time, which holds them
within milliseconds).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Awaitable, Callable, Collection, Mapping
from typing import Any

from common.limits import parse_json_message
from stream.websocket import clock_answer, clock_reading
from toonface.room.fanout import say_all

#: Seconds between the server's asks of a performer's clock (and a page's of the server's).
CLOCK_SECONDS = 2.0
#: Seconds an answer of the shortest round trip is kept before a longer one may replace it (two
#: machines' clocks drift apart by some tens of parts in a million: a millisecond a minute).
KEEP_SECONDS = 60.0


class Offsets:
    """Each performer connection's clock less this server's (seconds), from its link's answers to
    :meth:`ask` (see the module docstring).

    Parameters
    ----------
    clock : callable
        This server's clock, seconds.
    """

    def __init__(self, clock: Callable[[], float] = time.perf_counter) -> None:
        self.clock = clock
        self.asked: dict[Any, float] = {}
        self.best: dict[Any, tuple[float, float, float]] = {}  # owner: (round trip, offset, when), the shortest trip's
        self.remote: dict[int, float] = {}  # the performers of the room's other processes, by stream id (s)

    def ask(self, owner: Any) -> str | None:
        """An ask for ``owner``'s clock where its last is :data:`CLOCK_SECONDS` old, else None."""
        now = self.clock()
        if now - self.asked.get(owner, -math.inf) < CLOCK_SECONDS:
            return None
        self.asked[owner] = now
        return json.dumps({"clock": round(now * 1000, 3)})

    def heard(self, owner: Any, text: str | dict) -> bool:
        """Take ``owner``'s answer (its text, or that parsed); False where it is none (or answers
        no ask of ours)."""
        said = clock_reading(text, ("clock", "at"))
        now = self.clock()
        if said is None or not 0 <= now - said["clock"] / 1000 <= CLOCK_SECONDS * 30:
            return False
        sent = said["clock"] / 1000
        trip, offset = now - sent, said["at"] / 1000 - (sent + now) / 2
        best = self.best.get(owner)
        if best is None or trip <= best[0] or now - best[2] > KEEP_SECONDS:  # clocks drift: a minute at most
            self.best[owner] = (trip, offset, now)
        return True

    def offset(self, owner: Any) -> float | None:
        """``owner``'s clock less this server's (seconds), where it answered."""
        best = self.best.get(owner)
        return None if best is None else best[1]

    def forget(self, owner: Any) -> None:
        """``owner`` left."""
        self.asked.pop(owner, None)
        self.best.pop(owner, None)

    def by_stream(self, performers: Mapping[int, Any]) -> dict[int, float]:
        """The offsets known of ``performers`` (stream id: its owner, this process's) and of the
        other processes' performers (:meth:`told`), by stream id, seconds."""
        return {**self.remote, **self.local(performers)}

    def local(self, performers: Mapping[int, Any]) -> dict[int, float]:
        """The offsets known of ``performers`` (stream id: its owner) alone, by stream id, seconds."""
        return {stream: self.best[owner][1] for stream, owner in performers.items() if owner in self.best}

    def told(self, data: str | bytes) -> bool:
        """Take another process's ``{"clocks": {stream: ms}}`` of its performers; False where
        ``data`` is none (parsed within :mod:`common.limits`' bounds)."""
        try:
            message = parse_json_message(data)
        except ValueError:
            return False
        said = message.get("clocks") if isinstance(message, dict) and set(message) == {"clocks"} else None
        if not isinstance(said, dict) or not all(
                k.isdigit() and isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                for k, v in said.items()):
            return False
        self.remote.update({int(k): v / 1000 for k, v in said.items()})
        return True

    def own(self, owner: Any) -> None:
        """``owner``'s stream is stamped on this server's clock (a performer page's)."""
        self.best[owner] = (0.0, 0.0, math.inf)


async def clock_text(ws: Any, text: str, role: str, offsets: Offsets, performers: Mapping[int, Any],
                     viewers: Collection[Any], share: Callable[[str], Awaitable[None]] | None = None) -> bool:
    """A text message of a connection (not a performer page's): a performer's link telling its
    clock (the viewers are told the performers' offsets, ms; ``share``, where the room is shared,
    is given those of this process's performers for the others) or a page asking the server's (it
    is answered); False where it is neither."""
    if role == "perform":
        if not offsets.heard(ws, text):
            return False
        await say_all(viewers, _clocks(offsets.by_stream(performers)))
        if share is not None:
            await share(_clocks(offsets.local(performers)))
        return True
    answered = clock_answer(text, offsets.clock)
    if answered is not None:
        await ws.send_str(answered)
    return answered is not None


def _clocks(offsets: Mapping[int, float]) -> str:
    """The viewers' message of ``offsets`` (seconds, by stream id): ``{"clocks": {stream: ms}}``."""
    return json.dumps({"clocks": {stream: round(offset * 1000, 3) for stream, offset in offsets.items()}})
