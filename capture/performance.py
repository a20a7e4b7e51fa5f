"""What the synthetic performer does: a script of timed cues, turned into the 21 motor values.

A :class:`Performance` is a length and a list of :class:`Cue`. Each cue acts over
``[start, start + seconds)``:

``expression``
    Blend toward a pose from the expression repertoire (``data/expressions.toml``: CharToon's
    six basic expressions, blink, wink) by ``strength``, easing in and out.
``blink`` / ``wink``
    A quick close of both eyes / of the left eye (the repertoire's ``blink`` and ``wink`` poses).
``gaze``
    Both pupils to ``x`` (toward the performer's left, -1..1) and ``y`` (up, -1..1).
``talk``
    The jaw opens and closes at syllable rate (about 4 Hz, seeded variation), the corners
    drawn in a little.
``turn``
    The head turns ``yaw`` degrees toward the performer's left and ``pitch`` degrees chin up
    (each within ±30°, the head motors' range), and back.
``calibrate``
    A calibration segment: a neutral hold of ``hold`` seconds, then each motor group
    (:data:`CALIBRATION_GROUPS`: symmetric pairs together, they drive different markers) in turn
    to its minimum, its maximum and back, ``step`` seconds per group. Overrides every other cue
    while it lasts.

Cues are applied in that order (later kinds win where they overlap), then values are clipped to
[0, 1]. A performance is read from TOML (``format = "toonface.performance/1"``, one ``[[cue]]``
table per cue) or made by :func:`default_performance`.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np

from common import InputError, data_path, read_document, read_versioned
from common.validate import Validator, at

FORMAT = "toonface.performance/1"
KINDS = ("expression", "blink", "wink", "gaze", "talk", "turn", "calibrate")
#: The motor codes in ToonFace order, with the performer's neutral value of each.
NEUTRAL: dict[str, float] = {
    "BRL": 0.4, "BRC": 0.4, "BRM": 0.4, "BLL": 0.4, "BLC": 0.4, "BLM": 0.4,
    "ERU": 0.8, "ERL": 0.2, "ELU": 0.8, "ELL": 0.2,
    "PLH": 0.5, "PLV": 0.5, "PRH": 0.5, "PRV": 0.5,
    "MLH": 0.35, "MLV": 0.5, "MRH": 0.35, "MRV": 0.5, "MB": 0.1,
    "HH": 0.5, "HV": 0.5,
}
CODES: tuple[str, ...] = tuple(NEUTRAL)
HEAD_RANGE_DEG = 60.0  # full 0..1 travel of HH and HV: ±30°
CALIBRATION_GROUPS: tuple[tuple[str, ...], ...] = (
    ("BRM", "BLM"), ("BRC", "BLC"), ("BRL", "BLL"), ("ERU", "ELU"), ("ERL", "ELL"), ("PRH", "PLH"),
    ("PRV", "PLV"), ("MRH", "MLH"), ("MRV", "MLV"), ("MB",), ("HH",), ("HV",),
)
#: Within one calibration step (fraction of ``step``): neutral, minimum held, maximum held, neutral.
_CALIBRATION_KEYS = ((0.0, 0.2, 0.35, 0.6, 0.75, 1.0), ("n", 0.0, 0.0, 1.0, 1.0, "n"))
_FIELDS = {"kind", "start", "seconds", "name", "strength", "x", "y", "yaw", "pitch", "hold", "step"}
_DEFAULT_SECONDS = {"blink": 0.2, "wink": 0.5}


@dataclass(frozen=True)
class Cue:
    """One timed action of the performer (see the module docstring for the kinds)."""

    kind: str
    start: float
    seconds: float = 1.0
    name: str = ""
    strength: float = 1.0
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    pitch: float = 0.0
    hold: float = 1.0
    step: float = 1.2

    @property
    def end(self) -> float:
        """When the cue is over, seconds."""
        if self.kind == "calibrate":
            return self.start + self.hold + self.step * len(CALIBRATION_GROUPS)
        return self.start + self.seconds


@dataclass(frozen=True)
class Performance:
    """A script: ``seconds`` long, ``cues`` in any order; ``seed`` varies the talking rhythm."""

    seconds: float
    cues: tuple[Cue, ...] = field(default_factory=tuple)
    seed: int = 0


#: The expressions the generated performance acts in turn, unless told others.
DEFAULT_EXPRESSIONS = ("happiness", "surprise", "sadness", "anger", "fear", "disgust", "wink")


def default_performance(seconds: float = 10.0, expressions: tuple[str, ...] | None = None,
                        calibration: bool = False, max_turn_deg: float = 30.0, seed: int = 0) -> Performance:
    """A varied performance: neutral first second, then expressions, talking, blinks, gaze and turns.

    Parameters
    ----------
    seconds : float
        Length of the content after the calibration segment (if any).
    expressions : tuple of str, optional
        Repertoire names to act in turn, cycling; default happiness, surprise, sadness, anger,
        fear, disgust and wink, with a talking turn after every second one.
    calibration : bool
        Start with the calibration segment (1 s neutral, then every motor group to its extremes).
    max_turn_deg : float
        Largest head yaw, degrees (at most 30); pitch goes to a third of it.
    seed : int
        Seeds where blinks, gaze shifts and turns fall, and the talking rhythm.
    """
    if not 0.0 <= max_turn_deg <= HEAD_RANGE_DEG / 2:
        raise InputError(f"max turn must be 0-{HEAD_RANGE_DEG / 2:g} degrees, got {max_turn_deg:g}")
    names = expressions if expressions is not None else DEFAULT_EXPRESSIONS
    rng = np.random.default_rng(seed)
    cues: list[Cue] = []
    start = 0.0
    if calibration:
        cues.append(Cue("calibrate", 0.0, hold=1.0))
        start = cues[0].end
    end = start + seconds
    t, slot = start + 1.0, 0  # the first second is neutral
    acts = [n for i, name in enumerate(names) for n in ([name, "talk"] if i % 2 else [name])] or ["talk"]
    while t < end - 0.5:
        act = acts[slot % len(acts)]
        length = min(2.0 if act == "talk" else 1.8, end - t)
        cues.append(Cue("talk", t, length) if act == "talk" else Cue("expression", t, length, name=act))
        t, slot = t + length + 0.4, slot + 1
    t = start + 1.0 + rng.uniform(0.5, 1.5)
    while t < end - 0.3:
        cues.append(Cue("blink", t, 0.2))
        t += rng.uniform(2.0, 4.0)
    t = start + 1.0 + rng.uniform(0.2, 1.0)
    while t < end - 0.8:
        length = min(rng.uniform(0.6, 1.4), end - t)
        cues.append(Cue("gaze", t, length, x=rng.uniform(-0.9, 0.9), y=rng.uniform(-0.6, 0.6)))
        t += length + rng.uniform(0.5, 1.5)
    t, sign = start + 1.5, 1.0
    while max_turn_deg > 0 and t < end - 1.0:
        length = min(rng.uniform(1.5, 2.5), end - t)
        yaw = sign * max_turn_deg * rng.uniform(0.6, 1.0)
        cues.append(Cue("turn", t, length, yaw=yaw, pitch=max_turn_deg / 3 * rng.uniform(-1, 1)))
        t, sign = t + length + rng.uniform(0.3, 1.0), -sign
    return Performance(end, tuple(cues), seed)


def load_performance(path: str | os.PathLike) -> Performance:
    """Read a performance script (TOML); errors name the file and the bad field."""
    doc = read_versioned(path, FORMAT, "performance")
    check = Validator(path)
    seconds = check.number(check.present(doc.get("seconds"), "seconds"), "seconds", 0.0)
    check.require(seconds > 0, "expected a number above 0, got 0", "seconds")
    seed = check.integer(doc.get("seed", 0), "seed")
    entries = doc.get("cue", [])
    check.require(isinstance(entries, list), f"expected an array of tables ([[cue]]), got {entries!r}", "cue")
    cues = [_cue(check, entry, at("cue", i)) for i, entry in enumerate(entries)]
    return Performance(seconds, tuple(cues), seed)


#: Each cue field's range.
_LIMITS = {"seconds": (0.0, math.inf), "strength": (0.0, 1.0), "x": (-1.0, 1.0), "y": (-1.0, 1.0),
           "yaw": (-30.0, 30.0), "pitch": (-30.0, 30.0), "hold": (0.0, math.inf), "step": (0.1, math.inf)}


def _cue(check: Validator, entry: object, where: str) -> Cue:
    entry = check.fields(entry, _FIELDS, where)
    kind = check.choice(entry.get("kind"), KINDS, at(where, "kind"))
    values: dict = {"kind": kind, "start": check.number(check.present(entry.get("start"), at(where, "start")),
                                                        at(where, "start"), 0.0)}
    if kind == "expression":
        name = entry.get("name")
        check.require(isinstance(name, str) and bool(name), "an expression cue needs a name from the repertoire",
                      at(where, "name"))
        values["name"] = name
    for key, (low, high) in _LIMITS.items():
        if key in entry:
            values[key] = check.number(entry[key], at(where, key), low, high)
    if "seconds" not in values and kind in _DEFAULT_SECONDS:
        values["seconds"] = _DEFAULT_SECONDS[kind]
    return Cue(**values)


def load_poses() -> dict[str, dict[str, float]]:
    """The built-in expression repertoire's poses: name -> {motor code: value}, the 21 motors'
    (a face's parameters beyond them, UL or PERK, are no marker's motion: the performer leaves
    them out).

    ``capture`` may not import ``toon``, whose ``load_expressions`` validates the file fully;
    callers above both layers (the ``synth`` command) pass its poses to :func:`perform` instead.
    """
    path = data_path("expressions.toml")
    table = read_document(path).get("expressions", {})
    poses = {name: dict(entry.get("motors", {})) for name, entry in table.items()}
    check = Validator(path)
    for name, motors in poses.items():
        for code in motors:
            if not (code.isascii() and code.isupper()):  # a parameter's code is capitals, as a motor's
                check.choice(code, CODES, f"expressions.{name}.motors.{code}")
    return {name: {c: v for c, v in motors.items() if c in CODES} for name, motors in poses.items()}


def perform(performance: Performance, times: np.ndarray,
            poses: dict[str, dict[str, float]] | None = None) -> np.ndarray:
    """The motor values at ``times`` (seconds), shape ``(frames, 21)``, columns in :data:`CODES` order.

    Raises
    ------
    InputError
        For an expression cue whose name is not in ``poses`` (default: the built-in repertoire).
    """
    poses = load_poses() if poses is None else poses
    m = {c: np.full(times.shape, v, dtype=np.float64) for c, v in NEUTRAL.items()}
    order = {kind: i for i, kind in enumerate(KINDS)}
    rng = np.random.default_rng(performance.seed)
    for cue in sorted(performance.cues, key=lambda c: (order[c.kind], c.start)):
        w = _envelope(times, cue.start, cue.end, min(0.25, max(cue.end - cue.start, 1e-9) / 3))
        if cue.kind in ("expression", "blink", "wink"):
            name = cue.name if cue.kind == "expression" else cue.kind
            if name not in poses:
                raise InputError(f'no expression "{name}" in the repertoire (known: {", ".join(poses)})')
            weight = w * cue.strength if cue.kind == "expression" else _bump(times, cue.start, cue.end)
            targets = poses[name]
        elif cue.kind == "gaze":
            weight = w
            targets = {f"P{s}H": 0.5 + 0.45 * cue.x for s in "RL"} | {f"P{s}V": 0.5 + 0.4 * cue.y for s in "RL"}
        elif cue.kind == "turn":
            weight = w
            targets = {"HH": 0.5 + cue.yaw / HEAD_RANGE_DEG, "HV": 0.5 + cue.pitch / HEAD_RANGE_DEG}
        elif cue.kind == "talk":
            phase = rng.uniform(0, 2 * np.pi)
            rate = 2 * np.pi * (3.5 + 1.0 * np.sin(1.3 * (times - cue.start) + phase) ** 2)
            syllables = 0.5 * (1 - np.cos(rate * (times - cue.start)))
            m["MB"] = m["MB"] + w * 0.45 * syllables
            for side in "RL":
                m[f"M{side}H"] = m[f"M{side}H"] - w * 0.06 * syllables
            continue
        else:  # calibrate
            _calibrate(m, times, cue)
            continue
        for code, target in targets.items():
            m[code] = m[code] + weight * (target - m[code])
    return np.clip(np.column_stack([m[c] for c in CODES]), 0.0, 1.0)


def _calibrate(m: dict[str, np.ndarray], times: np.ndarray, cue: Cue) -> None:
    """Overwrite ``m`` inside the calibration cue: neutral hold, then each group to 0, 1, neutral."""
    inside = (times >= cue.start) & (times < cue.end)
    for code in CODES:
        m[code][inside] = NEUTRAL[code]
    fractions, keys = _CALIBRATION_KEYS
    for g, group in enumerate(CALIBRATION_GROUPS):
        begin = cue.start + cue.hold + g * cue.step
        active = (times >= begin) & (times < begin + cue.step)
        for code in group:
            values = [float(NEUTRAL[code] if k == "n" else k) for k in keys]
            m[code][active] = np.interp((times[active] - begin) / cue.step, fractions, values)


def _bump(t: np.ndarray, start: float, end: float) -> np.ndarray:
    """A smooth 0-1-0 pulse over ``[start, end]``."""
    x = np.clip(1 - np.abs(t - (start + end) / 2) / max((end - start) / 2, 1e-9), 0, 1)
    return x * x * (3 - 2 * x)


def _envelope(t: np.ndarray, start: float, end: float, ramp: float) -> np.ndarray:
    """0 before ``start``, smooth rise over ``ramp`` s, 1 until ``end - ramp``, smooth fall."""
    up = np.clip((t - start) / ramp, 0, 1)
    down = np.clip((end - t) / ramp, 0, 1)
    x = np.minimum(up, down)
    return x * x * (3 - 2 * x)
