"""Smoothing filters, each in two forms that agree frame for frame.

Every filter here works on many channels at once and has

``apply(x, t)``
    the whole recording: ``x`` of shape ``(frames, channels)`` (or ``(frames,)``), ``t`` the
    frame times ``(frames,)`` in seconds; returns the filtered array, same shape;
``step(sample, t)``
    one live frame: ``sample`` of shape ``(channels,)``, NaN for "not seen this frame"; returns
    the filtered frame. A NaN channel gives NaN and leaves that channel's state as it was;
``reset()``
    forget the past.

``apply`` returns what feeding the frames to ``step`` one by one returns (the agreement the
tests check). Where a better offline result needs the future (zero-phase Butterworth, a centred
Savitzky-Golay window) it is the separate :meth:`smooth_offline`, which has no live twin.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from types import ModuleType

import numpy as np

from mapping.robust import ROWS_AT_ONCE, as_rows


class Stepwise:
    """``apply`` as a loop over ``step``, for filters whose state depends on every sample.

    Frames are axis 0; ``step`` takes one frame of any shape (``(channels,)`` here,
    ``(markers, dims)`` for the outlier stages). A 1-D ``x`` is one channel.
    """

    def reset(self) -> None:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError

    def apply(self, x: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Filter a whole recording from a fresh state; equal to stepping it frame by frame."""
        arr = np.asarray(x, dtype=np.float64)
        frames = arr[:, None] if arr.ndim == 1 else arr
        self.reset()
        out = np.empty_like(frames)
        for f in range(len(frames)):
            out[f] = self.step(frames[f], float(t[f]))
        self.reset()
        return out.reshape(arr.shape)


#: Channels filtered in one call by :func:`_each_channel`: scipy's forward-backward filter keeps
#: about five copies of what it is given, which for every marker of an hour's take was gigabytes.
CHANNELS_AT_ONCE = 12


def _each_channel(x: np.ndarray, filter_seen: Callable[[np.ndarray], np.ndarray],
                  batched: Callable[[np.ndarray], np.ndarray] | None = None, overwrite: bool = False) -> np.ndarray:
    """``filter_seen`` on each channel's seen samples (NaN dropped, then put back as NaN).

    ``x`` is ``(frames, channels)`` or ``(frames,)``; the result has its shape. ``batched``, if
    given, filters all the channels without NaN at once, given as rows (``(n, frames)``, C order,
    along the last axis: scipy's filters copy and transpose an axis 0 on every pass, which on a
    long take costs more than the filtering) and must equal ``filter_seen`` on each.
    ``overwrite``: the result may be written into ``x`` (the caller no longer needs it: a long
    take's copy saved; each channel is read before it is written).
    """
    arr = np.asarray(x, dtype=np.float64)
    columns = arr[:, None] if arr.ndim == 1 else arr
    whole = np.isfinite(columns).all(axis=0)
    out = columns if overwrite and columns.flags.writeable else np.full_like(columns, np.nan)
    if batched is not None and whole.any():  # complete channels a few at a time (a long take's copies stay small)
        complete = np.flatnonzero(whole)
        for first in range(0, len(complete), CHANNELS_AT_ONCE):
            part = complete[first:first + CHANNELS_AT_ONCE]
            filtered = batched(as_rows(columns, part))
            for lo in range(0, len(columns), ROWS_AT_ONCE):  # back a block of frames at a time, as taken (as_rows)
                out[lo:lo + ROWS_AT_ONCE, part] = filtered[:, lo:lo + ROWS_AT_ONCE].T
    for c in np.flatnonzero(~whole) if batched is not None else range(columns.shape[1]):
        finite = np.isfinite(columns[:, c])
        seen = np.flatnonzero(finite)
        if len(seen):
            out[seen, c] = filter_seen(columns[seen, c])
        out[~finite, c] = np.nan
    return out.reshape(arr.shape)


class OneEuro(Stepwise):
    """The One Euro filter (Casiez, Roussel and Vogel, CHI 2012), per channel.

    A first-order low-pass whose cutoff rises with speed: ``cutoff = min_cutoff + beta * |dx|``,
    where ``dx`` is the low-passed (at ``d_cutoff``) rate of change from the previous filtered
    value to the new sample. Little jitter when still, little lag when moving. The smoothing
    factor for a step of ``te`` seconds is ``1 / (1 + tau / te)`` with ``tau = 1 / (2 pi cutoff)``.
    This reproduces the authors' reference output (``groundTruth.csv``) to 1e-4.

    Parameters
    ----------
    min_cutoff : float
        Hz; lower is smoother when still.
    beta : float
        Speed coefficient; higher is less lag when moving.
    d_cutoff : float
        Hz, for the derivative.
    rate : float
        Frame rate assumed for the very first step (later steps use the timestamps).
    """

    def __init__(self, min_cutoff: float = 1.0, beta: float = 0.0, d_cutoff: float = 1.0, rate: float = 60.0) -> None:
        if min_cutoff <= 0 or d_cutoff <= 0 or beta < 0 or rate <= 0:
            raise ValueError("One Euro needs min_cutoff > 0, d_cutoff > 0, beta >= 0 and rate > 0")
        self.min_cutoff, self.beta, self.d_cutoff, self.rate = min_cutoff, beta, d_cutoff, rate
        self.reset()

    def reset(self) -> None:
        self._x: np.ndarray | None = None  # filtered value per channel (NaN until first seen)
        self._dx: np.ndarray | None = None  # filtered derivative per channel
        self._t: np.ndarray | None = None  # time each channel was last seen

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """Filter one frame ``(channels,)``; NaN channels give NaN and keep their state."""
        x = np.asarray(sample, dtype=np.float64)
        if self._x is None or self._dx is None or self._t is None:
            shape = x.shape
            self._x, self._dx = np.full(shape, np.nan), np.zeros(shape)
            self._t = np.full(shape, np.nan)
        seen = np.isfinite(x)
        first = seen & np.isnan(self._x)
        later = seen & ~first
        out = np.full(x.shape, np.nan)
        if first.any():
            self._x[first], self._dx[first], self._t[first] = x[first], 0.0, t
            out[first] = x[first]
        if later.any():
            dt = t - self._t[later]
            te = np.where(dt > 0, dt, 1.0 / self.rate)
            dx = (x[later] - self._x[later]) / te
            edx = self._dx[later] + _alpha(self.d_cutoff, te) * (dx - self._dx[later])
            cutoff = self.min_cutoff + self.beta * np.abs(edx)
            filtered = self._x[later] + _alpha(cutoff, te) * (x[later] - self._x[later])
            self._dx[later], self._x[later], self._t[later] = edx, filtered, t
            out[later] = filtered
        return out


def _alpha(cutoff: float | np.ndarray, te: np.ndarray) -> np.ndarray:
    tau = 1.0 / (2.0 * math.pi * np.asarray(cutoff))
    return 1.0 / (1.0 + tau / te)


class Butterworth:
    """A low-pass Butterworth filter (second-order sections), per channel.

    ``apply``/``step`` are the causal filter, started at rest on each channel's first value (no
    step from zero). :meth:`smooth_offline` runs it forward and backward (zero phase, no lag)
    for recordings. Assumes a steady frame rate ``rate``; NaN samples pass through as NaN.

    Parameters
    ----------
    cutoff, rate : float
        Hz; the cutoff must be below half the rate.
    order : int
    """

    def __init__(self, cutoff: float = 6.0, rate: float = 60.0, order: int = 2) -> None:
        if not 0 < cutoff < rate / 2:
            raise ValueError(f"the cutoff must be between 0 and half the rate ({rate / 2:g} Hz), got {cutoff:g}")
        self.cutoff, self.rate, self.order = cutoff, rate, order
        self.sos = _signal().butter(order, cutoff, fs=rate, output="sos")
        self._zi_unit = _signal().sosfilt_zi(self.sos)  # (sections, 2): steady state for a unit input
        self.reset()

    def reset(self) -> None:
        self._z: np.ndarray | None = None  # (sections, 2, channels)

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """Filter one frame ``(channels,)``; NaN channels give NaN and keep their state."""
        x = np.asarray(sample, dtype=np.float64)
        seen = np.isfinite(x)
        if self._z is None:
            self._z = np.full((*self._zi_unit.shape, x.size), np.nan)
        fresh = seen & np.isnan(self._z[0, 0])
        self._z[:, :, fresh] = self._zi_unit[:, :, None] * x[fresh]
        out = np.full(x.shape, np.nan)
        if seen.any():
            y, z = _signal().sosfilt(self.sos, x[seen][None, :], axis=0, zi=self._z[:, :, seen])
            out[seen] = y[0]
            self._z[:, :, seen] = z
        return out

    def apply(self, x: np.ndarray, t: np.ndarray | None = None) -> np.ndarray:
        """The causal filter over a recording; equal to stepping it (runs of NaN restart nothing:
        a channel's state waits through them, as in :meth:`step`)."""
        return _each_channel(x, lambda v: _signal().sosfilt(self.sos, v, zi=self._zi_unit * v[0])[0])

    def smooth_offline(self, x: np.ndarray, overwrite: bool = False) -> np.ndarray:
        """Zero-phase (forward-backward) smoothing of each channel's seen samples; NaN stay NaN.

        A channel with too few samples for the filter's padding is left as it is. ``overwrite``:
        the result may be written into ``x`` (no longer needed by the caller).
        """
        pad = 3 * (2 * len(self.sos) + 1)
        return _each_channel(x, lambda v: _signal().sosfiltfilt(self.sos, v) if len(v) > pad else v,
                             lambda v: _signal().sosfiltfilt(self.sos, v) if v.shape[-1] > pad else v, overwrite)


class SavitzkyGolay:
    """Savitzky-Golay smoothing: a least-squares polynomial over a window of samples.

    ``apply``/``step`` fit the trailing ``window`` samples and take the fit at the newest (a
    causal filter: no future needed). :meth:`smooth_offline` centres the window (scipy's
    ``savgol_filter``, zero lag). Until a channel has ``window`` samples, ``step`` returns the
    sample unchanged. NaN samples give NaN and are left out of the window.
    """

    def __init__(self, window: int = 9, order: int = 2) -> None:
        if window < 3 or order >= window:
            raise ValueError(f"need window >= 3 and order < window, got window {window}, order {order}")
        self.window, self.order = window, order
        self._coef = _signal().savgol_coeffs(window, order, pos=window - 1, use="dot")  # (window,)
        self.reset()

    def reset(self) -> None:
        self._buf: np.ndarray | None = None  # (window, channels), newest last
        self._count: np.ndarray | None = None

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """Filter one frame ``(channels,)``; NaN channels give NaN and keep their window."""
        x = np.asarray(sample, dtype=np.float64)
        if self._buf is None or self._count is None:
            self._buf, self._count = np.zeros((self.window, x.size)), np.zeros(x.size, dtype=int)
        seen = np.isfinite(x)
        self._buf[:, seen] = np.roll(self._buf[:, seen], -1, axis=0)
        self._buf[-1, seen] = x[seen]
        self._count[seen] += 1
        out = np.where(seen, x, np.nan)
        full = seen & (self._count >= self.window)
        out[full] = self._coef @ self._buf[:, full]
        return out

    def apply(self, x: np.ndarray, t: np.ndarray | None = None) -> np.ndarray:
        """The causal filter over a recording, equal to stepping it."""
        return _each_channel(x, self._trailing_fit)

    def _trailing_fit(self, values: np.ndarray) -> np.ndarray:
        out = values.copy()
        if len(values) >= self.window:
            out[self.window - 1:] = np.correlate(values, self._coef, mode="valid")
        return out

    def smooth_offline(self, x: np.ndarray) -> np.ndarray:
        """Centred-window smoothing of each channel's seen samples (zero lag); NaN stay NaN.

        A channel shorter than the window is left as it is.
        """
        return _each_channel(x, lambda v: _signal().savgol_filter(v, self.window, self.order, mode="interp")
                             if len(v) >= self.window else v)


class SpeedLimit(Stepwise):
    """Limit how fast each channel may change: at most ``max_speed`` units per second.

    The output moves toward each new sample by no more than ``max_speed * dt``; NaN samples give
    NaN and leave the channel where it was. ``max_speed`` may be one value or one per channel
    (``inf``: no limit).
    """

    def __init__(self, max_speed: float | np.ndarray) -> None:
        if np.any(np.asarray(max_speed) <= 0):
            raise ValueError("max_speed must be > 0 (use inf for no limit)")
        self.max_speed = np.asarray(max_speed, dtype=np.float64)
        self.reset()

    def reset(self) -> None:
        self._y: np.ndarray | None = None
        self._t: np.ndarray | None = None

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(channels,)``."""
        x = np.asarray(sample, dtype=np.float64)
        if self._y is None or self._t is None:
            self._y, self._t = np.full(x.shape, np.nan), np.full(x.shape, np.nan)
        seen = np.isfinite(x)
        allowed = self.max_speed * (t - self._t)
        moved = np.where(np.isfinite(self._y), self._y + np.clip(x - self._y, -allowed, allowed), x)
        self._y = np.where(seen, moved, self._y)
        self._t = np.where(seen, t, self._t)
        return np.where(seen, self._y, np.nan)


class Delay(Stepwise):
    """Delay each channel by whole frames (``frames``: one count or one per channel); the first
    frames repeat the first sample (there is nothing older to show)."""

    def __init__(self, frames: int | np.ndarray) -> None:
        self.frames = np.asarray(frames, dtype=int)
        if np.any(self.frames < 0):
            raise ValueError("delays must be >= 0 frames")
        self.reset()

    def reset(self) -> None:
        self._buf: np.ndarray | None = None  # (depth, channels), newest last
        self._count = 0

    def step(self, sample: np.ndarray, t: float) -> np.ndarray:
        """One frame ``(channels,)``: each channel's sample from ``frames`` frames ago."""
        x = np.asarray(sample, dtype=np.float64)
        depth = int(self.frames.max(initial=0)) + 1
        if self._buf is None:
            self._buf = np.repeat(x[None], depth, axis=0)
        self._buf = np.roll(self._buf, -1, axis=0)
        self._buf[-1] = x
        frames = np.broadcast_to(self.frames, x.shape)
        return self._buf[depth - 1 - frames, np.arange(x.size).reshape(x.shape)]

    def apply(self, x: np.ndarray, t: np.ndarray) -> np.ndarray:
        """Whole recording ``(frames, channels)``; equal to stepping it."""
        arr = np.asarray(x, dtype=np.float64)
        frames = np.broadcast_to(self.frames, arr.shape[1:])
        rows = np.maximum(np.arange(len(arr))[:, None] - frames[None, :], 0)
        return arr[rows, np.arange(arr.shape[1])[None, :]]


def _signal() -> ModuleType:
    """scipy.signal, imported when a filter first needs it: it is a second of start-up."""
    from scipy import signal

    return signal
