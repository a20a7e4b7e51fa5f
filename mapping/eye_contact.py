"""Eye contact: the cartoon looks at the viewer when the performer looks at their screen.

A performer on a call looks at the screen, not into the lens; with the camera above the screen
the eyes sit some 10-15 degrees below the lens, and a cartoon that copies them looks past its
viewer's face. A second of calibration ("look at the middle of your screen") measures where the
pupils' motors sit then; from then on that look is the pupils' centre: each pupil motor is
shifted by what it was off its neutral in that second, so the screen reads as the viewer's eyes
and every real look away still moves the pupils as far as it did (a shift, not a squash).

The calibration takes the median of the frames whose lids are open (a blink's held pupils are
not a look; a look down lowers the lids throughout, and still counts). It is refused, with the
reason, where the pupils wandered in it (the middle half of a pupil's values spread over more
than :data:`STEADY`) or too few frames had the eyes open: the previous centre is kept and the
performer can try again. The live mapper (:class:`mapping.stepwise.LiveMapper`) runs it on every
frame, for ``send``, ``play`` and the room's performer page alike.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from toon.motors import motor_index

#: The pupils' motors, in the order of :attr:`LiveEyeContact.offsets`.
PUPILS = ("PRH", "PRV", "PLH", "PLV")
#: The most a pupil motor may wander in the calibration (the middle half of its values, motor
#: units): on the shared talking-face clips, a second of speech (nobody asked to hold a look)
#: spans 0.02-0.13 of the pupils' range under the arkit mapping, and up to 0.33 where the speaker
#: looks about.
STEADY = 0.15
#: A frame's lids count as open above this share of their median in the calibration (a blink
#: falls below it; a look down, which lowers the lids throughout, does not)...
LIDS_OPEN = 0.5
#: ... and the lids of a whole calibration count as shut below this share of the face's neutral.
SHUT = 0.25
#: The least share of the calibration's frames that must have the eyes open.
OPEN_SHARE = 0.5


def screen_look(values: np.ndarray, neutral: np.ndarray) -> tuple[np.ndarray, str | None]:
    """Where the pupils sit while the performer looks at the screen: each pupil motor's offset
    from its neutral ``(4,)`` (by :data:`PUPILS`), from frames of motors ``(n, 21)`` on a face
    whose neutral is ``neutral`` ``(21,)``; and None, or why the frames cannot say (the offsets
    are then zeros)."""
    values = np.asarray(values, dtype=float)
    pupils = [motor_index(code) for code in PUPILS]
    lids = [motor_index(code) for code in ("ERU", "ELU")]
    if values.ndim != 2 or len(values) == 0:
        return np.zeros(len(PUPILS)), "no frames"
    usual = np.maximum(np.nanmedian(values[:, lids], axis=0), SHUT * neutral[lids])  # a look down lowers the lids
    open_ = np.all(values[:, lids] > LIDS_OPEN * usual, axis=1) & np.all(np.isfinite(values[:, pupils]), axis=1)
    if open_.mean() < OPEN_SHARE:
        return np.zeros(len(PUPILS)), f"the eyes were closed or unseen in {100 * (1 - open_.mean()):.0f} % of it"
    seen = values[open_][:, pupils]
    spread = np.percentile(seen, 75, axis=0) - np.percentile(seen, 25, axis=0)
    if spread.max() > STEADY:
        worst = PUPILS[int(spread.argmax())]
        return np.zeros(len(PUPILS)), (f"the eyes moved during it ({worst} spread {spread.max():.2f} of its range, "
                                       f"more than {STEADY:g})")
    return np.median(seen, axis=0) - neutral[pupils], None


class LiveEyeContact:
    """Eye contact on a live stream of motor frames (see the module docstring).

    Parameters
    ----------
    neutral : ndarray, shape (21,)
        The face's neutral motors.
    seconds : float
        How long a calibration collects.
    after : float, optional
        Start a calibration this many seconds after the first frame (None: only on :meth:`begin`).
    say : callable
        Told, in a line, when a calibration begins, is taken, or is refused.
    """

    def __init__(self, neutral: np.ndarray, seconds: float = 1.0, after: float | None = None,
                 say: Callable[[str], None] = lambda _: None) -> None:
        self.neutral = np.asarray(neutral, dtype=float)
        self.seconds, self.after, self.say = seconds, after, say
        #: Each pupil motor's shift ``(4,)`` by :data:`PUPILS` (zeros until a calibration is taken).
        self.offsets = np.zeros(len(PUPILS))
        self.taken = False
        self._first: float | None = None
        self._asked_at: float | None = None
        self._start: float | None = None
        self._frames: list[np.ndarray] = []
        self._columns = [motor_index(code) for code in PUPILS]

    def begin(self, at: float | None = None) -> None:
        """Calibrate from the next frame on, or from the first frame at or after ``at`` seconds
        (the frames' clock). Safe to call from another thread: it only sets a value."""
        self._asked_at = -math.inf if at is None else at

    @property
    def calibrating(self) -> bool:
        """Whether a calibration is collecting frames."""
        return self._start is not None

    def step(self, values: np.ndarray, t: float) -> np.ndarray:
        """One frame's motors ``(21,)`` at ``t`` seconds, the pupils centred on the screen look
        (a copy; the frame as it is until a calibration is taken)."""
        if self._first is None:
            self._first = t
        if self.after is not None and t - self._first >= self.after:
            self.after, self._asked_at = None, t
        if self._asked_at is not None and t >= self._asked_at:
            self._asked_at, self._start, self._frames = None, t, []
            self.say(f"eye contact: look at the middle of your screen for {self.seconds:g} s")
        if self._start is not None:
            self._frames.append(np.asarray(values, dtype=float).copy())
            if t - self._start + 1e-9 >= self.seconds:
                self._finish()
        return self.apply(values)

    def apply(self, values: np.ndarray) -> np.ndarray:
        """Motors ``(..., 21)`` with the pupils shifted by :attr:`offsets` (clipped to 0..1)."""
        out = np.array(values, dtype=float, copy=True)
        if self.taken:
            out[..., self._columns] = np.clip(out[..., self._columns] - self.offsets, 0.0, 1.0)
        return out

    def _finish(self) -> None:
        offsets, why = screen_look(np.array(self._frames), self.neutral)
        self._start, self._frames = None, []
        if why is not None:
            kept = "the last centre kept" if self.taken else "the pupils left as tracked"
            self.say(f"eye contact not taken: {why}; {kept} (try again, looking at one point)")
            return
        self.offsets, self.taken = offsets, True
        h, v = (offsets[0] + offsets[2]) / 2, (offsets[1] + offsets[3]) / 2
        side, height = "right" if h < 0 else "left", "below" if v < 0 else "above"
        self.say(f"eye contact taken: the screen's middle is now the pupils' centre (they sat {abs(v):.2f} "
                 f"{height} it and {abs(h):.2f} to the performer's {side}, in motor units)")
