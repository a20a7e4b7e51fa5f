"""A second synthetic performer, designed apart from ``capture/synthetic.py``, to keep the
fidelity figures honest: a pipeline tuned on one generator should not pass for faithful.

What differs from the project's own performer, on purpose:

- **Face.** The ``toon32`` marker labels on a face of its own: 6 % larger than the marker set's
  neutral, every marker moved by a seeded 2.5 mm, so the head references' shape is not the set's.
- **Rest.** Its own neutral motor values (:data:`REST`: brows at 0.3, lids at 0.75 and 0.25,
  mouth corners at 0.5, the jaw at 0.05), not the faces' standard neutral.
- **Forward model.** Curved and coupled paths instead of straight lines: brows swing on a 40 mm
  arc (the inner brow also draws toward the midline as it lowers); upper and lower lids swing on
  the eyeball (radius 12 mm); pupils turn with the eyeball (±28° across, ±18° up and down); the
  jaw rotates about a hinge 75 mm behind and 30 mm below the origin (up to 26°), carrying the lower
  lips and chin, the lower lip dropping a little more; the corners move out and back on a curve.
  A brow raise lifts the upper lid (5 % of the brow's travel) and an open jaw pulls the corners
  down (8 % of the chin's drop), motion that no motor of the truth accounts for.
- **Head.** Pitch first, then yaw (``Rx(-pitch)`` applied before ``Ry(yaw)``), about a pivot
  75 mm below and 105 mm behind the origin, with a ±3° roll no motor shows and a 5 mm sway. HH's
  0..1 is ±30° of yaw, HV's ±20° of pitch.
- **Script.** One second at rest, a range-of-motion sweep (each group of motors to its minimum,
  held, to its maximum, held, and back), then random smooth bumps per group, blinks, talking at
  3-5 Hz and head turns.
- **Sensor.** 0.3 mm jitter, gaps of 0.5 s until 10 % of samples are missing, 1 % spikes of
  5-15 mm, drawn here (not by :mod:`capture.faults`).
"""

from __future__ import annotations

import numpy as np

from bench.sensor import PerformedTake, axis_rotations, sensor_faults
from capture import Take, load_markerset
from toon import MOTOR_CODES

#: The performer's own rest, per motor (its truth at rest).
REST: dict[str, float] = {
    "BRL": 0.3, "BRC": 0.3, "BRM": 0.3, "BLL": 0.3, "BLC": 0.3, "BLM": 0.3,
    "ERU": 0.75, "ERL": 0.25, "ELU": 0.75, "ELL": 0.25,
    "PLH": 0.5, "PLV": 0.5, "PRH": 0.5, "PRV": 0.5,
    "MLH": 0.5, "MLV": 0.5, "MRH": 0.5, "MRV": 0.5, "MB": 0.05, "HH": 0.5, "HV": 0.5,
}
#: The sweep's groups, in an order of their own.
GROUPS: tuple[tuple[str, ...], ...] = (
    ("MB",), ("MRH", "MLH"), ("MRV", "MLV"), ("ERU", "ELU"), ("ERL", "ELL"), ("BRL", "BLL"), ("BRC", "BLC"),
    ("BRM", "BLM"), ("PRH", "PLH"), ("PRV", "PLV"), ("HH",), ("HV",))
SWEEP_STEP = 2.2  # seconds per group: 0.3 down, 0.5 held, 0.6 up, 0.5 held, 0.3 back
REST_SECONDS = 1.0
SWEEP_END = REST_SECONDS + SWEEP_STEP * len(GROUPS)
HINGE = np.array([0.0, -30.0, -75.0])
HEAD_PIVOT = np.array([0.0, -75.0, -105.0])
YAW_RANGE, PITCH_RANGE = 60.0, 40.0  # degrees over HH's and HV's 0..1
EYE_RADIUS = 12.0


def perform(seconds: float = 20.0, rate: float = 60.0, seed: int = 7, faults: bool = True) -> PerformedTake:
    """The performer's take: rest, sweep, then ``seconds`` of performance."""
    rng = np.random.default_rng(seed)
    times = np.arange(int(round((SWEEP_END + seconds) * rate))) / rate
    motors = _script(times, rng)
    ms = load_markerset("toon32")
    face = ms.neutral * 1.06 + rng.normal(0.0, 2.5, ms.neutral.shape)
    local = _face(face, ms.labels, motors)
    world = _head(local, times, motors, rng)
    if faults:
        world = sensor_faults(world, rate, rng)
    take = Take(world, ms.labels, rate, times=times, meta={"source": "second synthetic performer", "seed": seed})
    return PerformedTake(take, motors, np.array([REST[c] for c in MOTOR_CODES]))


def _script(times: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """True motors ``(F, 21)``: rest, the sweep, then bumps, blinks, talk and head turns."""
    col = {c: i for i, c in enumerate(MOTOR_CODES)}
    out = np.tile([REST[c] for c in MOTOR_CODES], (len(times), 1))
    for g, group in enumerate(GROUPS):
        start = REST_SECONDS + g * SWEEP_STEP
        for code in group:
            keys_t = start + np.array([0.0, 0.3, 0.8, 1.4, 1.9, 2.2])
            keys_v = [REST[code], 0.0, 0.0, 1.0, 1.0, REST[code]]
            inside = (times >= start) & (times < start + SWEEP_STEP)
            out[inside, col[code]] = np.interp(times[inside], keys_t, keys_v)
    free = times >= SWEEP_END
    span = times[-1] - SWEEP_END
    for group in GROUPS[:-2]:  # face groups: raised-cosine bumps toward a random target
        for _ in range(int(span / 2.5)):
            at, width, target = SWEEP_END + rng.uniform(0, span), rng.uniform(0.4, 1.5), rng.uniform(0.0, 1.0)
            shape = np.where(np.abs(times - at) < width, 0.5 * (1 + np.cos(np.pi * (times - at) / width)), 0.0)
            for code in group:
                c = col[code]
                out[free, c] += (shape[free] * (target - out[free, c]))
    for at in np.arange(SWEEP_END + 1.3, times[-1], 3.1):  # blinks: 0.16 s down and up
        shut = np.clip(1 - np.abs(times - at) / 0.08, 0, 1)
        blinking = shut > 0
        for code in ("ERU", "ELU"):
            lid = out[blinking, col[code]]
            out[blinking, col[code]] = lid * (1 - shut[blinking]) + 0.02 * shut[blinking]
    talk = free & (np.sin(2 * np.pi * times / 7.0) > 0.2)
    per_second = 3.0 + 2.0 * (0.5 + 0.5 * np.sin(times))  # syllables a second, drifting between 3 and 5
    syllables = 0.5 - 0.5 * np.cos(2 * np.pi * np.concatenate([[0.0], np.cumsum(per_second[1:] * np.diff(times))]))
    out[talk, col["MB"]] = np.maximum(out[talk, col["MB"]], 0.05 + 0.6 * syllables[talk])
    for code, period, offset in (("HH", 9.0, 0.0), ("HV", 6.0, 1.0)):
        swing = 0.5 + 0.45 * np.sin(2 * np.pi * (times - SWEEP_END) / period + offset) * np.sin(
            np.pi * (times - SWEEP_END) / span)
        out[free, col[code]] = swing[free]
    return np.clip(out, 0.0, 1.0)


def _face(face: np.ndarray, labels: tuple[str, ...], motors: np.ndarray) -> np.ndarray:
    """Head-frame positions ``(F, M, 3)`` from the true motors by the curved, coupled model."""
    def v(code: str) -> np.ndarray:
        return motors[:, MOTOR_CODES.index(code)]

    frames = len(motors)
    pos = np.broadcast_to(face, (frames, *face.shape)).copy()
    index = {label: i for i, label in enumerate(labels)}
    lift: dict[str, np.ndarray] = {}
    for side, sign in (("R", -1.0), ("L", 1.0)):
        for part, code, reach in (("MED", f"B{side}M", 16.0), ("CEN", f"B{side}C", 18.0),
                                  ("LAT", f"B{side}L", 15.0)):
            m = index[f"BROW_{side}_{part}"]
            angle = reach * (v(code) - 0.3) / 40.0  # radians on a 40 mm arc
            pos[:, m, 1] += 40.0 * np.sin(angle)
            pos[:, m, 2] -= 40.0 * (1 - np.cos(angle))
            if part == "MED":  # a frown draws the inner brow toward the midline
                pos[:, m, 0] -= sign * 3.0 * np.clip(0.3 - v(code), 0, None)
            lift[side] = lift.get(side, 0.0) + 40.0 * np.sin(angle) / 3
        centre = face[index[f"PUPIL_{side}"]] - [0.0, 0.0, EYE_RADIUS]
        for lid, code, low, high in (("UP", f"E{side}U", -5.0, 62.0), ("LOW", f"E{side}L", -62.0, -8.0)):
            angle = np.radians(low + (high - low) * v(code))
            m = index[f"LID_{side}_{lid}"]
            pos[:, m] = centre + EYE_RADIUS * np.stack([np.zeros(frames), np.sin(angle), np.cos(angle)], -1)
            if lid == "UP":
                pos[:, m, 1] += 0.05 * lift[side]
        yaw, pitch = np.radians(28.0 * (2 * v(f"P{side}H") - 1)), np.radians(18.0 * (2 * v(f"P{side}V") - 1))
        pos[:, index[f"PUPIL_{side}"]] = centre + EYE_RADIUS * np.stack(
            [np.sin(yaw) * np.cos(pitch), np.sin(pitch), np.cos(yaw) * np.cos(pitch)], -1)
    angle = np.radians(26.0 * v("MB"))  # the jaw opens about its hinge
    cos, sin = np.cos(angle), np.sin(angle)
    for label, extra in (("LIP_LOW", 3.0), ("LIP_LOW_R", 2.0), ("LIP_LOW_L", 2.0), ("CHIN", 0.0)):
        m = index[label]
        rel = face[m] - HINGE
        pos[:, m, 1] = HINGE[1] + rel[1] * cos - rel[2] * sin - extra * v("MB")
        pos[:, m, 2] = HINGE[2] + rel[1] * sin + rel[2] * cos
    drop = face[index["CHIN"], 1] - pos[:, index["CHIN"], 1]
    for side, sign in (("R", -1.0), ("L", 1.0)):
        m = index[f"MOUTH_{side}"]
        out = 16.0 * (v(f"M{side}H") - 0.5)
        up = 13.0 * (v(f"M{side}V") - 0.5)
        pos[:, m, 0] += sign * out
        pos[:, m, 1] += up - 0.08 * drop
        pos[:, m, 2] -= 0.015 * out ** 2 + 0.1 * np.abs(up)
        pos[:, index[f"CHEEK_{side}"], 1] += 0.3 * up
        pos[:, index[f"LIP_UP_{side}"], 0] += sign * 0.4 * out
        pos[:, index[f"LIP_LOW_{side}"], 0] += sign * 0.4 * out
    return pos


def _head(local: np.ndarray, times: np.ndarray, motors: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Pitch, then yaw, then a small roll about the pivot, and a sway: world ``(F, M, 3)``."""
    yaw = np.radians(YAW_RANGE * (motors[:, MOTOR_CODES.index("HH")] - 0.5))
    pitch = np.radians(PITCH_RANGE * (motors[:, MOTOR_CODES.index("HV")] - 0.5))
    roll = np.radians(3.0 * np.sin(2 * np.pi * times / 11.0 + rng.uniform(0, 6)))
    ry, rx, rz = axis_rotations(yaw, pitch, roll)
    rotation = rz @ ry @ rx
    sway = 5.0 * np.column_stack([np.sin(0.5 * times), np.sin(0.37 * times + 1), np.sin(0.23 * times + 2)])
    return np.einsum("fij,fmj->fmi", rotation, local - HEAD_PIVOT) + HEAD_PIVOT + sway[:, None, :]
