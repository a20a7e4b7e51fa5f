"""Live warnings at either end of the motor stream: a trouble said once, within seconds, while
the stream runs (not at exit), and said again to be over once the stream flows.

The sender's trouble is silence: no acknowledgement or keyframe request for
:data:`SILENT_SECONDS` (nobody listens, or the receiver's key differs, so it cannot answer in a
way this end opens). The receiver's is packets that do not open: some came and none was read for
:data:`REFUSED_SECONDS` (another key, or no key at one end).
"""

from __future__ import annotations

from collections.abc import Callable

#: Seconds a sender goes unanswered before it says so (a receiver answers several times a second).
SILENT_SECONDS = 3.0
#: Seconds of packets that do not open, none read, before a receiver says so (a sender's long
#: header comes at least once a second, so a receiver that joins late opens one within it).
REFUSED_SECONDS = 1.5


class Trouble:
    """A condition said once when it has lasted ``after`` seconds and once when it ends.

    Parameters
    ----------
    say : callable
        Takes one line (a warning when trouble starts, a note when it ends).
    after : float
        Seconds the condition lasts before it is said.
    """

    def __init__(self, say: Callable[[str], None], after: float) -> None:
        self.say, self.after = say, after
        self.since: float | None = None  # when the condition began (None: it does not hold)
        self.said = False
        self.times = 0  # how often it was said

    def update(self, holds: bool, now: float, started: str | Callable[[], str], ended: str) -> None:
        """Whether the condition ``holds`` at ``now`` (s); says ``started`` (a line, or what makes
        one) once it has held for :attr:`after` seconds, and ``ended`` once it stops after that."""
        if not holds:
            if self.said:
                self.say(ended)
            self.since, self.said = None, False
            return
        if self.since is None:
            self.since = now
        if not self.said and now - self.since >= self.after:
            self.said = True
            self.times += 1
            self.say(started if isinstance(started, str) else started())
