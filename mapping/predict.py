"""Short-horizon prediction of motor tracks: hold, constant velocity, and a sparse motion model.

Used to bridge what is missing for a moment (a lost packet in a stream): at each frame, guess
the value ``horizon`` seconds ahead from the samples so far.

``hold``
    The last value.
``velocity``
    A straight line fitted to the last ``window`` samples, carried forward.
``sindy``
    Per motor, a sparse second-order model ``x'' = f(x, x')`` (a polynomial with few terms,
    found by pysindy's sequentially thresholded least squares on derivatives from pysindy's
    smoothed finite differences), integrated ahead from the same fitted line's value and slope.
    It learns what a line cannot: motions slow down and faces return toward rest. Outside the
    states it was fitted on it is read at the nearest fitted state, and its acceleration is kept
    within the fitted motion's (a polynomial extrapolated far runs away).

:func:`forecast` runs any of them causally over a whole track, for measuring
(``python -m bench predict``).
"""

from __future__ import annotations

import warnings

import numpy as np
import pysindy as ps

METHODS = ("hold", "velocity", "sindy")


class MotionModel:
    """Per-channel sparse second-order dynamics, fitted with pysindy.

    Parameters
    ----------
    degree : int
        Polynomial degree of the library in ``(x, x')``.
    threshold : float
        STLSQ threshold: smaller coefficients are set to zero.
    smoothing : int
        Window (samples) of the Savitzky-Golay smoothing behind the derivatives.
    """

    def __init__(self, degree: int = 2, threshold: float = 0.05, smoothing: int = 9) -> None:
        self.degree, self.threshold, self.smoothing = degree, threshold, smoothing
        self.models_: list[ps.SINDy] = []
        self.bounds_: list[tuple[np.ndarray, np.ndarray, float]] = []  # per channel: state low, high, |x''| max

    def fit(self, values: np.ndarray, times: np.ndarray) -> MotionModel:
        """Fit one model per channel of ``values`` ``(F, C)`` sampled at ``times`` ``(F,)``."""
        dt = float(np.median(np.diff(times)))
        window = self.smoothing if self.smoothing % 2 else self.smoothing + 1
        diff = ps.SmoothedFiniteDifference(smoother_kws={"window_length": window, "polyorder": 3, "axis": 0})
        self.models_, self.bounds_ = [], []
        for column in np.asarray(values, dtype=float).T:
            velocity = diff(column[:, None], dt)
            acceleration = diff(velocity, dt)
            state = np.column_stack([column, velocity[:, 0]])
            model = ps.SINDy(optimizer=ps.STLSQ(threshold=self.threshold, alpha=1e-3),
                             feature_library=ps.PolynomialLibrary(degree=self.degree))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # STLSQ warns when a threshold empties a row
                model.fit(state, t=dt, x_dot=np.column_stack([velocity[:, 0], acceleration[:, 0]]))
            self.models_.append(model)
            self.bounds_.append((state.min(axis=0), state.max(axis=0), float(np.abs(acceleration).max())))
        return self

    def advance(self, position: np.ndarray, velocity: np.ndarray, seconds: float, steps: int = 4) -> np.ndarray:
        """Integrate each channel from ``(position, velocity)`` (both ``(N, C)``) for ``seconds``
        by classical Runge-Kutta; returns the positions ``(N, C)``."""
        out = np.empty_like(position)
        h = seconds / steps
        for c, model in enumerate(self.models_):
            low, high, most = self.bounds_[c]

            def rate(state: np.ndarray, model=model, low=low, high=high, most=most) -> np.ndarray:
                # the model is only trusted on the states it was fitted on: outside them it is read
                # at the nearest such state, and its acceleration never exceeds the fitted motion's
                change = model.predict(np.clip(state, low, high))
                change[:, 0] = state[:, 1]
                change[:, 1] = np.clip(change[:, 1], -most, most)
                return change

            state = np.column_stack([position[:, c], velocity[:, c]])
            with np.errstate(all="ignore"):
                for _ in range(steps):
                    k1 = rate(state)
                    k2 = rate(state + 0.5 * h * k1)
                    k3 = rate(state + 0.5 * h * k2)
                    k4 = rate(state + h * k3)
                    state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            out[:, c] = np.where(np.isfinite(state[:, 0]), state[:, 0], position[:, c])
        return out

    def describe(self) -> list[str]:
        """Each channel's equation for ``x''`` (``x0`` is the value, ``x1`` its rate)."""
        return [model.equations()[1] for model in self.models_]


def trailing_line(values: np.ndarray, times: np.ndarray, window: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """At each frame, the least-squares line through the last ``window`` samples (fewer at the
    start): its value at that frame and its slope per second; both ``(F, C)``."""
    x = np.asarray(values, dtype=float)
    level, slope = x.copy(), np.zeros_like(x)
    for f in range(1, len(x)):
        lo = max(0, f - window + 1)
        t = times[lo:f + 1] - times[f]
        tc = t - t.mean()
        s = (tc[:, None] * x[lo:f + 1]).sum(axis=0) / (tc ** 2).sum()
        slope[f] = s
        level[f] = x[lo:f + 1].mean(axis=0) - s * t.mean()
    return level, slope


def forecast(values: np.ndarray, times: np.ndarray, horizon: float, method: str,
             model: MotionModel | None = None, window: int = 3) -> np.ndarray:
    """Each frame's guess of the value ``horizon`` seconds later, from samples up to that frame.

    Parameters
    ----------
    values : ndarray, shape (F, C)
    times : ndarray, shape (F,)
    horizon : float
        Seconds ahead.
    method : str
        One of :data:`METHODS`; ``sindy`` needs a fitted ``model``.

    Returns
    -------
    ndarray, shape (F, C)
        Clipped to the motors' [0, 1].
    """
    if method == "hold":
        return np.asarray(values, dtype=float).copy()
    level, slope = trailing_line(values, times, window)
    if method == "velocity":
        guess = level + slope * horizon
    elif method == "sindy":
        if model is None or not model.models_:
            raise ValueError("the sindy forecast needs a fitted MotionModel")
        guess = model.advance(level, slope, horizon)
    else:
        raise ValueError(f"unknown method {method!r} (one of {', '.join(METHODS)})")
    return np.clip(guess, 0.0, 1.0)
