"""Two clocks compared over a link, as NTP does: one side asks for the other's clock
(``{"clock": ms}``, on its own clock), the other answers with its reading added (``{"clock": ms,
"at": ms}``), and the asking side keeps the answer of the shortest round trip (within a minute) and
takes the other's reading as made halfway through it (within half that trip of the truth).

Used by the room server (:mod:`toonface.room.clocks`: each performer's link and each page) and by a
native viewer's link to it (:class:`stream.websocket.WebSocketLink`), so that a caption or
``receive``'s readout says a face's delay from capture whatever the machines' clocks.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable, Collection, Mapping
from typing import Any

from common.limits import parse_json_message


def clock_reading(text: str | dict, keys: Collection[str]) -> dict | None:
    """``text`` (or its JSON already parsed) as a clock message, finite numbers at exactly ``keys``
    (``clock``, and ``at`` in an answer: :mod:`toonface.room.clocks`), or None where it is none;
    parsed within :mod:`common.limits`' bounds (a deep nest from afar raised RecursionError)."""
    try:
        message = text if isinstance(text, dict) else parse_json_message(text)
    except ValueError:
        return None
    if not isinstance(message, dict) or set(message) != set(keys):
        return None
    if not all(isinstance(message[k], int | float) and not isinstance(message[k], bool)
               and math.isfinite(message[k]) for k in keys):
        return None
    return message


def performer_clocks(data: str | bytes) -> dict[int, float] | None:
    """A room server's ``{"clocks": {stream: ms}}`` (each performer's clock less the server's) as
    seconds by stream id, or None where ``data`` is none; parsed within :mod:`common.limits`' bounds."""
    try:
        message = parse_json_message(data)
    except ValueError:
        return None
    said = message.get("clocks") if isinstance(message, dict) and set(message) == {"clocks"} else None
    if not isinstance(said, dict) or not all(
            k.isdigit() and isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
            for k, v in said.items()):
        return None
    return {int(k): v / 1000 for k, v in said.items()}


def clock_answer(text: str, clock: Callable[[], float]) -> str | None:
    """The answer to an ask of ``clock`` (``{"clock": ms}`` -> ``{"clock": ms, "at": ms}``, its
    reading added), or None where ``text`` is no such ask."""
    asked = clock_reading(text, ("clock",))
    return None if asked is None else json.dumps({"clock": asked["clock"], "at": round(clock() * 1000, 3)})


#: Seconds between the server's asks of a performer's clock (and a page's or viewer's of the server's).
CLOCK_SECONDS = 2.0
#: Seconds an answer of the shortest round trip is kept before a longer one may replace it (two
#: machines' clocks drift apart by some tens of parts in a million: a millisecond a minute).
KEEP_SECONDS = 60.0


class Offsets:
    """Each other end's clock less this one's (seconds), from its answers to :meth:`ask` (see the
    module docstring): the room server's of each performer's link (an owner each), a viewer's link's
    of the server (owner ``"server"``); and (:meth:`told`) the performers of a room's other server
    processes, by stream id.

    Parameters
    ----------
    clock : callable
        This end's clock, seconds.
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
        """``owner``'s clock less this end's (seconds), where it answered."""
        best = self.best.get(owner)
        return None if best is None else best[1]

    def forget(self, owner: Any) -> None:
        """``owner`` left (or, a viewer's server, may keep another clock now: asked afresh)."""
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
        """Take another process's ``{"clocks": {stream: ms}}`` of its performers
        (:func:`performer_clocks`); False where ``data`` is none."""
        said = performer_clocks(data)
        if said is not None:
            self.remote.update(said)
        return said is not None

    def own(self, owner: Any) -> None:
        """``owner``'s stream is stamped on this server's clock (a performer page's)."""
        self.best[owner] = (0.0, 0.0, math.inf)
