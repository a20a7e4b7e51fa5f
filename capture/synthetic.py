"""The synthetic performer (v2): the ``toon32`` markers driven by a known motor track.

Content comes from a :class:`~capture.performance.Performance` (a script of expressions, blinks,
winks, gaze shifts, talking, head turns and an optional calibration segment), turned into the
true motor values ``v`` (the 21 ToonFace motors; DESIGN.md gives their directions).

The forward model, in order:

1. **Face**: each motor moves markers from their neutral positions (the marker set's) in the
   head frame by ``mm_per_unit * (v - neutral_v)`` along one axis (:data:`DRIVES`, millimetres
   per unit of motor value; a marker may be moved by several motors, which add). Head-reference
   markers never move in the head frame.
2. **Head**: the head turns rigidly about a pivot 90 mm behind and 30 mm below the origin
   between the eyes: yaw ``(HH - 0.5) * 60`` degrees toward the performer's left, then pitch
   ``(HV - 0.5) * 60`` degrees chin up (``Ry(yaw) @ Rx(-pitch)``), so the head motors' 0..1
   covers ±30°; then a slow sway of a few millimetres is added (translation only).
3. **Sensor**: Gaussian jitter of ``noise_mm`` on every coordinate. Other faults (gaps, spikes,
   swaps, drift) are applied afterwards by :func:`capture.faults.apply_faults`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture.markerset import MarkerSet, load_markerset
from capture.performance import CODES, HEAD_RANGE_DEG, NEUTRAL, Performance, default_performance, perform
from capture.take import Take

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
               markerset: MarkerSet | None = None, performance: Performance | None = None,
               poses: dict[str, dict[str, float]] | None = None) -> SyntheticTake:
    """Make a synthetic take of a performance.

    Parameters
    ----------
    seconds, rate : float
        Length (ignored when ``performance`` is given: it has its own) and frame rate.
    noise_mm : float
        Standard deviation of the Gaussian jitter added to each coordinate.
    seed : int
        Seeds the jitter; the same arguments always give the same take.
    markerset : MarkerSet, optional
        Defaults to the built-in ``toon32``.
    performance : Performance, optional
        What the performer does; defaults to :func:`~capture.performance.default_performance`.
    poses : dict, optional
        The expression repertoire (name -> motor code -> value); defaults to the built-in one.
    """
    if seconds <= 0 or rate <= 0:
        raise ValueError(f"seconds and rate must be positive, got {seconds}, {rate}")
    if noise_mm < 0:
        raise ValueError(f"noise_mm must be >= 0, got {noise_mm}")
    ms = markerset if markerset is not None else load_markerset("toon32")
    performance = performance if performance is not None else default_performance(seconds)
    times = np.arange(int(round(performance.seconds * rate))) / rate
    made = performed(perform(performance, times, poses), rate, noise_mm, seed, ms)
    made.take.meta["cues"] = sorted({cue.kind for cue in performance.cues})
    return made


def performed(motors: np.ndarray, rate: float, noise_mm: float = 0.2, seed: int = 0,
              markerset: MarkerSet | None = None) -> SyntheticTake:
    """The synthetic take of given true motor values ``(frames, 21)`` (columns in :data:`CODES`
    order) at ``rate`` frames a second: the forward model of :func:`synthesize` without a script."""
    ms = markerset if markerset is not None else load_markerset("toon32")
    motors = np.asarray(motors, dtype=float)
    times = np.arange(len(motors)) / rate
    local = _face_motion(ms, CODES, motors)
    world = _head_motion(local, times, motors[:, CODES.index("HH")], motors[:, CODES.index("HV")])
    rng = np.random.default_rng(seed)
    world = world + rng.normal(0.0, noise_mm, size=world.shape) if noise_mm else world
    meta = {"source": "synthetic", "seed": seed, "noise_mm": noise_mm, "markerset": ms.name,
            "head_reference": list(ms.head_reference)}
    return SyntheticTake(Take(world, ms.labels, rate, times=times, meta=meta), CODES, motors)


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
