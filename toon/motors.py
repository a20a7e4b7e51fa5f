"""The 21 ToonFace motors (appendix A1.2.1): codes, the control point each moves, directions.

A motor moves one coordinate of one control point between a minimum and a maximum position set
by the face; its value is that position as a fraction ``P_CTRL`` in ``[0, 1]`` (formula A1.5).

Directions (DESIGN.md; the seed leaves some open). Right/left are the character's own:
- vertical motors: 1 is higher on the face (brows up, upper lid open, lower lid raised, mouth
  corner up), except ``MB``, the mouth's bottom point, where 1 is fully open (lowest);
- pupils and head horizontal: 1 is toward the character's own left (ToonFace: "left is
  positive"); head vertical: 1 is chin up;
- mouth corners horizontal: 1 is outward from the midline, so a symmetric smile raises MLH and
  MRH alike.

The seed's list calls PLH "PUPIL/RIGHT/HORIZONTAL"; the code and its neighbour PLV say left, so
PLH is the left pupil here.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np


@dataclass(frozen=True)
class MotorSpec:
    """One motor: its code, the control point it moves, the axis, and which way 1 points.

    ``increasing`` is +1 when the motor's maximum lies at a larger face coordinate than its
    minimum on a face drawn with the character's right on the viewer's left (x to the viewer's
    right, y up), -1 when smaller.
    """

    code: str
    point: str
    axis: str  # "x" or "y"
    increasing: int
    description: str
    #: What a designer calls it, for panels and staves, saying which way 1 lies ("Left eye looks
    #: left"): left and right are the character's own, its right on the viewer's left.
    name: str = ""


MOTORS: tuple[MotorSpec, ...] = (
    MotorSpec("BRL", "BRL", "y", +1, "brow right lateral [3]", "Right brow, outer"),
    MotorSpec("BRC", "BRC", "y", +1, "brow right central [2]", "Right brow, middle"),
    MotorSpec("BRM", "BRM", "y", +1, "brow right medial [1]", "Right brow, inner"),
    MotorSpec("BLL", "BLL", "y", +1, "brow left lateral [6]", "Left brow, outer"),
    MotorSpec("BLC", "BLC", "y", +1, "brow left central [5]", "Left brow, middle"),
    MotorSpec("BLM", "BLM", "y", +1, "brow left medial [4]", "Left brow, inner"),
    MotorSpec("ERU", "ERU", "y", +1, "eye right upper lid [7]", "Right upper lid"),
    MotorSpec("ERL", "ERL", "y", +1, "eye right lower lid [9]", "Right lower lid"),
    MotorSpec("ELU", "ELU", "y", +1, "eye left upper lid [8]", "Left upper lid"),
    MotorSpec("ELL", "ELL", "y", +1, "eye left lower lid [10]", "Left lower lid"),
    MotorSpec("PLH", "PL", "x", +1, "pupil left horizontal [15]", "Left eye looks left"),
    MotorSpec("PLV", "PL", "y", +1, "pupil left vertical [15]", "Left eye looks up"),
    MotorSpec("PRH", "PR", "x", +1, "pupil right horizontal [16-H]", "Right eye looks left"),
    MotorSpec("PRV", "PR", "y", +1, "pupil right vertical [16-V]", "Right eye looks up"),
    MotorSpec("MLH", "ML", "x", +1, "mouth left corner horizontal, outward [14-H]", "Left corner out"),
    MotorSpec("MLV", "ML", "y", +1, "mouth left corner vertical [14-V]", "Left corner up"),
    MotorSpec("MRH", "MR", "x", -1, "mouth right corner horizontal, outward [13-H]", "Right corner out"),
    MotorSpec("MRV", "MR", "y", +1, "mouth right corner vertical [13-V]", "Right corner up"),
    MotorSpec("MB", "MB", "y", -1, "mouth bottom, 1 = fully open [12]", "Mouth open"),
    MotorSpec("HH", "HEAD", "x", +1, "head horizontal (turn), degrees [17-H]", "Head turns left"),
    MotorSpec("HV", "HEAD", "y", +1, "head vertical (tilt, 1 = chin up), degrees [17-V]", "Head tips back"),
)
"""The 21 motors of ToonFace's A1.2.1, in the movie script's column order: each one's code, the
control point it moves, along which axis, which way 1 lies, and what it is."""

MOTOR_CODES: tuple[str, ...] = tuple(m.code for m in MOTORS)
"""The motors' codes in column order, ``BRL`` ... ``HV``."""
N_MOTORS: int = len(MOTORS)
"""21."""


@dataclass(frozen=True)
class ExtraSpec:
    """A standard parameter beyond the 21: what it means and the value a face rests at."""

    description: str
    neutral: float
    #: What a designer calls it, for panels and staves.
    name: str = ""


#: Parameters beyond the 21 that a face may declare, each 0..1 like a motor; a track carries
#: them as named columns after the 21. The mapping presets drive all of them; a face that does
#: not declare one is drawn without it (the player says so once).
STANDARD_EXTRAS: dict[str, ExtraSpec] = {
    "HT": ExtraSpec("head tilt (roll): 0.5 upright; towards 1 the head turns counter-clockwise as seen, towards 0 "
                    "clockwise, by up to the face's head.tilt degrees, about its head pivot", 0.5, "Head tilts"),
    "UL": ExtraSpec("upper lip raised, as in a sneer or a snarl: 0 at rest, 1 fully raised", 0.0, "Sneer (upper lip)"),
    "CP": ExtraSpec("cheeks puffed out with air: 0 at rest, 1 fully puffed", 0.0, "Cheeks puffed"),
    "JS": ExtraSpec("jaw sideways: 0.5 centred; towards 1 the chin moves to the character's own left, towards 0 "
                    "to its right", 0.5, "Jaw sideways"),
    "PERK": ExtraSpec("what stands on the head rises in surprise (ears prick up, a hat lifts): 0 at rest, "
                      "1 fully up", 0.0, "Perks up (surprise)"),
}
#: What an extra parameter's code looks like (a motor's do too).
EXTRA_CODE = r"[A-Z][A-Z0-9_]{0,15}"
#: The 21 motors and then the standard extras: the columns a mapping computes.
ALL_CODES: tuple[str, ...] = (*MOTOR_CODES, *STANDARD_EXTRAS)
N_CODES: int = len(ALL_CODES)
MOTOR_INDEX: MappingProxyType[str, int] = MappingProxyType({c: i for i, c in enumerate(MOTOR_CODES)})
HEAD_MOTORS: tuple[str, ...] = ("HH", "HV")

# The neutral pose every built-in face is drawn in, so that one motor track reads the same on
# all of them: brows a little below the middle (room to raise), upper lids mostly open, lower
# lids low, pupils and head centred, mouth corners a third of the way out, mouth nearly closed.
_STANDARD_NEUTRAL = {
    "BRL": 0.4, "BRC": 0.4, "BRM": 0.4, "BLL": 0.4, "BLC": 0.4, "BLM": 0.4,
    "ERU": 0.8, "ERL": 0.2, "ELU": 0.8, "ELL": 0.2,
    "PLH": 0.5, "PLV": 0.5, "PRH": 0.5, "PRV": 0.5,
    "MLH": 0.35, "MLV": 0.5, "MRH": 0.35, "MRV": 0.5, "MB": 0.1,
    "HH": 0.5, "HV": 0.5,
}


def standard_neutral() -> np.ndarray:
    """The standard neutral motor values, shape ``(21,)``, in motor-code order (a fresh copy)."""
    return np.array([_STANDARD_NEUTRAL[c] for c in MOTOR_CODES], dtype=np.float64)


def code_index(code: str) -> int:
    """Column of a motor or a standard extra in a ``(frames, N_CODES)`` array (:data:`ALL_CODES`)."""
    try:
        return ALL_CODES.index(code)
    except ValueError:
        raise KeyError(f'unknown motor or parameter "{code}" (expected one of {" ".join(ALL_CODES)})') from None


def extended_neutral(neutral: np.ndarray) -> np.ndarray:
    """A neutral of the 21 motors ``(21,)`` with each standard extra's after it, ``(N_CODES,)``; one
    already that long as it is."""
    neutral = np.asarray(neutral, dtype=np.float64)
    if len(neutral) == N_CODES:
        return neutral
    return np.concatenate([neutral, [spec.neutral for spec in STANDARD_EXTRAS.values()]])


def extra_rest(code: str, declared: Mapping[str, float] | None = None) -> float:
    """Where parameter ``code`` beyond the 21 rests: as ``declared`` (a face's
    :meth:`~toon.Face.extra_neutral`) where it is there, else its standard neutral, else 0.5."""
    if declared and code in declared:
        return float(declared[code])
    return STANDARD_EXTRAS[code].neutral if code in STANDARD_EXTRAS else 0.5


def motor_index(code: str) -> int:
    """Column of a motor code in a ``(frames, 21)`` array; raises ``KeyError`` naming the code."""
    try:
        return MOTOR_INDEX[code]
    except KeyError:
        raise KeyError(f'unknown motor code "{code}" (expected one of {" ".join(MOTOR_CODES)})') from None


#: Right/left motor pairs swapped by mirroring.
MIRROR_PAIRS: tuple[tuple[str, str], ...] = (
    ("BRL", "BLL"), ("BRC", "BLC"), ("BRM", "BLM"), ("ERU", "ELU"), ("ERL", "ELL"),
    ("PRH", "PLH"), ("PRV", "PLV"), ("MRH", "MLH"), ("MRV", "MLV"),
)
#: Each motor of :data:`MIRROR_PAIRS` to its partner on the other side of the face, both ways.
MIRROR_OF: Mapping[str, str] = MappingProxyType({**dict(MIRROR_PAIRS), **{left: right for right, left in MIRROR_PAIRS}})
#: Motors whose direction (toward the character's left) flips in a mirror image.
MIRROR_REFLECTED: tuple[str, ...] = ("PLH", "PRH", "HH", "HT", "JS")  # HT, JS where values carry the extras


def mirror_values(values: np.ndarray, neutral: np.ndarray) -> np.ndarray:
    """The mirror image of motor values: sides swapped, leftward motions made rightward.

    Parameters
    ----------
    values : ndarray, shape (frames, 21)
    neutral : ndarray, shape (21,)
        Reflected motors are reflected about their neutral value (then clipped to [0, 1]).
    """
    out = np.array(values, dtype=np.float64, copy=True)
    for right, left in MIRROR_PAIRS:
        i, j = MOTOR_INDEX[right], MOTOR_INDEX[left]
        out[:, [i, j]] = out[:, [j, i]]
    for code in MIRROR_REFLECTED:
        i = ALL_CODES.index(code)
        if i < out.shape[1]:
            out[:, i] = 2 * neutral[i] - out[:, i]
    return np.clip(out, 0.0, 1.0)
