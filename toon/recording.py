"""Where motor values go, frame by frame: the :class:`MotorSink` interface and the recording.

A motor sink takes frames of the 21 motor values as they are made, live or offline, and is kept
(:meth:`~MotorSink.close`) or dropped (:meth:`~MotorSink.abort`) at the end. The recording
(:class:`MotorRecorder`) writes a ``.csv`` or ``.npz`` track; the stream sender
(:class:`stream.sender.StreamSender`) sends the frames over UDP; ``toonface.outputs`` opens
either from a command-line spec.
"""

from __future__ import annotations

import math
import os
import threading
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Protocol, TextIO

import numpy as np

from common import InputError
from toon.motors import MOTOR_CODES, N_MOTORS, extra_rest
from toon.track import MotorTrack
from toon.track_io import save_track

#: A live recording's partial file is flushed at least this often (seconds of the recording).
FLUSH_SECONDS = 1.0


class MotorSink(Protocol):
    """A consumer of motor frames.

    ``write(t, values, captured, confidence, extra)``: ``t`` the frame's time in seconds on the
    producer's clock (the take's, the source's or the stream's), ``values`` ``(21,)``,
    ``captured`` when its performer data was captured on this machine's ``time.perf_counter``
    clock, where known, each motor's ``confidence`` ``(21,)`` (1 seen, 0 lost), where known, and
    the parameters beyond the 21 by code (``{"HT": 0.6}``), where there are any.
    """

    def write(self, t: float, values: np.ndarray, captured: float | None = None,
              confidence: np.ndarray | None = None, extra: Mapping[str, float] | None = None) -> None: ...
    def close(self) -> None: ...
    def abort(self) -> None: ...


class MotorRecorder:
    """Motor frames into a track file (``.csv`` or ``.npz``), written atomically on :meth:`close`.

    The track has one row per frame slot at ``rate`` from time 0 to the last frame written: a
    slot holds the newest frame at or before it (within half a slot), so slots that went by
    without a frame (a player that fell behind) repeat the frame before them. Values are clipped
    to [0, 1], so that no stray value can cost the recording.

    While it records, each slot is also appended as it is settled to ``NAME.partial.csv`` beside
    the output, flushed every :data:`FLUSH_SECONDS` of the recording: a process killed outright
    (SIGKILL, a power cut to the program) leaves that movie script with all but the last second
    or so. :meth:`close` writes the output and removes it; :meth:`abort` removes it.

    Parameters
    ----------
    path : str or PathLike
        ``.csv`` or ``.npz``; checked at once.
    rate : float
        Frames per second of the track.
    meta : dict, optional
        Goes into the track (``.npz``).
    """

    def __init__(self, path: str | os.PathLike, rate: float, meta: dict | None = None) -> None:
        self.path = Path(path)
        if self.path.suffix.lower() not in (".csv", ".npz"):
            raise InputError(f"unknown motor track format {self.path.suffix!r} (use .csv or .npz)", self.path)
        self.rate, self.meta = rate, dict(meta or {})
        self.written: Path | None = None
        self._times: list[float] = []
        self._values: list[np.ndarray] = []
        self.partial = self.path.with_name(f"{self.path.stem}.partial.csv")
        self._live: TextIO | None = None
        self._slot = 0  # the next slot to append
        self._latest: np.ndarray | None = None
        self._flushed = 0.0
        self.codes: tuple[str, ...] = ()  # the parameters beyond the 21 recorded: the first frame's

    @property
    def frames(self) -> int:
        """Frames written so far."""
        return len(self._times)

    def write(self, t: float, values: np.ndarray, captured: float | None = None,
              confidence: np.ndarray | None = None, extra: Mapping[str, float] | None = None) -> None:
        """Keep one frame ``(21,)`` at ``t`` seconds, and the parameters beyond the 21 its first
        frame had (``extra``; one a later frame lacks at its standard neutral), and append the
        slots it settles."""
        if extra and not self._times:
            self.codes = tuple(extra)
        given = extra or {}
        frame = np.concatenate([np.array(values, dtype=float),
                                [given.get(c, extra_rest(c)) for c in self.codes]])
        self._times.append(float(t))
        self._values.append(frame)
        self._append_settled(float(t), frame)

    def _append_settled(self, t: float, frame: np.ndarray) -> None:
        """Append the slots that ``t`` settles (those more than half a slot before it) to the
        partial file, holding the newest frame before ``t``."""
        if self._live is None:
            self._live = open(self.partial, "w", encoding="utf-8")  # noqa: SIM115 - closed by close/abort
            self._live.write(",".join(("time", *MOTOR_CODES, *self.codes)) + "\n")
        held = frame if self._latest is None else self._latest
        rows = []
        while (self._slot + 0.5) / self.rate < t:
            rows.append(f"{self._slot / self.rate:.6f}," + ",".join(f"{v:.6f}" for v in np.clip(held, 0.0, 1.0)))
            self._slot += 1
        self._latest = frame
        if rows:
            self._live.write("\n".join(rows) + "\n")
            if t - self._flushed >= FLUSH_SECONDS:
                self._live.flush()
                self._flushed = t

    def track(self) -> MotorTrack:
        """The frames so far as a track (see the class docstring); needs at least one frame."""
        times = np.array(self._times)
        slots = np.arange(int(round(times.max() * self.rate)) + 1) / self.rate
        order = np.argsort(times, kind="stable")
        rows = np.searchsorted(times[order], slots + 0.5 / self.rate, side="right") - 1
        values = np.clip(np.array(self._values)[order][np.maximum(rows, 0)], 0.0, 1.0)
        return MotorTrack(values[:, :N_MOTORS], self.rate, meta=self.meta, extra_codes=self.codes,
                          extra=values[:, N_MOTORS:] if self.codes else None)

    def close(self) -> None:
        """Write the track (nothing when no frame came); :attr:`written` is its path. The partial
        file goes once the track is written."""
        if self._times and self.written is None:
            self.written = save_track(self.track(), self.path)
        self._drop_partial()

    def abort(self) -> None:
        """Write nothing."""
        self._times.clear()
        self._values.clear()
        self._drop_partial()

    def _drop_partial(self) -> None:
        if self._live is not None:
            self._live.close()
            self._live = None
            self.partial.unlink(missing_ok=True)


class LatestMotors:
    """A motor sink that keeps only the newest frame, its motors' confidence and when it came
    (on ``clock``), for a loop that draws at its own pace (``play --source``); safe to write
    from one thread and read from another."""

    def __init__(self, neutral: np.ndarray, clock: Callable[[], float] = time.perf_counter) -> None:
        self._lock = threading.Lock()
        self._values = np.array(neutral, dtype=float)
        self._confidence = np.zeros(len(self._values))
        self._at = -math.inf
        self._captured: float | None = None
        self._extra: dict[str, float] = {}
        self.clock = clock
        self.frames = 0

    def write(self, t: float, values: np.ndarray, captured: float | None = None,
              confidence: np.ndarray | None = None, extra: Mapping[str, float] | None = None) -> None:
        """Keep ``values`` ``(21,)`` and ``extra`` as the newest (with full confidence where none
        is given)."""
        with self._lock:
            self._values = np.array(values, dtype=float)
            self._extra = dict(extra or {})
            self._confidence = np.ones(len(self._values)) if confidence is None else np.array(confidence, dtype=float)
            self._at = self.clock()
            self._captured = captured
            self.frames += 1

    def values(self) -> np.ndarray:
        """The newest frame ``(21,)`` (the neutral before any)."""
        with self._lock:
            return self._values.copy()

    def extra(self) -> dict[str, float]:
        """The newest frame's parameters beyond the 21, by code (none before any)."""
        with self._lock:
            return dict(self._extra)

    def newest(self) -> tuple[np.ndarray, np.ndarray, float]:
        """The newest frame ``(21,)``, its confidence ``(21,)`` (0 before any) and the seconds
        since it came."""
        with self._lock:
            return self._values.copy(), self._confidence.copy(), self.clock() - self._at

    def captured(self) -> float | None:
        """When the newest frame was captured, where its writer said (None before any, or where not)."""
        with self._lock:
            return self._captured

    def close(self) -> None:
        """Nothing to keep."""

    def abort(self) -> None:
        """Nothing to drop."""
