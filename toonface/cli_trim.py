"""``--start`` and ``--end``: the part of a take, track or voice a command's output keeps.

One rule for ``render``, ``retarget``, ``map``, ``lipsync`` and ``export web``: the whole input
is read, cleaned, calibrated and heard as it is (its rest and ranges, a voice's words and
pauses, come from all of it), and the output keeps the frames from START (inclusive) to END
(exclusive), its own time starting at 0 there; the sound that goes with it is cut alike.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import click

from toonface.cli_options import FiniteFloat

if TYPE_CHECKING:
    from toon import MotorTrack


@dataclass(frozen=True)
class Trim:
    """The ``--start`` and ``--end`` given (None: the input's own)."""

    start: float | None = None
    end: float | None = None

    @property
    def given(self) -> bool:
        return self.start is not None or self.end is not None

    @property
    def offset(self) -> float:
        """Seconds of the input before the output's first frame."""
        return self.start or 0.0

    def track(self, track: MotorTrack) -> MotorTrack:
        """``track``'s part from START to END (the whole where neither is given)."""
        return track.part(self.start, self.end) if self.given else track

    def said(self) -> str:
        """How the output was cut, for a command's last line ("" where it was not)."""
        if not self.given:
            return ""
        return f", {self.offset:g}-{'the end' if self.end is None else f'{self.end:g} s'} of the input"


def trim_options(fn: Callable) -> Callable:
    """--start and --end, handed to the command as one :class:`Trim` argument named ``trim``."""

    @functools.wraps(fn)
    def command(*args, start: float | None, end: float | None, **kwargs):
        if start is not None and end is not None and end <= start:
            raise click.BadParameter(f"{end:g} s is not after --start {start:g} s", param_hint="--end")
        return fn(*args, trim=Trim(start, end), **kwargs)

    command = click.option("--end", type=FiniteFloat(min=0.0, min_open=True), default=None, metavar="SECONDS",
                           help="Keep the output to before this time of the input [default: its end].")(command)
    return click.option("--start", type=FiniteFloat(min=0.0), default=None, metavar="SECONDS",
                        help="Keep the output from this time of the input on, its own time starting at 0 there "
                             "(the whole input is still read, cleaned and calibrated; a sound is cut alike) "
                             "[default: 0].")(command)
