"""A third synthetic performer, written apart from the other two, to test what they share.

The project's own performer and the second one agree on things a real face need not: lids that
travel 10 mm or more, brows that rest mid-range and move in the face's plane, a mouth as wide as
``toon32``'s. This one differs on purpose (values from measured faces, not from the marker set):

- **Face.** ``toon32``'s labels on its own proportions: 9 % wider, 4 % shorter, 6 % deeper, the
  mouth 20 % wider again, the brows 4 mm lower, every marker moved by a seeded 2 mm.
- **Rest.** Brows rest low in their range (0.2), upper lids high (0.85), lower lids low (0.15),
  the mouth corners off-centre (out 0.42, up 0.58), the jaw closed (0.0).
- **Forward model.** Each motor moves its markers by one displacement at 0 and another at 1,
  straight from rest either way (so each side has its own slope): brows 3-4 mm down and 11-13 mm
  up with 4-6 mm of it toward the camera (a brow rides forward over the brow ridge); upper lids
  close by 3.5 mm and open by 0.6; lower lids rise by 2.6 mm (a smile's squint) and drop by 0.5;
  pupils 5 mm across and 3.5 mm up or down; mouth corners 9 mm out and back around the teeth,
  5 mm in and forward, 8 mm up, 7 mm down; the jaw drops the lower lip 21 mm and the chin 25 mm,
  both swinging back. A brow raise lifts the upper lid 0.9 mm, a jaw drop pulls the corners 3 mm
  down: motion no motor of the truth accounts for.
- **Head.** Yaw then pitch (``Rx(pitch) @ Ry(yaw)``) about a pivot 95 mm below and 90 mm behind
  the origin, a ±2° roll and a 6 mm drift. HH's 0..1 is ±25° of yaw, HV's ±18° of pitch.
- **Script.** A second at rest, a sweep (each group to its lowest, held, to its highest, held,
  back: 0.4, 0.4, 0.8, 0.4, 0.4 s), then expressions (smile with squint, surprise, frown, sad),
  speech, blinks every 2.5-5 s, gaze holds reached by 50 ms saccades and head turns, each at a
  seeded strength.
- **Sensor.** 0.3 mm jitter, 0.5 s gaps until 10 % of samples are missing, 1 % spikes of 5-15 mm.
"""

from __future__ import annotations

import numpy as np

from bench.sensor import PerformedTake, axis_rotations, sensor_faults
from capture import Take, load_markerset
from toon import MOTOR_CODES

REST: dict[str, float] = {
    "BRL": 0.2, "BRC": 0.2, "BRM": 0.2, "BLL": 0.2, "BLC": 0.2, "BLM": 0.2,
    "ERU": 0.85, "ERL": 0.15, "ELU": 0.85, "ELL": 0.15,
    "PLH": 0.5, "PLV": 0.5, "PRH": 0.5, "PRV": 0.5,
    "MLH": 0.42, "MLV": 0.58, "MRH": 0.42, "MRV": 0.58, "MB": 0.0, "HH": 0.5, "HV": 0.5,
}
GROUPS: tuple[tuple[str, ...], ...] = (
    ("BRL", "BLL", "BRC", "BLC", "BRM", "BLM"), ("ERU", "ELU"), ("ERL", "ELL"), ("MRH", "MLH"), ("MRV", "MLV"),
    ("MB",), ("PRH", "PLH"), ("PRV", "PLV"), ("HH",), ("HV",))
SWEEP_STEP = 2.4
REST_SECONDS = 1.0
SWEEP_END = REST_SECONDS + SWEEP_STEP * len(GROUPS)
HEAD_PIVOT = np.array([0.0, -95.0, -90.0])
YAW_DEGREES, PITCH_DEGREES = 25.0, 18.0  # either way of rest, over HH's and HV's 0..1

#: Per motor: (markers, displacement at 0, displacement at 1), mm in the head frame, as on the
#: performer's left ("{s}" is R or L; the right side's x is mirrored, except the pupils', whose
#: motors both count toward the character's own left).
_MOVES: dict[str, tuple[tuple[str, ...], tuple[float, float, float], tuple[float, float, float]]] = {
    "B{s}L": (("BROW_{s}_LAT",), (0.0, -3.0, -0.6), (0.0, 11.0, 4.0)),
    "B{s}C": (("BROW_{s}_CEN",), (0.0, -3.5, -0.8), (0.0, 13.0, 5.5)),
    "B{s}M": (("BROW_{s}_MED",), (-1.5, -4.0, -0.5), (0.0, 12.0, 6.0)),  # a frown draws it in (x toward 0)
    "E{s}U": (("LID_{s}_UP",), (0.0, -3.5, 0.7), (0.0, 0.6, -0.1)),
    "E{s}L": (("LID_{s}_LOW",), (0.0, -0.5, 0.0), (0.0, 2.6, 0.5)),
    "P{s}H": (("PUPIL_{s}",), (-5.0, 0.0, -0.4), (5.0, 0.0, -0.4)),  # x toward the performer's left
    "P{s}V": (("PUPIL_{s}",), (0.0, -3.5, -0.3), (0.0, 3.5, -0.3)),
    "M{s}H": (("MOUTH_{s}",), (-5.0, 0.0, 2.0), (9.0, 1.0, -4.0)),  # outward is +x on the left
    "M{s}V": (("MOUTH_{s}",), (0.0, -7.0, -0.5), (0.0, 8.0, -1.5)),
}
_JAW = {"LIP_LOW": (0.0, -21.0, -4.0), "LIP_LOW_R": (0.0, -18.0, -3.5), "LIP_LOW_L": (0.0, -18.0, -3.5),
        "CHIN": (0.0, -25.0, -8.0), "MOUTH_R": (0.0, -3.0, -1.0), "MOUTH_L": (0.0, -3.0, -1.0)}
#: Expressions after the sweep: targets of the motors each moves.
_EXPRESSIONS: tuple[dict[str, float], ...] = (
    {"MLH": 0.85, "MRH": 0.85, "MLV": 0.9, "MRV": 0.9, "ERL": 0.8, "ELL": 0.8, "ERU": 0.6, "ELU": 0.6},  # smile
    {"BRL": 0.95, "BRC": 1.0, "BLL": 0.95, "BLC": 1.0, "BRM": 0.9, "BLM": 0.9, "ERU": 1.0, "ELU": 1.0, "MB": 0.45},
    {"BRM": 0.0, "BLM": 0.0, "BRC": 0.05, "BLC": 0.05, "ERU": 0.6, "ELU": 0.6, "MLV": 0.35, "MRV": 0.35},  # frown
    {"BRM": 0.7, "BLM": 0.7, "BRL": 0.05, "BLL": 0.05, "MLV": 0.15, "MRV": 0.15, "MLH": 0.3, "MRH": 0.3},  # sad
)


def perform(seconds: float = 20.0, rate: float = 60.0, seed: int = 11, faults: bool = True) -> PerformedTake:
    """Rest, sweep, then ``seconds`` of performance."""
    rng = np.random.default_rng(seed)
    times = np.arange(int(round((SWEEP_END + seconds) * rate))) / rate
    motors = _script(times, rng)
    ms = load_markerset("toon32")
    face = _proportions(ms.neutral, ms.labels, rng)
    world = _head(_face(face, ms.labels, motors), times, motors, rng)
    if faults:
        world = sensor_faults(world, rate, rng)
    take = Take(world, ms.labels, rate, times=times, meta={"source": "third synthetic performer", "seed": seed})
    return PerformedTake(take, motors, np.array([REST[c] for c in MOTOR_CODES]))


def _proportions(neutral: np.ndarray, labels: tuple[str, ...], rng: np.random.Generator) -> np.ndarray:
    face = neutral * np.array([1.09, 0.96, 1.06]) + rng.normal(0.0, 2.0, neutral.shape)
    for i, label in enumerate(labels):
        if label.startswith(("MOUTH_", "LIP_")):
            face[i, 0] *= 1.2
        if label.startswith("BROW_"):
            face[i, 1] -= 4.0
    return face


def _script(times: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    col = {c: i for i, c in enumerate(MOTOR_CODES)}
    rest = np.array([REST[c] for c in MOTOR_CODES])
    out = np.tile(rest, (len(times), 1))
    for g, group in enumerate(GROUPS):
        start = REST_SECONDS + g * SWEEP_STEP
        keys_t = start + np.array([0.0, 0.4, 0.8, 1.6, 2.0, 2.4])
        inside = (times >= start) & (times < start + SWEEP_STEP)
        for code in group:
            out[inside, col[code]] = np.interp(times[inside], keys_t, [REST[code], 0.0, 0.0, 1.0, 1.0, REST[code]])
    free = np.flatnonzero(times >= SWEEP_END)
    if not len(free):
        return out
    t0, t1 = times[free[0]], times[-1]
    at = t0 + 0.5
    while at < t1:  # expressions: raised-cosine in, hold, out, each at a seeded strength
        target, strength = _EXPRESSIONS[int(rng.integers(len(_EXPRESSIONS)))], rng.uniform(0.6, 1.0)
        rise, hold = rng.uniform(0.25, 0.5), rng.uniform(0.4, 1.2)
        envelope = np.interp(times, [at, at + rise, at + rise + hold, at + 2 * rise + hold], [0, 1, 1, 0])
        envelope = 0.5 - 0.5 * np.cos(np.pi * envelope)
        for code, value in target.items():
            c = col[code]
            out[:, c] += envelope * strength * (value - rest[c])
        at += 2 * rise + hold + rng.uniform(0.3, 1.5)
    speech = (times > t0 + 2.0) & (np.sin(2 * np.pi * (times - t0) / 6.5) > 0.3)
    syllable = 0.5 - 0.5 * np.cos(2 * np.pi * 4.3 * times + np.sin(1.7 * times))
    out[speech, col["MB"]] = np.maximum(out[speech, col["MB"]], 0.55 * syllable[speech])
    at = t0 + rng.uniform(1.0, 2.5)
    while at < t1:  # blinks close both lids in 0.12 s and open in 0.2 s
        shut = np.interp(times, [at, at + 0.12, at + 0.32], [0, 1, 0])
        for code in ("ERU", "ELU"):
            out[:, col[code]] *= 1 - shut
        at += rng.uniform(2.5, 5.0)
    at = t0
    while at < t1:  # gaze holds, both eyes together, reached by 50 ms saccades
        look = rng.uniform(0.1, 0.9, 2)
        hold = (times >= at) & (times < at + 1.5)
        for axis, value in zip("HV", look, strict=True):
            for side in "RL":
                out[hold, col[f"P{side}{axis}"]] = value
        at += rng.uniform(0.8, 2.0)
    saccade = max(1, int(round(0.05 / float(np.median(np.diff(times))))))
    for code in ("PRH", "PRV", "PLH", "PLV"):  # a moving average: each jump becomes a 50 ms ramp
        c = col[code]
        padded = np.concatenate([np.full(saccade, out[free[0], c]), out[free, c]])
        out[free, c] = np.convolve(padded, np.ones(saccade) / saccade, mode="valid")[1:]
    for code, period in (("HH", 7.5), ("HV", 5.2)):
        phase, reach = rng.uniform(0, 6), rng.uniform(0.3, 0.45)
        out[free, col[code]] = 0.5 + reach * np.sin(2 * np.pi * (times[free] - t0) / period + phase) * np.sin(
            np.pi * (times[free] - t0) / max(t1 - t0, 1e-9))
    return np.clip(out, 0.0, 1.0)


def _face(face: np.ndarray, labels: tuple[str, ...], motors: np.ndarray) -> np.ndarray:
    index = {label: i for i, label in enumerate(labels)}
    pos = np.broadcast_to(face, (len(motors), *face.shape)).copy()

    def push(code: str, markers: tuple[str, ...], low: np.ndarray, high: np.ndarray) -> None:
        value, rest = motors[:, MOTOR_CODES.index(code)], REST[code]
        below = np.clip((rest - value) / max(rest, 1e-9), 0, None)[:, None]
        above = np.clip((value - rest) / max(1 - rest, 1e-9), 0, None)[:, None]
        for marker in markers:
            pos[:, index[marker]] += below * low + above * high

    for pattern, (markers, low, high) in _MOVES.items():
        for side in "RL":
            mirror = np.array([-1.0 if side == "R" and not pattern.startswith("P") else 1.0, 1.0, 1.0])
            push(pattern.format(s=side), tuple(m.format(s=side) for m in markers), np.array(low) * mirror,
                 np.array(high) * mirror)
    for marker, drop in _JAW.items():
        push("MB", (marker,), np.zeros(3), np.array(drop))
    for side in "RL":  # couplings no motor accounts for
        brow = np.clip(motors[:, MOTOR_CODES.index(f"B{side}C")] - REST[f"B{side}C"], 0, None) / (1 - REST["BRC"])
        pos[:, index[f"LID_{side}_UP"], 1] += 0.9 * brow
    return pos


def _head(local: np.ndarray, times: np.ndarray, motors: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    yaw = np.radians(2 * YAW_DEGREES * (motors[:, MOTOR_CODES.index("HH")] - 0.5))
    pitch = np.radians(2 * PITCH_DEGREES * (motors[:, MOTOR_CODES.index("HV")] - 0.5))
    roll = np.radians(2.0 * np.sin(2 * np.pi * times / 13.0 + rng.uniform(0, 6)))
    ry, rx, rz = axis_rotations(yaw, pitch, roll)
    rotation = rz @ rx @ ry
    drift = 6.0 * np.column_stack([np.sin(0.31 * times), np.sin(0.43 * times + 2), np.sin(0.19 * times + 4)])
    return np.einsum("fij,fmj->fmi", rotation, local - HEAD_PIVOT) + HEAD_PIVOT + drift[:, None, :]
