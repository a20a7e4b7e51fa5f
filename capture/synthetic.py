"""A synthetic performer (v1): the ``toon32`` markers driven by a known motor script.

Forward model. Each motor value ``v`` (ToonFace's 21 motors, named by code; see DESIGN.md for
directions) moves markers away from their neutral positions in the head frame by
``mm_per_unit * (v - neutral)`` along one axis (:data:`DRIVES`). Then the whole head turns:
yaw ``(HH - 0.5) * 60`` degrees toward the performer's left and pitch ``(HV - 0.5) * 60``
degrees chin up, about a pivot behind the face, plus a slow sway; finally Gaussian jitter of
``noise_mm`` is added to every coordinate.

The script (times in seconds, repeating every 9 s after the first second):
0-1 neutral hold (for calibration); blinks; gaze shifts; a smile; brows up; talking; head turns.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture.markerset import MarkerSet, load_markerset
from capture.take import Take

#: The motor codes in ToonFace order, with the performer's neutral value of each.
NEUTRAL: dict[str, float] = {
    "BRL": 0.4, "BRC": 0.4, "BRM": 0.4, "BLL": 0.4, "BLC": 0.4, "BLM": 0.4,
    "ERU": 0.8, "ERL": 0.2, "ELU": 0.8, "ELL": 0.2,
    "PLH": 0.5, "PLV": 0.5, "PRH": 0.5, "PRV": 0.5,
    "MLH": 0.35, "MLV": 0.5, "MRH": 0.35, "MRV": 0.5, "MB": 0.1,
    "HH": 0.5, "HV": 0.5,
}

#: (motor, marker, axis, millimetres per unit of motor value) in the head frame.
DRIVES: tuple[tuple[str, str, int, float], ...] = (
    ("BRM", "BROW_R_MED", 1, 20.0), ("BRC", "BROW_R_CEN", 1, 20.0), ("BRL", "BROW_R_LAT", 1, 20.0),
    ("BLM", "BROW_L_MED", 1, 20.0), ("BLC", "BROW_L_CEN", 1, 20.0), ("BLL", "BROW_L_LAT", 1, 20.0),
    ("ERU", "LID_R_UP", 1, 14.0), ("ERL", "LID_R_LOW", 1, 6.0),
    ("ELU", "LID_L_UP", 1, 14.0), ("ELL", "LID_L_LOW", 1, 6.0),
    ("PRH", "PUPIL_R", 0, 12.0), ("PRV", "PUPIL_R", 1, 8.0),
    ("PLH", "PUPIL_L", 0, 12.0), ("PLV", "PUPIL_L", 1, 8.0),
    ("MRH", "MOUTH_R", 0, -20.0), ("MRV", "MOUTH_R", 1, 20.0),
    ("MLH", "MOUTH_L", 0, 20.0), ("MLV", "MOUTH_L", 1, 20.0),
    ("MRH", "LIP_UP_R", 0, -8.0), ("MLH", "LIP_UP_L", 0, 8.0),
    ("MRH", "LIP_LOW_R", 0, -8.0), ("MLH", "LIP_LOW_L", 0, 8.0),
    ("MRV", "CHEEK_R", 1, 6.0), ("MLV", "CHEEK_L", 1, 6.0),
    ("MB", "LIP_LOW", 1, -24.0), ("MB", "LIP_LOW_R", 1, -20.0), ("MB", "LIP_LOW_L", 1, -20.0),
    ("MB", "CHIN", 1, -18.0),
)
HEAD_RANGE_DEG = 60.0  # full 0..1 travel of HH and HV
HEAD_PIVOT_MM = (0.0, -30.0, -90.0)


@dataclass(frozen=True, eq=False)
class SyntheticTake:
    """A synthetic take and the motor values that drove it.

    Attributes
    ----------
    take : Take
    motor_codes : tuple of str, length 21
    motors : ndarray, shape (frames, 21)
        The true motor values, columns in ``motor_codes`` order.
    """

    take: Take
    motor_codes: tuple[str, ...]
    motors: np.ndarray


def synthesize(seconds: float = 10.0, rate: float = 30.0, noise_mm: float = 0.2, seed: int = 0,
               markerset: MarkerSet | None = None) -> SyntheticTake:
    """Make a synthetic take of the scripted performance.

    Parameters
    ----------
    seconds, rate : float
        Length and frame rate.
    noise_mm : float
        Standard deviation of the Gaussian jitter added to each coordinate.
    seed : int
        Seeds the jitter; the same arguments always give the same take.
    markerset : MarkerSet, optional
        Defaults to the built-in ``toon32``.
    """
    if seconds <= 0 or rate <= 0:
        raise ValueError(f"seconds and rate must be positive, got {seconds}, {rate}")
    if noise_mm < 0:
        raise ValueError(f"noise_mm must be >= 0, got {noise_mm}")
    ms = markerset if markerset is not None else load_markerset("toon32")
    times = np.arange(int(round(seconds * rate))) / rate
    codes = tuple(NEUTRAL)
    motors = script(times)
    local = _face_motion(ms, codes, motors)
    world = _head_motion(local, times, motors[:, codes.index("HH")], motors[:, codes.index("HV")])
    rng = np.random.default_rng(seed)
    world = world + rng.normal(0.0, noise_mm, size=world.shape) if noise_mm else world
    meta = {"source": "synthetic", "seed": seed, "noise_mm": noise_mm, "markerset": ms.name,
            "head_reference": list(ms.head_reference)}
    return SyntheticTake(Take(world, ms.labels, rate, times=times, meta=meta), codes, motors)


def script(times: np.ndarray) -> np.ndarray:
    """The scripted motor values at ``times`` (seconds), shape ``(frames, 21)``, ``NEUTRAL`` order."""
    codes = tuple(NEUTRAL)
    m = {c: np.full(times.shape, v) for c, v in NEUTRAL.items()}
    t = np.where(times < 1.0, -1.0, (times - 1.0) % 9.0 + 1.0)  # the neutral second, then cycles
    blink = sum(_bump(t, c, 0.18) for c in (1.6, 4.3, 6.9, 9.3))
    smile = _envelope(t, 2.0, 4.0, 0.35)
    brows = _envelope(t, 4.6, 6.1, 0.3)
    talk = _envelope(t, 6.4, 9.6, 0.2) * 0.5 * (1 - np.cos(2 * np.pi * 3.5 * (t - 6.4)))
    gaze_left = _envelope(t, 1.2, 2.8, 0.2)
    gaze_right_up = _envelope(t, 5.0, 6.3, 0.2)
    turn = _envelope(t, 2.2, 9.7, 0.6)
    for side in "RL":
        m[f"E{side}U"] = m[f"E{side}U"] * (1 - blink) + 0.15 * brows
        m[f"E{side}L"] = m[f"E{side}L"] + 0.12 * blink + 0.15 * smile
        m[f"M{side}H"] = m[f"M{side}H"] + 0.4 * smile + 0.08 * talk
        m[f"M{side}V"] = m[f"M{side}V"] + 0.35 * smile - 0.05 * talk
        m[f"P{side}H"] = m[f"P{side}H"] + 0.35 * gaze_left - 0.3 * gaze_right_up
        m[f"P{side}V"] = m[f"P{side}V"] + 0.25 * gaze_right_up
        for part in "MCL":
            m[f"B{side}{part}"] = m[f"B{side}{part}"] + 0.45 * brows
    m["MB"] = m["MB"] + 0.5 * talk + 0.1 * smile
    m["HH"] = 0.5 + 0.3 * np.sin(2 * np.pi * (t - 2.2) / 4.0) * turn
    m["HV"] = 0.5 + 0.1 * np.sin(2 * np.pi * (t - 2.2) / 3.0) * turn
    return np.clip(np.column_stack([m[c] for c in codes]), 0.0, 1.0)


def _face_motion(ms: MarkerSet, codes: tuple[str, ...], motors: np.ndarray) -> np.ndarray:
    """Marker positions in the head frame, shape ``(frames, markers, 3)``."""
    pos = np.broadcast_to(ms.neutral, (len(motors), *ms.neutral.shape)).copy()
    for code, label, axis, mm in DRIVES:
        col = codes.index(code)
        pos[:, ms.labels.index(label), axis] += mm * (motors[:, col] - NEUTRAL[code])
    return pos


def _head_motion(local: np.ndarray, times: np.ndarray, hh: np.ndarray, hv: np.ndarray) -> np.ndarray:
    """Turn the head (yaw then pitch about the pivot) and sway it; shape as ``local``."""
    yaw = np.radians((hh - 0.5) * HEAD_RANGE_DEG)
    pitch = np.radians((hv - 0.5) * HEAD_RANGE_DEG)
    rot = rotation_yaw_pitch(yaw, pitch)  # (F, 3, 3)
    pivot = np.asarray(HEAD_PIVOT_MM)
    sway = np.column_stack([4 * np.sin(0.7 * times), 2 * np.sin(0.45 * times), 3 * np.sin(0.3 * times)])
    return np.einsum("fij,fmj->fmi", rot, local - pivot) + pivot + sway[:, None, :]


def rotation_yaw_pitch(yaw: np.ndarray, pitch: np.ndarray) -> np.ndarray:
    """Rotations ``Ry(yaw) @ Rx(-pitch)``, shape ``(F, 3, 3)``, angles in radians.

    Positive yaw turns the face (+z) toward +x (the performer's left); positive pitch raises
    the chin (the face direction tilts toward +y).
    """
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
    zeros, ones = np.zeros_like(yaw), np.ones_like(yaw)
    ry = np.stack([np.stack([cy, zeros, sy], -1), np.stack([zeros, ones, zeros], -1),
                   np.stack([-sy, zeros, cy], -1)], -2)
    rx = np.stack([np.stack([ones, zeros, zeros], -1), np.stack([zeros, cp, sp], -1),
                   np.stack([zeros, -sp, cp], -1)], -2)
    return ry @ rx


def _bump(t: np.ndarray, centre: float, width: float) -> np.ndarray:
    """A smooth 0-1-0 pulse of total ``width`` seconds centred at ``centre``."""
    x = np.clip(1 - np.abs(t - centre) / (width / 2), 0, 1)
    return x * x * (3 - 2 * x)


def _envelope(t: np.ndarray, start: float, end: float, ramp: float) -> np.ndarray:
    """0 before ``start``, smooth rise over ``ramp`` s, 1 until ``end - ramp``, smooth fall."""
    up = np.clip((t - start) / ramp, 0, 1)
    down = np.clip((end - t) / ramp, 0, 1)
    x = np.minimum(up, down)
    return x * x * (3 - 2 * x)
