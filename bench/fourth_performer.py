"""A fourth synthetic performer, made as real capture is (issue 62), designed apart from the others.

The first three move each marker straight from rest; real faces move along arcs and drag their
neighbours, and real optical capture loses and mislabels markers. Here:

- **Face.** ``toon32``'s labels on a narrower (8 %), longer (8 %), shallower (6 %) head, eyes 3 mm
  further apart, and every marker placed a seeded 2.5 mm off nominal in the face's plane (0.8 mm
  in depth), as hands place them.
- **Rest.** Brows a little raised (0.55), upper lids 0.75, lower lids 0.3, the mouth corners a
  little low (0.45), the jaw just open (0.05).
- **Arcs.** Pupils turn with an eyeball of 12 mm radius (±25° across, ±18° up and down); lids
  turn about the same centre (an upper lid closes by 32° and opens by 7°, a lower lid rises
  14° and drops 4°); brows slide over a forehead of 70 mm radius (11-13 mm of arc up, 4 down,
  the inner brow drawn 2 mm in as it lowers); mouth corners run around the teeth on a 45 mm arc
  (8 mm out, 5 in) and 7 mm up, 6 down; the jaw is a hinge 14 mm below and 95 mm behind the
  nose bridge: 0..20°, the chin and lower lip fully, the corners a third, the upper lip a little.
- **Cross-talk no motor accounts for.** A smile lifts the lower lids 1.8 mm and the cheeks 3 mm;
  raised brows lift the upper lids 1.2 mm; the corners drag the lips beside them by 40 %.
- **Skin under the head references.** The forehead marker slides 1.5 mm up with raised brows,
  the temples 0.8 mm back and 0.5 mm down as the jaw opens, the nose tip 0.4 mm up in a smile.
- **Head.** ±40° of yaw (HH), ±20° of pitch (HV), a slow roll of up to ±12°, about a pivot 100
  mm below and 85 mm behind the origin, with 10 mm of drift.
- **Script.** A second at rest; a sweep in an order of its own, each group to its low end and
  back to rest, then to its high end and back (2.5 s a group); then laughs, a raised brow of
  doubt, disgust, shock and a pucker at seeded strengths, speech at about 5 syllables a second
  whose corners move with the jaw, blinks every 2-6 s (a double blink now and then), gaze held and
  moved by 30 ms saccades, and large slow head turns.
- **Sensor, at 120 Hz.** 0.25 mm jitter; occlusions of lengths from 2 frames to 1.5 s (log-uniform),
  likeliest at lids, pupils and lips, until 8 % is missing; the far side's cheek, temple and outer
  eye markers hidden while the head is turned past 30°; six short swaps (3-10 frames) of
  neighbouring labels; 0.3 % spikes of 4-12 mm; and the left cheek marker falls off for good
  halfway through the performance.

:func:`write_in_metres` writes the same take as a TRC file in metres, as a lab's file says them.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from bench.sensor import PerformedTake, axis_rotations
from capture import Take, load_markerset
from capture.trcfile import write_trc
from toon import MOTOR_CODES

REST: dict[str, float] = {
    "BRL": 0.55, "BRC": 0.55, "BRM": 0.55, "BLL": 0.55, "BLC": 0.55, "BLM": 0.55,
    "ERU": 0.75, "ERL": 0.3, "ELU": 0.75, "ELL": 0.3, "PLH": 0.5, "PLV": 0.5, "PRH": 0.5, "PRV": 0.5,
    "MLH": 0.5, "MLV": 0.45, "MRH": 0.5, "MRV": 0.45, "MB": 0.05, "HH": 0.5, "HV": 0.5,
}
GROUPS: tuple[tuple[str, ...], ...] = (
    ("PRH", "PLH"), ("PRV", "PLV"), ("MB",), ("BRM", "BLM"), ("BRC", "BLC"), ("BRL", "BLL"), ("MRV", "MLV"),
    ("MRH", "MLH"), ("ERL", "ELL"), ("ERU", "ELU"), ("HH",), ("HV",))
RATE = 120.0
REST_SECONDS = 1.0
SWEEP_STEP = 2.5
SWEEP_END = REST_SECONDS + SWEEP_STEP * len(GROUPS)
EYEBALL_MM, FOREHEAD_MM, TEETH_MM = 12.0, 70.0, 45.0
HINGE = np.array([0.0, -20.0, -95.0])  # 14 mm below and 95 mm behind the nose bridge
HEAD_PIVOT = np.array([0.0, -100.0, -85.0])
#: Brows: arc (mm) up at 1 and down at 0, per brow marker.
_BROW_ARC = {"MED": (10.0, -4.0), "CEN": (13.0, -4.0), "LAT": (11.0, -3.0)}
_EXPRESSIONS: tuple[dict[str, float], ...] = (
    {"MRH": 0.95, "MLH": 0.95, "MRV": 0.85, "MLV": 0.85, "MB": 0.5, "ERL": 0.85, "ELL": 0.85, "ERU": 0.5,
     "ELU": 0.5, "BRC": 0.65, "BLC": 0.65},  # a laugh
    {"BLL": 0.95, "BLC": 0.9, "BRM": 0.3, "MLV": 0.3},  # doubt: one brow up
    {"MRV": 0.75, "MLV": 0.75, "ERL": 0.6, "ELL": 0.6, "BRM": 0.25, "BLM": 0.25, "MRH": 0.35, "MLH": 0.35},
    {"BRL": 1.0, "BRC": 1.0, "BRM": 1.0, "BLL": 1.0, "BLC": 1.0, "BLM": 1.0, "ERU": 1.0, "ELU": 1.0, "MB": 0.7},
    {"MRH": 0.1, "MLH": 0.1, "MB": 0.15},  # a pucker
)
_SWAPS = (("LIP_LOW_R", "LIP_LOW"), ("BROW_R_MED", "BROW_R_CEN"), ("LID_L_UP", "LID_L_LOW"),
          ("MOUTH_L", "LIP_UP_L"), ("BROW_L_LAT", "BROW_L_CEN"), ("LIP_UP", "LIP_UP_R"))


def perform(seconds: float = 20.0, seed: int = 21, faults: bool = True) -> PerformedTake:
    """Rest, sweep, then ``seconds`` of performance at 120 Hz."""
    rng = np.random.default_rng(seed)
    times = np.arange(int(round((SWEEP_END + seconds) * RATE))) / RATE
    motors = _script(times, rng)
    ms = load_markerset("toon32")
    face = _placed(ms.neutral, ms.labels, rng)
    yaw, world = _head(_face(face, ms.labels, motors), times, motors, rng)
    if faults:
        world = _sensor(world, ms.labels, face, yaw, times, rng)
    take = Take(world, ms.labels, RATE, times=times, meta={"source": "fourth synthetic performer", "seed": seed})
    return PerformedTake(take, motors, np.array([REST[c] for c in MOTOR_CODES]))


def write_in_metres(take: Take, path: Path) -> Path:
    """``take`` as a TRC file whose header says metres and whose numbers are metres."""
    write_trc(replace(take, positions=take.positions / 1000.0), path)
    lines = path.read_text(encoding="utf-8").split("\n")
    cells = lines[2].split("\t")
    cells[4] = "m"  # the Units column of the header's values
    lines[2] = "\t".join(cells)
    path.write_text("\n".join(lines), encoding="utf-8")
    return path


def _placed(neutral: np.ndarray, labels: tuple[str, ...], rng: np.random.Generator) -> np.ndarray:
    face = neutral * np.array([0.92, 1.08, 0.94])
    for i, label in enumerate(labels):
        if label.startswith(("EYE_", "LID_", "PUPIL_", "BROW_")):
            face[i, 0] += 3.0 * np.sign(face[i, 0])
    return face + rng.normal(0.0, 1.0, face.shape) * np.array([2.5, 2.5, 0.8])


def _script(times: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    col = {c: i for i, c in enumerate(MOTOR_CODES)}
    rest = np.array([REST[c] for c in MOTOR_CODES])
    out = np.tile(rest, (len(times), 1))
    for g, group in enumerate(GROUPS):  # low end and back, then high end and back
        start = REST_SECONDS + g * SWEEP_STEP
        keys = start + np.array([0.0, 0.35, 0.7, 1.0, 1.2, 1.55, 1.9, 2.2, 2.5])
        inside = (times >= start) & (times < start + SWEEP_STEP)
        for code in group:
            r = REST[code]
            out[inside, col[code]] = np.interp(times[inside], keys, [r, 0.0, 0.0, r, r, 1.0, 1.0, r, r])
    free = np.flatnonzero(times >= SWEEP_END)
    if not len(free):
        return out
    t0, t1 = times[free[0]], times[-1]
    at = t0 + 0.3
    while at < t1:
        target, strength = _EXPRESSIONS[int(rng.integers(len(_EXPRESSIONS)))], rng.uniform(0.5, 1.0)
        rise, hold = rng.uniform(0.15, 0.45), rng.uniform(0.3, 1.5)
        envelope = np.interp(times, [at, at + rise, at + rise + hold, at + 2.2 * rise + hold], [0, 1, 1, 0])
        envelope = 0.5 - 0.5 * np.cos(np.pi * envelope)
        for code, value in target.items():
            out[:, col[code]] += envelope * strength * (value - rest[col[code]])
        at += 2.2 * rise + hold + rng.uniform(0.2, 1.2)
    talking = (times > t0 + 1.0) & (np.sin(2 * np.pi * (times - t0) / 5.3 + 1.0) > 0.0)
    syllable = 0.5 - 0.5 * np.cos(2 * np.pi * 5.1 * times + 0.8 * np.sin(2.3 * times))
    depth = rng.uniform(0.35, 0.6)
    out[talking, col["MB"]] = np.maximum(out[talking, col["MB"]], REST["MB"] + depth * syllable[talking])
    for code in ("MRH", "MLH"):  # the corners narrow on rounded vowels, in time with the jaw
        out[talking, col[code]] -= 0.08 * np.sin(2 * np.pi * 2.55 * times[talking])
    at = t0 + rng.uniform(0.5, 2.0)
    while at < t1:
        for k in range(1 + int(rng.random() < 0.2)):  # now and then a double blink
            start = at + 0.3 * k
            shut = np.interp(times, [start, start + 0.08, start + 0.23], [0, 1, 0])
            for code in ("ERU", "ELU"):
                out[:, col[code]] *= 1 - shut
        at += rng.uniform(2.0, 6.0)
    at, gaze = t0, np.full(2, 0.5)
    targets = np.tile(gaze, (len(times), 1))
    while at < t1:
        gaze = rng.uniform(0.05, 0.95, 2)
        targets[times >= at] = gaze
        at += rng.uniform(0.4, 2.2)
    ramp = max(1, int(round(0.03 * RATE)))  # 30 ms saccades
    for axis, codes in ((0, ("PRH", "PLH")), (1, ("PRV", "PLV"))):
        padded = np.concatenate([np.full(ramp, targets[free[0], axis]), targets[free, axis]])
        moved = np.convolve(padded, np.ones(ramp) / ramp, mode="valid")[1:]
        for code in codes:
            out[free, col[code]] = moved
    for code, period in (("HH", 9.0), ("HV", 6.1)):
        phase = rng.uniform(0, 6)
        out[free, col[code]] = 0.5 + 0.48 * np.sin(2 * np.pi * (times[free] - t0) / period + phase)
    return np.clip(out, 0.0, 1.0)


def _turn(vector: np.ndarray, angle: np.ndarray, axis: str) -> np.ndarray:
    """``vector`` ``(F, 3)`` turned by ``angle`` ``(F,)`` radians: about x (positive lifts a point
    in front) or about y (positive carries a point in front toward +x)."""
    c, s = np.cos(angle), np.sin(angle)
    x, y, z = vector[:, 0], vector[:, 1], vector[:, 2]
    if axis == "x":
        return np.column_stack([x, y * c + z * s, -y * s + z * c])
    return np.column_stack([x * c + z * s, y, -x * s + z * c])


def _face(face: np.ndarray, labels: tuple[str, ...], motors: np.ndarray) -> np.ndarray:
    index = {label: i for i, label in enumerate(labels)}
    frames = len(motors)
    pos = np.broadcast_to(face, (frames, *face.shape)).copy()

    def m(code: str) -> np.ndarray:
        return motors[:, MOTOR_CODES.index(code)]

    def sided(code: str) -> np.ndarray:
        """-1 at the motor's 0, 0 at rest, +1 at its 1."""
        value, rest = m(code), REST[code]
        return np.where(value >= rest, (value - rest) / (1 - rest), (value - rest) / rest)

    for s, sign in (("R", -1.0), ("L", 1.0)):
        centre = face[index[f"PUPIL_{s}"]] - np.array([0.0, 0.0, EYEBALL_MM])
        yaw, pitch = np.radians(50.0 * (m(f"P{s}H") - 0.5)), np.radians(36.0 * (m(f"P{s}V") - 0.5))
        eye = _turn(_turn(np.tile(face[index[f"PUPIL_{s}"]] - centre, (frames, 1)), pitch, "x"), yaw, "y")
        pos[:, index[f"PUPIL_{s}"]] = centre + eye
        up, low = sided(f"E{s}U"), sided(f"E{s}L")
        brows_up = np.clip(np.mean([sided(f"B{s}{p}") for p in "LCM"], axis=0), 0, None)
        lid_up = np.radians(np.where(up >= 0, 7.0 * up, 32.0 * up))
        lid_low = np.radians(np.where(low >= 0, 14.0 * low, 4.0 * low))
        for label, angle in ((f"LID_{s}_UP", lid_up), (f"LID_{s}_LOW", lid_low)):
            pos[:, index[label]] = centre + _turn(np.tile(face[index[label]] - centre, (frames, 1)), angle, "x")
        pos[:, index[f"LID_{s}_UP"], 1] += 1.2 * brows_up
        for part, (raise_mm, lower_mm) in _BROW_ARC.items():
            i, share = index[f"BROW_{s}_{part}"], sided(f"B{s}{part[0]}")
            arc = np.where(share >= 0, raise_mm * share, -lower_mm * share)
            behind = face[i] - np.array([0.0, 0.0, FOREHEAD_MM])
            pos[:, i] = behind + _turn(np.tile(face[i] - behind, (frames, 1)), arc / FOREHEAD_MM, "x")
            if part == "MED":
                pos[:, i, 0] -= sign * 2.0 * np.clip(-share, 0, None)  # drawn in as it lowers
        h, v = sided(f"M{s}H"), sided(f"M{s}V")
        corner = index[f"MOUTH_{s}"]
        teeth = np.array([0.0, face[corner, 1], face[corner, 2] - TEETH_MM])
        out_mm = np.where(h >= 0, 8.0 * h, 5.0 * h)
        moved = teeth + _turn(np.tile(face[corner] - teeth, (frames, 1)), sign * out_mm / TEETH_MM, "y")
        moved[:, 1] += np.where(v >= 0, 7.0 * v, 6.0 * v)
        drag = moved - face[corner]
        pos[:, corner] = moved
        for lip in (f"LIP_UP_{s}", f"LIP_LOW_{s}"):
            pos[:, index[lip]] += 0.4 * drag
        smile = np.clip(h, 0, None) * np.clip(v + 0.5, 0, 1)
        pos[:, index[f"LID_{s}_LOW"], 1] += 1.8 * smile
        pos[:, index[f"CHEEK_{s}"]] += np.column_stack([sign * smile, 3.0 * smile, 0.0 * smile])
    jaw = np.radians(-20.0 * m("MB"))
    for label, carried in (("CHIN", 1.0), ("LIP_LOW", 1.0), ("LIP_LOW_R", 0.95), ("LIP_LOW_L", 0.95),
                           ("MOUTH_R", 0.33), ("MOUTH_L", 0.33), ("LIP_UP", 0.05)):
        i = index[label]
        pos[:, i] = HINGE + _turn(pos[:, i] - HINGE, carried * jaw, "x")
    brows = np.clip(np.mean([sided(c) for c in ("BRL", "BRC", "BRM", "BLL", "BLC", "BLM")], axis=0), 0, None)
    pos[:, index["FOREHEAD"], 1] += 1.5 * brows
    for temple in ("TEMPLE_R", "TEMPLE_L"):
        pos[:, index[temple]] += np.column_stack([0 * brows, -0.5 * m("MB"), -0.8 * m("MB")])
    pos[:, index["NOSE_TIP"], 1] += 0.4 * np.clip(sided("MRH") + sided("MLH"), 0, None) / 2
    return pos


def _head(local: np.ndarray, times: np.ndarray, motors: np.ndarray, rng: np.random.Generator
          ) -> tuple[np.ndarray, np.ndarray]:
    """World positions, and the head's yaw (degrees) per frame."""
    yaw = 80.0 * (motors[:, MOTOR_CODES.index("HH")] - 0.5)
    pitch = 40.0 * (motors[:, MOTOR_CODES.index("HV")] - 0.5)
    roll = 12.0 * np.sin(2 * np.pi * times / 11.0 + rng.uniform(0, 6)) * np.clip((times - SWEEP_END) / 3, 0, 1)
    ry, rx, rz = axis_rotations(*np.radians([yaw, pitch, roll]))
    rotation = ry @ rz @ rx
    drift = 10.0 * np.column_stack([np.sin(0.23 * times), np.sin(0.37 * times + 1), np.sin(0.17 * times + 3)])
    return yaw, np.einsum("fij,fmj->fmi", rotation, local - HEAD_PIVOT) + HEAD_PIVOT + drift[:, None, :]


def _sensor(world: np.ndarray, labels: tuple[str, ...], face: np.ndarray, yaw: np.ndarray, times: np.ndarray,
            rng: np.random.Generator) -> np.ndarray:
    out = world + rng.normal(0.0, 0.25, world.shape)
    frames, markers = out.shape[:2]
    index = {label: i for i, label in enumerate(labels)}
    for a, b in _SWAPS:  # neighbouring labels swapped for a few frames
        start, length = int(rng.integers(int(REST_SECONDS * RATE), frames - 12)), int(rng.integers(3, 11))
        rows = slice(start, start + length)
        out[rows, [index[a], index[b]]] = out[rows, [index[b], index[a]]]
    spikes = rng.random((frames, markers)) < 0.003
    direction = rng.normal(size=(frames, markers, 3))
    direction /= np.linalg.norm(direction, axis=2, keepdims=True)
    out = np.where(spikes[..., None], out + direction * rng.uniform(4, 12, (frames, markers, 1)), out)
    missing = np.zeros((frames, markers), bool)
    for label in ("CHEEK_L", "TEMPLE_L", "EYE_L_OUT", "BROW_L_LAT"):  # the far side, turned away (+x goes back)
        missing[yaw > 30.0, index[label]] = True
    for label in ("CHEEK_R", "TEMPLE_R", "EYE_R_OUT", "BROW_R_LAT"):
        missing[yaw < -30.0, index[label]] = True
    likely = np.array([3.0 if label.startswith(("LID_", "PUPIL_", "LIP_", "MOUTH_")) else 1.0 for label in labels])
    while missing.mean() < 0.08:  # occlusions of every length, from two frames to 1.5 s
        length = int(np.exp(rng.uniform(np.log(2), np.log(1.5 * RATE))))
        start, m = int(rng.integers(0, frames - length)), int(rng.choice(markers, p=likely / likely.sum()))
        missing[start:start + length, m] = True
    after = times >= SWEEP_END
    if after.any():  # the left cheek's marker falls off halfway through the performance
        missing[np.flatnonzero(after)[after.sum() // 2]:, index["CHEEK_L"]] = True
    out[missing] = np.nan
    return out
