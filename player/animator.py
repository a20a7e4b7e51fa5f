"""ToonFace's Animator scheduler (appendix A1.2.4): moves cut into loop-time slices.

A command moves one or more motors to targets over a duration. Each motor's share is cut into
``ceil(duration / loop_time)`` slices (at least one), each an equal step toward the target; every
loop executes one slice per motor that has any, so motors move independently and in parallel.
A new command for a motor that is still moving replaces its remaining slices, starting from
where the motor is. Worked example (the seed's): from fully open, closing the left eye
(``ELU`` to 0) in 500 ms at a 100 ms loop makes 5 slices of 20 % each; closing both eyes makes
10 slices, two per loop.

Commands may be scheduled for a later time (standard motions are timed sequences of moves); the
loop starts them when its clock reaches their time. :class:`Loop` holds the loop time: it reads
the injected clock, applies what arrived, executes one slice per motor, hands the values on and
waits out the rest of the loop (``perf_counter`` and ``sleep`` live; a frame counter and no wait
offline).
"""

from __future__ import annotations

import heapq
import math
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from toon import MOTOR_CODES, motor_index

#: ToonFace used 100 ms; ours defaults to 40 ms (25 frames per second).
DEFAULT_LOOP_TIME = 0.040


@dataclass(frozen=True)
class Move:
    """Move ``code`` to ``target`` (0..1) over ``seconds``."""

    code: str
    target: float
    seconds: float


class Animator:
    """The motors' values and their pending slices (thread-safe).

    Parameters
    ----------
    start : ndarray, shape (len(codes),)
        Values at the start (a face's neutral).
    loop_time : float
        Seconds per loop: the length of one slice.
    codes : tuple of str
        What it moves: the 21 motors by default, or a face's parameters beyond them (``HT``...).
    """

    def __init__(self, start: np.ndarray, loop_time: float = DEFAULT_LOOP_TIME,
                 codes: tuple[str, ...] = MOTOR_CODES) -> None:
        if loop_time <= 0:
            raise ValueError(f"loop_time must be > 0, got {loop_time}")
        self.loop_time = loop_time
        self.codes = tuple(codes)
        self._index = {code: i for i, code in enumerate(self.codes)}
        self._values = np.array(start, dtype=np.float64, copy=True)
        if self._values.shape != (len(self.codes),):
            raise ValueError(f"expected {len(self.codes)} start values, got shape {self._values.shape}")
        self._steps: list[list[float]] = [[] for _ in self.codes]  # per motor, slices still to run
        self._later: list[tuple[float, int, tuple[Move, ...]]] = []  # (time, order, moves) heap
        self._order = 0
        self._lock = threading.Lock()

    def command(self, moves: Iterable[Move]) -> None:
        """Start ``moves`` now: cut each into slices from the motor's current value.

        A command replaces everything pending for its motors (A1.2.4): their slices, and the
        later steps of a motion already running (a nod's way back must not undo a new HV).
        """
        moves = tuple(moves)
        with self._lock:
            codes = {move.code for move in moves}
            self._later = [(at, order, rest) for at, order, scheduled in self._later
                           if (rest := tuple(m for m in scheduled if m.code not in codes))]
            heapq.heapify(self._later)
            self._start(moves)

    def jump(self, targets: dict[str, float]) -> None:
        """Set these motors (code to value, clipped to [0, 1]) now, dropping what is pending for
        them as a command would; the other motors go on (a slider dragged during a blink)."""
        with self._lock:
            codes = set(targets)
            self._later = [(at, order, rest) for at, order, scheduled in self._later
                           if (rest := tuple(m for m in scheduled if m.code not in codes))]
            heapq.heapify(self._later)
            for code, value in targets.items():
                i = self.index(code)
                self._steps[i] = []
                self._values[i] = min(max(float(value), 0.0), 1.0)

    def schedule(self, at: float, moves: Iterable[Move]) -> None:
        """Start ``moves`` when the loop's clock reaches ``at`` seconds."""
        with self._lock:
            heapq.heappush(self._later, (at, self._order, tuple(moves)))
            self._order += 1

    def set_values(self, values: np.ndarray) -> None:
        """Jump to ``values`` ``(21,)`` now, dropping every pending slice and scheduled move."""
        with self._lock:
            self._values[:] = np.clip(values, 0.0, 1.0)
            self._steps = [[] for _ in self.codes]
            self._later.clear()

    def tick(self, now: float = math.inf) -> np.ndarray:
        """One loop: start the moves due by ``now``, execute one slice per moving motor; returns
        the values ``(21,)`` (a copy)."""
        with self._lock:
            while self._later and self._later[0][0] <= now:
                self._start(heapq.heappop(self._later)[2])
            for i, steps in enumerate(self._steps):
                if steps:
                    self._values[i] = steps.pop(0)
            return self._values.copy()

    def values(self) -> np.ndarray:
        """The current values ``(21,)`` (a copy)."""
        with self._lock:
            return self._values.copy()

    def pending(self, code: str | None = None) -> int:
        """Slices still to run, for one motor or all."""
        with self._lock:
            if code is not None:
                return len(self._steps[self.index(code)])
            return sum(len(s) for s in self._steps)

    def busy(self) -> bool:
        """Whether any slice or scheduled move remains."""
        with self._lock:
            return bool(self._later) or any(self._steps)

    def active(self) -> np.ndarray:
        """Per motor ``(21,)``: whether it has slices to run or a scheduled move."""
        with self._lock:
            out = np.array([bool(steps) for steps in self._steps])
            for _at, _order, moves in self._later:
                for move in moves:
                    out[self.index(move.code)] = True
            return out

    def index(self, code: str) -> int:
        """The column of ``code`` in :meth:`values`; a ``KeyError`` naming it where it moves none."""
        if code not in self._index:
            raise KeyError(f'unknown motor code "{code}" (expected one of {" ".join(self.codes)})')
        return self._index[code]

    def _start(self, moves: tuple[Move, ...]) -> None:
        for move in moves:
            i = self.index(move.code)
            count = max(1, math.ceil(round(move.seconds / self.loop_time, 9)))
            start = self._values[i]
            target = min(max(move.target, 0.0), 1.0)
            self._steps[i] = [start + (target - start) * (k + 1) / count for k in range(count - 1)] + [target]


class Loop:
    """The Animator's main loop with a constant loop time.

    Parameters
    ----------
    animator : Animator
    clock : callable
        Seconds; ``time.perf_counter`` live. Offline, a counter advanced by ``sleep``.
    sleep : callable
        Waits the given seconds; ``time.sleep`` live.

    ToonFace's READ SOCKET INPUT needs no step here: commands are sliced as they arrive, under
    the Animator's lock, so the next loop executes their first slices.

    Loops are due on a fixed grid, ``started + k * loop_time``: ToonFace's PAUSE (LOOP-TIME -
    elapsed) when on time. When drawing takes longer than a loop, the slots already past are
    dropped: their slices still run (motions keep their duration) but no frame is drawn, and
    ``skip`` hears how many, so the outputs keep real time. :attr:`dropped` counts them.
    """

    def __init__(self, animator: Animator, clock: Callable[[], float] = time.perf_counter,
                 sleep: Callable[[float], None] = time.sleep, beside: tuple[Animator, ...] = ()) -> None:
        self.animator, self.clock, self.sleep = animator, clock, sleep
        self.beside = beside  # animators ticked in step with it (a face's parameters beyond the 21)
        self.started = clock()
        self.lateness: list[float] = []  # seconds each drawn loop started after it was due
        self.dropped = 0  # loop slots that passed without a frame
        self.drawn = 0  # loops whose frame was drawn (counted as each one finishes)

    def run(self, loops: int | None, frame: Callable[[np.ndarray, float], None],
            stop: Callable[[], bool] = lambda: False, skip: Callable[[int], None] = lambda _: None) -> int:
        """Run until ``loops`` loop slots have passed (None: until ``stop()``), handing each
        drawn loop's values and its slot's time since the start to ``frame``; returns the loops
        drawn. Slots dropped before a frame are announced by ``skip(count)``."""
        step = self.animator.loop_time
        origin = self.clock() - self.started  # the grid starts now
        slot = 0
        while (loops is None or slot < loops) and not stop():
            late = self.clock() - self.started - (origin + slot * step)
            behind = max(int(late // step), 0)
            if loops is not None:
                behind = min(behind, loops - slot - 1)  # the last slot is drawn
            for _ in range(behind):  # slots already past: their slices run, nothing is drawn
                for other in self.beside:
                    other.tick(origin + slot * step)
                self.animator.tick(origin + slot * step)
                slot += 1
            if behind:
                self.dropped += behind
                skip(behind)
            due = origin + slot * step
            self.lateness.append(max(0.0, self.clock() - self.started - due))
            for other in self.beside:
                other.tick(due)
            frame(self.animator.tick(due), due)
            self.drawn += 1
            slot += 1
            rest = self.started + origin + slot * step - self.clock()
            if rest > 0:
                self.sleep(rest)
        return self.drawn


class FakeClock:
    """A clock for offline runs and tests: ``sleep`` advances it, nothing waits."""

    def __init__(self, start: float = 0.0) -> None:
        self.now = start

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        """Advance the clock by ``seconds``."""
        self.now += max(0.0, seconds)


def schedule(animators: tuple[Animator, ...], at: float, moves: Iterable[Move]) -> None:
    """Start ``moves`` at ``at`` on whichever of ``animators`` moves each code (the 21 motors'
    and a face's parameters' animators); a code none moves is left out."""
    moves = tuple(moves)
    for animator in animators:
        mine = tuple(m for m in moves if m.code in animator.codes)
        if mine:
            animator.schedule(at, mine)


def moves_to(values: np.ndarray, seconds: float, codes: Iterable[str] = MOTOR_CODES) -> tuple[Move, ...]:
    """Moves taking ``codes`` to ``values`` ``(21,)`` over ``seconds``."""
    return tuple(Move(code, float(values[motor_index(code)]), seconds) for code in codes)
