"""The receiving end's jitter buffer, loss concealment and recovery.

Frames arrive in packets (:class:`stream.reader.Frames`), late, early or never. The playout
shows the stream ``delay`` seconds behind the sender's clock: each call of :meth:`Playout.values_at`
interpolates the frames around ``now - delay``. The delay adapts to what arrives: it is the 95th
percentile, over the last ``window`` seconds, of how long after its capture each frame was ready
(packetisation and network together), plus ``margin``; it rises at once and falls slowly
(``settle`` seconds). On one machine the two clocks are the same; between machines their offset
is simply part of the delay.

Where a frame is missing when its time comes it is concealed, from the frames before it:

``hold``
    the last value;
``linear``
    the line through the last three frames, carried on with its slope fading (time constant
    ``fade`` seconds): the default, with the lowest error under 10 % loss with bursts on the
    live-mapped synthetic performer and on two real facial takes (``python -m bench stream``);
``sindy``
    a forecaster given by the caller (the mapping's pysindy motion model).

Whatever the method, after ``ease_after`` seconds of loss the face eases to its neutral over
``ease_seconds`` (hold-then-ease). While concealing, and after it until it has caught up with the
stream again, a motor moves toward where it should be by at most the larger of ``max_jump`` of
its range and the fastest step it made itself in the stream lately (a peak that halves in about
2 s) per stream frame: the face never moves faster than it does on its own. A blink missed
while concealing is caught up at the eyelid's own speed, not drawn out over twenty frames.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from stream.reader import Frames
from toon.motors import N_MOTORS, extra_rest

CONCEALMENT = ("hold", "linear", "sindy")
#: A stream whose first frame received lies within this many seconds of its sender's start is
#: recorded from the sender's frame 0 (the frames before it were lost), one joined later from its first frame received.
FROM_START_SECONDS = 2.0
#: Per stream frame, the factor a motor's remembered fastest step decays by (half in ~2.3 s at 60 Hz).
SPEED_DECAY = 0.995
#: A forecaster: (values (k, 21), times (k,), seconds ahead) -> values (21,).
Forecaster = Callable[[np.ndarray, np.ndarray, float], np.ndarray]


@dataclass
class PlayoutStats:
    """What the playout did: output frames by state, the latency of the last 600 outputs
    (seconds, when the sender shares this clock), and the summed RMS error (motor units) of
    concealed output against the ``late_frames`` that came too late to show. Bounded however
    long it runs."""

    live: int = 0
    concealed: int = 0
    recovering: int = 0
    waiting: int = 0
    latencies: deque[float] = field(default_factory=lambda: deque(maxlen=600))
    late_frames: int = 0
    late_error_sum: float = 0.0


class Playout:
    """Jitter buffer and concealment (see the module docstring).

    Parameters
    ----------
    neutral : ndarray, shape (21,)
        The face's neutral (where a long loss eases to, and what shows before the first frame).
    method : str
        One of :data:`CONCEALMENT`; ``sindy`` needs ``forecaster``.
    margin, min_delay, max_delay, window, settle : float
        Seconds (see the module docstring).
    max_jump : float
        Motor units per stream frame while concealing or recovering, where the motor's own
        recent steps were smaller.
    declared : mapping, optional
        The face's own parameters beyond the 21 and their neutrals (:meth:`toon.Face.extra_neutral`):
        where a stream's parameters ease to (a standard one the face lacks: its standard neutral).
    """

    def __init__(self, neutral: np.ndarray, method: str = "linear", forecaster: Forecaster | None = None,
                 margin: float = 0.004, min_delay: float = 0.0, max_delay: float = 0.5, window: float = 2.0,
                 settle: float = 2.0, max_jump: float = 0.05, fade: float = 0.06, ease_after: float = 0.3,
                 ease_seconds: float = 0.5, declared: Mapping[str, float] | None = None) -> None:
        if method not in CONCEALMENT:
            raise ValueError(f"concealment must be one of {', '.join(CONCEALMENT)}, got {method!r}")
        if method == "sindy" and forecaster is None:
            raise ValueError("sindy concealment needs a fitted forecaster")
        self.neutral = np.asarray(neutral, dtype=float)
        self.codes: tuple[str, ...] = ()  # the stream's parameters after the 21 (its frames' last columns)
        self.declared = dict(declared or {})
        self.method, self.forecaster = method, forecaster
        self.margin, self.min_delay, self.max_delay = margin, min_delay, max_delay
        self.window, self.settle, self.max_jump, self.fade = window, settle, max_jump, fade
        self.ease_after, self.ease_seconds = ease_after, ease_seconds
        self.stats = PlayoutStats()
        self.delay: float | None = None  # seconds behind the sender's clock (its offset included)
        self.offset = 0.0  # this clock less the sender's (s), where known (stream.clocks): what latency() takes out
        self._needed = 0.0  # the delay the recent frames need (see _needed_delay)
        self.position = 0.0  # the stream frame (fractional index) shown last
        self.rate = 60.0
        self._frames: dict[int, np.ndarray] = {}
        self._anchor: tuple[int, float] | None = None  # (frame index, its capture time)
        self._transit: deque[tuple[float, float]] = deque()  # (arrival, seconds after capture)
        self._output: np.ndarray | None = None
        self._last_now: float | None = None
        self._concealed: dict[int, np.ndarray] = {}  # what was shown for frames that were missing
        self._behind = False  # concealing or catching up
        self._first = np.iinfo(np.int64).max  # the first frame index received
        self._index = 0  # the frame shown last (the first received, before any is shown)
        self.speed = np.zeros_like(self.neutral)  # each motor's fastest recent step, units per stream frame
        self.shown: Callable[[float, np.ndarray], None] | None = None  # see values_at
        self._told_offset: int | None = None  # a told row's number less its stream frame's (see values_at)
        self._told: int = -1  # the last row told to ``shown``
        self._newest = (-1, 0.0)  # the newest frame index received and its arrival
        self._run = 0  # the sender's run the frames held belong to (see Frames)

    def add(self, frames: Frames) -> None:
        """Take a packet's frames (arrival on the caller's clock)."""
        self.rate = frames.rate
        if frames.codes != self.codes:  # the stream's parameters beyond the 21 came or changed: start anew
            self._carry(frames.codes)
        count = len(frames.values)
        restarted = frames.run != self._run or frames.first < self._anchor[0] - 5 * self.rate if self._anchor else False
        self._run = frames.run
        if restarted:  # a restarted sender
            if self._told_offset is not None:  # its rows go on after the gap, as long as it lasted here
                gap = max(1, int(round((frames.arrival - self._newest[1]) * frames.rate)))
                self._told_offset = max(self._told + 1, self._newest[0] + self._told_offset + gap) - frames.first
            self._newest = (-1, 0.0)
            self._frames.clear()
            self.speed[:] = 0.0
            self._concealed.clear()
            self._transit.clear()
            self._anchor, self.delay, self._first = None, None, frames.first
        if self._anchor is None:
            self._index = frames.first  # nothing shown yet: the stream starts here
        if self._anchor is None or frames.first > self._anchor[0]:
            self._anchor = (frames.first, frames.time_s)
        self._first = min(self._first, frames.first)
        if frames.first + count - 1 > self._newest[0]:
            self._newest = (frames.first + count - 1, frames.arrival)
        for i in range(count):
            index = frames.first + i
            captured = frames.time_s + i / frames.rate
            if i >= frames.filled:  # a frame that fills a hole came late by design, not by the network's jitter
                self._transit.append((frames.arrival, frames.arrival - captured))
            self._note_speed(index, frames.values[i])
            if index in self._concealed:  # too late to show: how wrong was what was shown instead
                self.stats.late_frames += 1
                guessed = self._concealed.pop(index)
                self.stats.late_error_sum += float(np.sqrt(np.mean((guessed - frames.values[i]) ** 2)))
            else:
                self._frames[index] = frames.values[i]
        while self._transit and self._transit[0][0] < frames.arrival - self.window:
            self._transit.popleft()
        if self._transit:  # (a packet of frames that all filled holes says nothing of the network)
            self._needed = self._needed_delay()
            if self.delay is None or self._needed > self.delay:
                self.delay = self._needed
        self._forget()

    def _carry(self, codes: tuple[str, ...]) -> None:
        """Frames from now on carry the parameters ``codes`` after the 21: widen the neutral and
        forget what was held at the old width."""
        self.codes = codes
        self.neutral = np.concatenate([self.neutral[:N_MOTORS], [extra_rest(c, self.declared) for c in codes]])
        self.speed = np.zeros_like(self.neutral)
        self._frames.clear()
        self._concealed.clear()
        self._output = None

    def _note_speed(self, index: int, values: np.ndarray) -> None:
        """Let :attr:`speed` decay by a frame and take in the steps to and from frame ``index``."""
        self.speed *= SPEED_DECAY
        for other in (self._frames.get(index - 1), self._frames.get(index + 1)):
            if other is not None:
                np.maximum(self.speed, np.abs(values - other), out=self.speed)

    def _needed_delay(self) -> float:
        """The delay the recent frames need: the fastest frame's transit (which holds the clocks'
        offset) plus the spread above it up to the 95th percentile, plus the margin, the spread
        bounded by ``min_delay`` and ``max_delay``."""
        transit = np.array([d for _, d in self._transit])
        fastest = float(transit.min())
        spread = float(np.percentile(transit, 95)) - fastest + self.margin
        return fastest + min(max(spread, self.min_delay), self.max_delay)

    def latency(self, offset: float = 0.0) -> float | None:
        """Seconds from a frame's capture to its showing, where this clock less the sender's is
        ``offset`` seconds (0: the same clock, one machine; see :mod:`toonface.room.clocks`; the
        stamps wrap every 2**32 milliseconds); None where that leaves over 10 s (another clock)."""
        if self.delay is None:
            return None
        wrap = 2.0 ** 32 / 1e3
        shown = (self.delay - offset + wrap / 2) % wrap - wrap / 2
        return shown if abs(shown) < 10.0 else None

    def values_at(self, now: float) -> tuple[np.ndarray, str]:
        """The face at ``now`` (caller's clock) and the state: ``live``, ``concealed``,
        ``recovering`` or ``waiting`` (nothing received yet).

        With :attr:`shown` set (``shown(t, values)``), every stream frame the playout passes is
        told once, in order, at its stream time ``t``: the frame as it arrived where it was shown
        live, else what was shown in its place. A recording made so keeps stream time, frame for
        frame, whatever the drawing rate: row k is the sender's frame k when the first frame
        received lies within :data:`FROM_START_SECONDS` of its start (the rows of frames lost
        before it hold what was shown while waiting), else row 0 is the first frame received; a
        restarted sender's frames go on after the rows of the gap, as long as it lasted here.
        """
        if self._anchor is None or self.delay is None:
            self.stats.waiting += 1
            return self.neutral.copy(), "waiting"
        elapsed = 0.0 if self._last_now is None else max(now - self._last_now, 0.0)
        self._settle(elapsed)
        self._last_now = now
        position = self._anchor[0] + (now - self.delay - self._anchor[1]) * self.rate
        self.position = position
        index = self._index = int(np.floor(position))
        if index < self._first:  # the stream's first frame is not due yet
            self.stats.waiting += 1
            return self._frames.get(self._first, self.neutral).copy(), "waiting"
        stream = self._stream_at(index, position - index)
        if stream is not None and not self._behind:
            state, value = "live", stream
        else:
            target = stream if stream is not None else self._conceal(index, position)
            value = self._limited(target, elapsed)
            caught_up = stream is not None and np.abs(value - stream).max() < 1e-6
            self._behind = not caught_up
            state = "live" if caught_up else ("recovering" if stream is not None else "concealed")
            if stream is None:
                self._concealed.setdefault(index, value)
                if len(self._concealed) > 4 * self.rate:  # a stream that stopped adds no frames to forget on
                    self._forget()
        self._output = value
        if self.shown is not None:
            self._tell_shown(index, value, state == "live")
        setattr(self.stats, state, getattr(self.stats, state) + 1)
        latency = self.latency(self.offset)
        if latency is not None:
            self.stats.latencies.append(latency)
        return value.copy(), state

    def _tell_shown(self, index: int, value: np.ndarray, live: bool) -> None:
        """Pass the stream frames up to ``index`` not yet told to :attr:`shown`."""
        assert self.shown is not None
        if self._told_offset is None:
            self._told_offset = 0 if self._first <= FROM_START_SECONDS * self.rate else -self._first
        waiting = self._frames.get(self._first, self.neutral)  # what is shown before the first frame
        for row in range(self._told + 1, index + self._told_offset + 1):
            k = row - self._told_offset
            frame = self._frames.get(k)
            told = waiting if k < self._first else (frame if live and frame is not None else value)
            self.shown(row / self.rate, told)
        self._told = max(self._told, index + self._told_offset)

    def _stream_at(self, index: int, fraction: float) -> np.ndarray | None:
        here = self._frames.get(index)
        if here is None:
            return None
        after = self._frames.get(index + 1)
        return here if after is None else here + (after - here) * fraction

    def _conceal(self, index: int, position: float) -> np.ndarray:
        known = sorted(k for k in self._frames if k < index)[-6:]
        if not known:
            return self._output if self._output is not None else self.neutral.copy()
        last = known[-1]
        gap = (position - last) / self.rate
        values = np.array([self._frames[k] for k in known])
        times = np.array(known, dtype=float) / self.rate
        if self.method == "hold" or len(known) < 2:
            guess = values[-1]
        elif self.method == "linear":
            t = times[-3:] - times[-1]
            slope = np.polyfit(t, values[-3:], 1)[0]
            level = values[-3:].mean(axis=0) - slope * t.mean()
            guess = level + slope * self.fade * (1 - np.exp(-gap / self.fade))
        else:
            assert self.forecaster is not None  # __init__ refuses sindy without one
            guess = values[-1].copy()  # the parameters beyond the 21 hold; the forecaster knows the 21
            guess[:N_MOTORS] = self.forecaster(values[:, :N_MOTORS], times, gap)
        ease = np.clip((gap - self.ease_after) / self.ease_seconds, 0.0, 1.0)
        return np.clip(guess + (self.neutral - guess) * ease, 0.0, 1.0)

    def _limited(self, target: np.ndarray, elapsed: float) -> np.ndarray:
        """Toward ``target`` by at most ``max_jump``, or the motor's own recent fastest step,
        per stream frame."""
        if self._output is None:
            return target
        step = np.maximum(self.speed, self.max_jump) * max(elapsed * self.rate, 1e-9)
        return np.clip(self._output + np.clip(target - self._output, -step, step), 0.0, 1.0)  # motors live in [0, 1]

    def _settle(self, elapsed: float) -> None:
        """Let the delay fall toward what the recent frames need, slowly."""
        if self.delay is not None and self._needed < self.delay:
            self.delay = max(self._needed, self.delay - (self.delay - self._needed) * min(elapsed / self.settle, 1.0))

    def _forget(self) -> None:
        """Drop frames more than 2 s behind the playout or 10 s ahead of it, and concealment
        records behind it (memory stays bounded whatever arrives)."""
        behind, ahead = self._index - int(2 * self.rate), self._index + int(10 * self.rate)
        for k in [k for k in self._frames if not behind <= k <= ahead]:
            del self._frames[k]
        for k in [k for k in self._concealed if k < behind]:
            del self._concealed[k]
