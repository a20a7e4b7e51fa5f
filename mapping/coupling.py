"""Motion one motor's markers make because another motor moved: learned from a range-of-motion
calibration, taken away when mapping.

A face is not a set of independent levers: an open jaw pulls the mouth corners down, raised
brows lift the upper lids. A mapping rule names the motors whose motion it should not show
(``decouple = ["MB"]`` on a mouth corner). A range-of-motion calibration moves each group of
motors in turn while the rest stay at rest, so it shows how far each of the rule's sources
moves, as a share of its own range, per share of the other motor's range (its first
source's), on each side of rest: least squares through rest over the frames where the other
motor has moved (beyond 0.3 of its way) and the rule's own sources are not being swept (within
0.9), only where both were seen (a filled gap would teach the filler's guess back). Mapping
then subtracts that share of the other motor's measured motion from each source before the
sources combine, offline and live alike.
"""

from __future__ import annotations

import numpy as np

from mapping.mapfile import Mapping, MotorRule
from mapping.profile import Profile
from mapping.sources import Source
from toon.motors import MIRROR_PAIRS

#: A driver at least this far along its way to either end (a share) has moved enough to show
#: what it carries; a rule's own sources this far along are being swept themselves.
MOVED = 0.3
EXTREME = 0.9
#: Frames at an extreme needed on one side before a coupling is measured there.
MIN_FRAMES = 10


def driver_of(mapping: Mapping, code: str) -> tuple[MotorRule, Source]:
    """The rule of motor ``code`` and the source that stands for its motion (its first)."""
    rule = next(r for r in mapping.rules if r.code == code)
    return rule, rule.sources[0]


def learn_couplings(mapping: Mapping, profile: Profile, normalised: dict[str, np.ndarray]
                    ) -> dict[str, dict[str, tuple[float, float]]]:
    """Couplings ``{source key: {driver source key: (below rest, above rest)}}`` for the rules
    that ask for them (``decouple``), from each source's values over the sweep's frames as a
    signed share of its range (``normalised``: source key -> ``(F,)``, as
    :func:`mapping.mapper.normalise` gives them, NaN unseen). A side the sweep did not show (the
    source lost while the other motor moved) takes the mirror motor's, where that one was seen."""
    measured: dict[tuple[str, int, str], list[float | None]] = {}  # (motor, source index, driver) -> sides
    for rule in mapping.rules:
        own = np.nan_to_num(np.abs(np.column_stack([normalised[s.key] for s in rule.sources])), nan=0.0).max(axis=1)
        for code in rule.decouple:
            _, driver = driver_of(mapping, code)
            if driver.key not in normalised or driver.key not in profile.sources:
                continue
            d = normalised[driver.key]
            for i, source in enumerate(rule.sources):
                x = normalised[source.key]
                sides: list[float | None] = []
                for side in (-1.0, 1.0):
                    at = (side * d >= MOVED) & (own < EXTREME) & np.isfinite(x)
                    sides.append(float(np.sum(x[at] * d[at]) / np.sum(d[at] ** 2)) if at.sum() >= MIN_FRAMES
                                 else None)
                measured[(rule.code, i, code)] = sides
    mirror = {a: b for a, b in MIRROR_PAIRS} | {b: a for a, b in MIRROR_PAIRS}
    out: dict[str, dict[str, tuple[float, float]]] = {}
    for (code, i, driver_code), sides in measured.items():
        partner = measured.get((mirror.get(code, code), i, mirror.get(driver_code, driver_code)), [None, None])
        slopes = [s if s is not None else (p if p is not None else 0.0) for s, p in zip(sides, partner, strict=True)]
        if any(slopes):
            rule, (_, driver) = next(r for r in mapping.rules if r.code == code), driver_of(mapping, driver_code)
            out.setdefault(rule.sources[i].key, {})[driver.key] = (slopes[0], slopes[1])
    return out


def decoupled(value: np.ndarray, source: Source, drivers: dict[str, np.ndarray], profile: Profile) -> np.ndarray:
    """A source's normalised values ``(F,)`` less the share of each driver's normalised motion
    (``drivers``: driver source key -> ``(F,)``) the profile measured; a driver not seen in a
    frame takes nothing away there."""
    out = value
    for key, (below, above) in profile.couplings.get(source.key, {}).items():
        if key in drivers:
            d = np.nan_to_num(drivers[key], nan=0.0)
            out = out - np.where(d < 0, below, above) * d
    return out
