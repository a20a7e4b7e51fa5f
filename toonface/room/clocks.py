"""The room's clocks: how far each performer's clock is from the server's, so that a page far from
both can say how old the face it shows is.

A stream's packets are stamped on the performer's clock and a page shows them on its own; the
delay it sees is the true one plus the difference of the two clocks, which between machines can be
anything (the captions said "latency –" there). So the server asks each performer's link for its
clock every :data:`~stream.clocks.CLOCK_SECONDS` (``{"clock": ms}``, answered ``{"clock": ms,
"at": ms}``: the server's reading sent back, and the performer's, on the clock it stamps packets
with; :mod:`stream.clocks`), and answers
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
from collections.abc import Awaitable, Callable, Collection, Mapping
from typing import Any

from stream.clocks import Offsets, clock_answer
from toonface.room.fanout import say_all


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
