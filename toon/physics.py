"""Secondary motion: physics drivers that make hair, hats and beards swing and settle.

A face file's ``physics`` list holds drivers. Each is a damped spring (a pendulum for small
swings) that follows a target made of its inputs, and moves one of the face's parameters
(:mod:`toon.params`), and through it whatever the parameter drives::

    {"name": "beard", "inputs": [{"code": "MB", "gain": 0.8}, {"code": "HH", "of": "velocity", "gain": -0.1}],
     "frequency": 1.4, "damping": 0.25, "output": {"param": "BEARD", "gain": 1.0, "swing": true}}

- ``inputs``: motors or parameters (``code``), their value (``of = "value"``, counted from
  their rest), their velocity (``"velocity"``, units a second) or their acceleration
  (``"acceleration"``), or an earlier driver's output (``driver``: its name; drivers feeding
  drivers make chains), each times its ``gain``. The target ``T`` is their sum. Values change
  linearly between samples, so an acceleration is a kick where a velocity changes, at a
  sample: the spring's speed jumps by ``w^2`` times the gain times the change.
- ``frequency`` (Hz) and ``damping`` (a fraction of critical): the spring ``z`` obeys
  ``z'' = w^2 (T - z) - 2 d w z'`` with ``w = 2 pi frequency``, the standard second-order
  system: a step in ``T`` overshoots by ``exp(-pi d / sqrt(1 - d^2))`` and rings with the period
  ``1 / (frequency sqrt(1 - d^2))``.
- ``output``: the parameter it moves, by ``gain`` times ``z`` (``swing`` false: it follows its
  target, late and overshooting) or times ``z - T`` (``swing`` true: only the swing, what a
  pendulum does about a base that moves), added to the parameter's value (the track's, or its
  rest) and kept within [0, 1].

Gravity is an input like any other (the head's tilt ``HT``, with the gain that keeps a
hanging item plumb); there is no wind.

The drivers of a face make one linear system, ``x' = F x + G w(t)`` (``x``: every spring's
position and speed; ``w``: the inputs' values and velocities). Between two samples of the
inputs their values change linearly (tracks are drawn so) and their velocities are constant,
and the system is integrated *exactly* there with a matrix exponential of the augmented
system: the result depends on neither the frame rate nor the step (no sub-steps to choose),
and a state reached by one path is the state reached by any other.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from scipy.linalg import expm

from toon.validate import ShapeValidator

INPUT_KINDS = ("value", "velocity", "acceleration")


@dataclass(frozen=True)
class DriverInput:
    """One input of a driver: a code's value or velocity, or an earlier driver's output, times a gain."""

    gain: float
    code: str = ""
    of: str = "value"
    driver: str = ""


@dataclass(frozen=True)
class Driver:
    """A damped spring moving parameter ``param`` (see the module docstring)."""

    name: str
    inputs: tuple[DriverInput, ...]
    frequency: float
    damping: float
    param: str
    gain: float = 1.0
    swing: bool = True

    def to_dict(self) -> dict[str, Any]:
        """The driver as written in a face file."""
        inputs = [{"driver": i.driver, "gain": i.gain} if i.driver else
                  {"code": i.code, "gain": i.gain, **({"of": i.of} if i.of != "value" else {})} for i in self.inputs]
        return {"name": self.name, "inputs": inputs, "frequency": self.frequency, "damping": self.damping,
                "output": {"param": self.param, "gain": self.gain, "swing": self.swing}}


def parse_physics(raw: Any, v: ShapeValidator, codes: tuple[str, ...], params: tuple[str, ...]) -> tuple[Driver, ...]:
    """Validate a face file's ``physics`` list: inputs among ``codes`` (the 21 and the face's
    parameters) or earlier drivers, outputs among ``params``; errors name the field."""
    if raw is None:
        return ()
    v.require(isinstance(raw, list), "must be a list of drivers", "physics")
    drivers: list[Driver] = []
    for k, body in enumerate(raw):
        where = f"physics[{k}]"
        v.require(isinstance(body, dict), "must be an object", where)
        v.fields(body, {"name", "inputs", "frequency", "damping", "output"}, where, "a driver")
        name = body.get("name")
        v.require(isinstance(name, str) and bool(name), "a driver needs a name", f"{where}.name")
        v.require(all(d.name != name for d in drivers), f"a second driver named {name!r}", f"{where}.name")
        inputs = body.get("inputs")
        v.require(isinstance(inputs, list) and bool(inputs), "a list of at least one input", f"{where}.inputs")
        parsed = tuple(_input(i, v, f"{where}.inputs[{j}]", codes, [d.name for d in drivers])
                       for j, i in enumerate(inputs))
        output = body.get("output")
        v.require(isinstance(output, dict), "an object naming the parameter it moves", f"{where}.output")
        v.fields(output, {"param", "gain", "swing"}, f"{where}.output", "a driver's output")
        param = output.get("param")
        v.require(param in params, f"expected one of the face's parameters ({', '.join(params) or 'none'}), "
                  f"got {param!r}", f"{where}.output.param")
        drivers.append(Driver(
            name, parsed, v.number(body.get("frequency"), f"{where}.frequency", 0.01, 100.0),
            v.number(body.get("damping"), f"{where}.damping", 0.0, 10.0), str(param),
            v.number(output.get("gain", 1.0), f"{where}.output.gain", -1e6, 1e6),
            v.boolean(output.get("swing", True), f"{where}.output.swing")))
    return tuple(drivers)


def _input(raw: Any, v: ShapeValidator, where: str, codes: tuple[str, ...], earlier: list[str]) -> DriverInput:
    v.require(isinstance(raw, dict), "must be an object", where)
    gain = v.number(raw.get("gain", 1.0), f"{where}.gain", -1e6, 1e6)
    if "driver" in raw:
        v.fields(raw, {"driver", "gain"}, where, "a driver input")
        v.require(raw["driver"] in earlier, f"expected an earlier driver ({', '.join(earlier) or 'none'}), got "
                  f"{raw['driver']!r}", f"{where}.driver")
        return DriverInput(gain, driver=str(raw["driver"]))
    v.fields(raw, {"code", "of", "gain"}, where, "an input")
    code = v.choice(raw.get("code"), codes, f"{where}.code")
    return DriverInput(gain, code=code, of=v.choice(raw.get("of", "value"), INPUT_KINDS, f"{where}.of"))


@dataclass
class Physics:
    """A face's drivers as one linear system, with its state (see the module docstring).

    Parameters
    ----------
    drivers : tuple of Driver
    codes : tuple of str
        The columns of an input row (the 21 motors, then the parameters beyond them).
    rests : ndarray, shape (len(codes),)
        Where each input rests: a value input counts from there.
    """

    drivers: tuple[Driver, ...]
    codes: tuple[str, ...]
    rests: np.ndarray
    _time: float | None = None
    _row: np.ndarray | None = None
    _state: np.ndarray = field(default_factory=lambda: np.zeros(0))
    _cache: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        used = sorted({self.codes.index(i.code) for d in self.drivers for i in d.inputs if i.code})
        self._used = np.array(used, dtype=int)  # the input columns read
        m, n = len(used), len(self.drivers)
        # w = [values of the used columns less their rests (m), their velocities (m)]
        # each driver's target and output as rows over (x (2n), w (2m))
        target = np.zeros((n, 2 * n + 2 * m))
        output = np.zeros((n, 2 * n + 2 * m))
        kick = np.zeros((2 * n, m))  # a change of velocity at a sample: the springs' speeds jump
        names = {d.name: k for k, d in enumerate(self.drivers)}
        for k, d in enumerate(self.drivers):
            for i in d.inputs:
                if i.driver:
                    target[k] += i.gain * output[names[i.driver]]
                elif i.of == "acceleration":
                    kick[2 * k + 1, used.index(self.codes.index(i.code))] += (2 * np.pi * d.frequency) ** 2 * i.gain
                else:
                    column = used.index(self.codes.index(i.code)) + (m if i.of == "velocity" else 0)
                    target[k, 2 * n + column] += i.gain
            output[k] = -target[k] if d.swing else 0.0
            output[k, 2 * k] += 1.0  # z (less T for a swing)
        self._target, self._output, self._kick = target, output, kick
        size = 2 * n + 2 * m + m  # x, w and the values' slope (the velocities' slope is 0)
        a = np.zeros((size, size))
        for k, d in enumerate(self.drivers):
            omega = 2 * np.pi * d.frequency
            a[2 * k, 2 * k + 1] = 1.0
            a[2 * k + 1] = np.concatenate([omega ** 2 * target[k], np.zeros(m)])  # w^2 T ...
            a[2 * k + 1, 2 * k] -= omega ** 2  # ... - w^2 z
            a[2 * k + 1, 2 * k + 1] -= 2 * d.damping * omega  # - 2 d w z'
        a[2 * n:2 * n + m, 2 * n + 2 * m:] = np.eye(m)  # the values change by their slope
        self._a = a

    @property
    def params(self) -> tuple[str, ...]:
        """The parameters the drivers move."""
        return tuple(dict.fromkeys(d.param for d in self.drivers))

    def reset(self) -> None:
        """Forget the state: the next row starts every spring settled at its target."""
        self._time, self._row = None, None

    def advance(self, t: float, row: np.ndarray) -> None:
        """Take the input ``row`` ``(len(codes),)`` at ``t`` seconds (later than the last): the
        state moves there, the inputs having changed linearly since the last row."""
        self._state = self._at(t, row)
        self._time, self._row = float(t), np.asarray(row, dtype=float)[self._used].copy()

    def moving(self, tolerance: float = 1e-3) -> bool:
        """Whether a spring is still away from its target or still moving (at the last row taken), by
        more than ``tolerance`` (a thousandth of a parameter: less than a pixel)."""
        if self._time is None:
            return False
        n = len(self.drivers)
        x, w = self._state[:2 * n], self._state[2 * n:2 * n + 2 * len(self._used)]
        targets = self._target @ np.concatenate([x, w])
        omegas = np.array([2 * np.pi * d.frequency for d in self.drivers])  # a speed as the swing it carries
        return bool(np.any(np.abs(x[0::2] - targets) > tolerance) or np.any(np.abs(x[1::2]) / omegas > tolerance))

    def settle(self) -> None:
        """Every spring at its target and still (the state only: a live view's springs that have
        all but stopped come to rest exactly, so that a still face is drawn as still)."""
        if self._time is None:
            return
        n = len(self.drivers)
        w = self._state[2 * n:2 * n + 2 * len(self._used)]
        x = np.zeros(2 * n)
        for k in range(n):
            x[2 * k] = self._target[k] @ np.concatenate([x, w])
        self._state = np.concatenate([x, self._state[2 * n:]])

    def outputs(self, t: float, row: np.ndarray) -> dict[str, float]:
        """How far each moved parameter is displaced at ``t`` (not before the last row taken)
        for inputs ``row`` there, as if they changed linearly from the last row; the state is
        not moved (a frame drawn between two samples of a track)."""
        x = self._at(t, row)
        out: dict[str, float] = {}
        for k, d in enumerate(self.drivers):
            out[d.param] = out.get(d.param, 0.0) + d.gain * float(self._output[k] @ x[:len(self._output[k])])
        return out

    def _at(self, t: float, row: np.ndarray) -> np.ndarray:
        """The augmented state ``(x, w, slope)`` at ``t`` for the inputs ``row`` there."""
        values = np.asarray(row, dtype=float)[self._used]
        m, n = len(self._used), len(self.drivers)
        rest = self.rests[self._used]
        if self._time is None or self._row is None:  # the first row: every spring at its target, still
            w = np.concatenate([values - rest, np.zeros(m)])
            x = np.zeros(2 * n)
            for k in range(n):
                x[2 * k] = self._target[k] @ np.concatenate([x, w])  # earlier drivers' outputs are set
            return np.concatenate([x, w, np.zeros(m)])
        h = float(t) - self._time
        if h < -1e-9:
            raise ValueError(f"physics goes forward: {t:g} s after {self._time:g} s")
        if h <= 0:  # the same instant (or reached by another sum of steps): the inputs jump, the springs not yet
            return np.concatenate([self._state[:2 * n], values - rest, self._state[2 * n + m:2 * n + 2 * m],
                                   np.zeros(m)])
        slope = (values - self._row) / h
        x = self._state[:2 * n] + self._kick @ (slope - self._state[2 * n + m:2 * n + 2 * m])  # velocities changed
        start = np.concatenate([x, self._row - rest, slope, slope])
        return self._transition(h) @ start

    def _transition(self, h: float) -> np.ndarray:
        key = round(h, 12)
        found = self._cache.get(key)
        if found is None:
            if len(self._cache) > 512:
                self._cache.clear()
            with blas_threads().limit(limits=1, user_api="blas"):  # scipy's BLAS threads otherwise spin on
                found = self._cache[key] = expm(self._a * h)  # after this 8x8 product, a second core's worth
        return found


@lru_cache(maxsize=1)
def blas_threads() -> Any:
    """threadpoolctl's controller of the BLAS libraries loaded (scipy's among them, which
    :func:`scipy.linalg.expm` calls), made once a process: making one looks at every loaded
    library, 3-15 ms, which each render's drivers paid anew (2 % of a 4 s render at 512 px)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def physics_for(drivers: tuple[Driver, ...], codes: tuple[str, ...], rests: Mapping[str, float] | np.ndarray
                ) -> Physics | None:
    """The :class:`Physics` of a face's ``drivers`` over input rows of ``codes`` (None without drivers)."""
    if not drivers:
        return None
    rest = np.asarray([rests[c] for c in codes] if isinstance(rests, Mapping) else rests, dtype=float)
    return Physics(drivers, codes, rest)
