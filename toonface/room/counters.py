"""What a room server has been doing, as a line a person reads (``room --stats SECONDS``).

Per room: performers and viewers now, packets relayed and packets a slow viewer missed since the
last line (and in all), and what was refused, by reason; the refusals before any room was known
(a wrong room, another site's page) are the server's own.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from toonface.room.server import Rooms


@dataclass
class Counters:
    """The totals at the last line, so that each line says what changed since."""

    relayed: dict[str, int] = field(default_factory=dict)
    skipped: dict[str, int] = field(default_factory=dict)

    def line(self, rooms: Rooms) -> str:
        """One line for every room of ``rooms`` (see the module docstring), and the totals kept."""
        parts = []
        for name, room in rooms.rooms.items():
            skipped = room.skipped + (room.browsers.skipped if room.browsers is not None else 0)
            new_relayed = room.forwarded - self.relayed.get(name, 0)
            new_skipped = skipped - self.skipped.get(name, 0)
            self.relayed[name], self.skipped[name] = room.forwarded, skipped
            refused = _said(room.refused)
            parts.append(f"{name}: {len(room.performers)} performing, {room.watching()} watching, "
                         f"{new_relayed} packets relayed ({room.forwarded} in all), {new_skipped} missed by slow "
                         f"viewers ({skipped}), refused {refused}")
        return "; ".join(parts) + f"; refused before a room: {_said(rooms.refused)}"


def _said(refused: Counter[str]) -> str:
    total = sum(refused.values())
    return "0" if not total else f"{total} ({', '.join(f'{why} {n}' for why, n in sorted(refused.items()) if n)})"
