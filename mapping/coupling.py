"""Motion one motor's markers make because another motor moved: learned from a range-of-motion
calibration, taken away when mapping.

A face is not a set of independent levers: an open jaw pulls the mouth corners down, raised
brows lift the upper lids. A mapping rule names the motors whose motion it should not show
(``decouple = ["MB"]`` on a mouth corner). A range-of-motion calibration moves each group of
motors in turn while the rest stay at rest, so it shows how far each of the rule's sources
moves, as a share of its own range, per share of the other motor's range (its first
source's), on each side of rest: least squares over the frames where the other motor has
moved (beyond 0.3 of its way) and the rule's own sources are not being swept (within 0.9), only
where both were seen (a filled gap would teach the filler's guess back), through the source's
level while no driver moves (:data:`STILL`). Mapping
then subtracts that share of the other motor's measured motion from each source before the
sources combine, offline and live alike.

A rule may name several drivers (an upper lid under the three parts of its brow): they are
fitted together, each on its own side. A sweep that moves them one at a time shows what each
carries; one that moves them at once cannot tell them apart, and the driver named first carries
it all (``toon32`` names the centre of the brow first). Fitted one by one, each driver took the
whole lift, and a lid under a whole brow lost three times its millimetre. A driver that moved
only while one named before it was lost is not measured (:func:`_together`).

The motion a driver carries is the same distance whichever side of rest the source stands
(raised brows lift a lid by a millimetre, open or shut), but a source's range may differ
either side (an upper lid shuts by 3.5 mm and opens by 0.6): so the coupling is measured and
taken away in the source's own units, and kept as a share of the source's range on the side
it moves the source toward. Taken away as a share of whichever side the source stands on, a
lid lifted by raised brows and blinking at once read as shut four times too early.
"""

from __future__ import annotations

import numpy as np

from mapping.mapfile import Mapping, MotorRule
from mapping.plan import reach_of
from mapping.profile import NOISE_FACTOR, Profile
from mapping.robust import jitter
from mapping.sources import Source
from toon.motors import MIRROR_OF

#: A driver at least this far along its way to either end (a share) has moved enough to show
#: what it carries; a rule's own sources this far along are being swept themselves.
MOVED = 0.3
EXTREME = 0.9
#: Frames at an extreme needed on one side before a coupling is measured there.
MIN_FRAMES = 10
#: Drivers within this share of rest are still: the source's level while all of them are (and it
#: is not being swept itself) is what it reads with none of their motion, and the slopes are
#: measured from that level. The project's own performer's lids sat 0.1 mm above their rest
#: through its whole sweep, and measured from rest each part of the brow seemed to lift them.
STILL = 0.1
#: A driver that moved in this share of its frames with one the mapping names before it is not
#: told apart from that one, which carries what both do (a whole brow swept at once).
TOGETHER = 0.5


def driver_of(mapping: Mapping, code: str) -> tuple[MotorRule, Source]:
    """The rule of motor ``code`` and the source that stands for its motion (its first)."""
    rule = next(r for r in mapping.rules if r.code == code)
    return rule, rule.sources[0]


def learn_couplings(mapping: Mapping, profile: Profile, normalised: dict[str, np.ndarray],
                    noise: dict[str, float] | None = None) -> dict[str, dict[str, tuple[float, float]]]:
    """Couplings ``{source key: {driver source key: (below rest, above rest)}}`` for the rules
    that ask for them (``decouple``), from each source's values over the sweep's frames as a
    signed share of its range (``normalised``: source key -> ``(F,)``, as
    :func:`mapping.mapper.normalise` gives them, NaN unseen). A side the sweep did not show (the
    source lost while the other motor moved) takes the mirror motor's, where that one was seen.
    ``noise``: driver source key -> its jitter as recorded (a standard deviation in its units); a
    side of a driver's range no longer than the jitter says (:func:`_sides_shown`) carries nothing."""
    measured: dict[tuple[str, int, str], list[float | None]] = {}  # (motor, source index, driver) -> sides
    for rule in mapping.rules:
        own = np.nan_to_num(np.abs(np.column_stack([normalised[s.key] for s in rule.sources])), nan=0.0).max(axis=1)
        drivers: dict[str, np.ndarray] = {}  # the drivers' shares, by code
        shown: dict[str, tuple[bool, bool]] = {}  # and whether each side goes further than the jitter
        for code in rule.decouple:
            driver_rule, driver = driver_of(mapping, code)
            if driver.key in normalised and driver.key in profile.sources:
                drivers[code] = normalised[driver.key]
                shown[code] = _sides_shown(reach_of(driver, driver_rule, profile), (noise or {}).get(driver.key))
        if not drivers:
            continue
        for i, source in enumerate(rule.sources):
            x = normalised[source.key]
            up, down = reach_of(source, rule, profile)
            units = np.where(x >= 0, x * up, x * down)  # the source's own units
            for code, found in _slopes(units, own, drivers, shown).items():
                measured[(rule.code, i, code)] = [None if v is None else v / (up if v * side >= 0 else down)
                                                  for v, side in zip(found, (-1.0, 1.0), strict=True)]  # a share
    out: dict[str, dict[str, tuple[float, float]]] = {}
    for (code, i, driver_code), found in measured.items():
        partner = measured.get((MIRROR_OF.get(code, code), i, MIRROR_OF.get(driver_code, driver_code)), [None, None])
        kept = [s if s is not None else (p if p is not None else 0.0) for s, p in zip(found, partner, strict=True)]
        if any(kept):
            rule, (_, driver) = next(r for r in mapping.rules if r.code == code), driver_of(mapping, driver_code)
            out.setdefault(rule.sources[i].key, {})[driver.key] = (kept[0], kept[1])
    return out


def _slopes(units: np.ndarray, own: np.ndarray, drivers: dict[str, np.ndarray], shown: dict[str, tuple[bool, bool]]
            ) -> dict[str, list[float | None]]:
    """Each driver's slope below and above rest (the source's ``units`` ``(F,)`` per unit of the
    driver's share, ``drivers``: code -> ``(F,)``, NaN unseen, in the mapping's order), None for a
    side not shown (the mirror motor's then); ``own`` ``(F,)``: how far the rule's own sources
    are along their way (being swept at :data:`EXTREME`); ``shown``: whether each side of a driver
    goes further than its jitter (one that does not carries nothing, 0.0)."""
    free = (own < EXTREME) & np.isfinite(units)
    columns: list[tuple[str, int]] = []  # (driver, side) fitted together
    sides: dict[str, list[float | None]] = {code: [0.0, 0.0] for code in drivers}
    frames = np.zeros(len(units), bool)
    for s, side in enumerate((-1.0, 1.0)):
        moved = {code: (side * d >= MOVED) & free for code, d in drivers.items() if shown[code][s]}
        order = list(moved)  # the mapping's: one that moved with an earlier one is that one's
        for n, code in enumerate(order):
            together = [_together(moved[code], moved[c], drivers[c]) for c in order[:n]]
            if True in together:
                continue  # carries nothing of its own (0.0)
            if None in together or moved[code].sum() < MIN_FRAMES:
                sides[code][s] = None
                continue
            columns.append((code, s))
            frames |= moved[code]
    if columns:
        still = free & (own < MOVED) & np.all([np.abs(np.nan_to_num(d, nan=1.0)) < STILL for d in drivers.values()],
                                               axis=0)
        level = float(np.median(units[still])) if still.sum() >= MIN_FRAMES else 0.0
        for (code, s), slope in zip(columns, _joint_slopes(units - level, drivers, columns, frames), strict=True):
            sides[code][s] = slope
    return sides


def _together(at: np.ndarray, other: np.ndarray, values: np.ndarray) -> bool | None:
    """Whether a driver that moved at ``at`` ``(F,)`` moved with another, which moved at
    ``other`` ``(F,)``: in at least :data:`TOGETHER` of the frames where it moved and the other
    was seen (``values`` ``(F,)``, NaN unseen); None where the other was seen in none of them.
    A third-performer brow's centre was lost while its whole brow rose, and the inner part,
    fitted alone there, took the lift the centre had taken where it was seen: the lid lost it
    twice. A fourth-performer brow's centre was lost while its outer part rose alone."""
    both = at & np.isfinite(values)
    return bool((at & other).sum() >= TOGETHER * both.sum()) if both.any() else None


def _joint_slopes(units: np.ndarray, drivers: dict[str, np.ndarray],
                  columns: list[tuple[str, int]], at: np.ndarray) -> list[float | None]:
    """The slope of each ``(driver, side)`` of ``columns`` (side 0 below rest, 1 above): the
    source's ``units`` ``(F,)`` (from its level with every driver still) per unit of the driver's
    share (``drivers``: code -> its shares ``(F,)``, NaN unseen), on that side only, all fitted
    together through 0 over the frames ``at`` ``(F,)`` where any of them moved: where one driver's
    frames also hold another's motion (a brow part still raised as the next one sweeps), each
    takes only its own. A frame where one of them is unseen is left out: read as still there, its
    motion went to the others moving with it. A side left with fewer than :data:`MIN_FRAMES`
    frames of its own is None, as one not shown.

    >>> t = np.linspace(0.0, 1.0, 40)
    >>> a, b = np.r_[t, t], np.r_[0 * t, t]  # A rises alone, then both
    >>> units = 2 * a + b
    >>> a[65:] = np.nan  # A lost while both rose
    >>> [round(v, 6) for v in _joint_slopes(units, {"A": a, "B": b}, [("A", 1), ("B", 1)], np.r_[t, t] > 0.3)]
    [2.0, 1.0]
    """
    rows = np.flatnonzero(at & np.all([np.isfinite(drivers[code]) for code, _ in columns], axis=0))
    design = np.column_stack([np.where((2 * s - 1) * drivers[code][rows] > 0, drivers[code][rows], 0.0)
                              for code, s in columns])
    slopes = np.linalg.lstsq(design, units[rows], rcond=None)[0] if len(rows) else np.zeros(len(columns))
    enough = (design != 0.0).sum(axis=0) >= MIN_FRAMES
    return [float(v) if shown else None for v, shown in zip(slopes, enough, strict=True)]


def recorded_jitter(mapping: Mapping, positions: np.ndarray, columns: dict[str, int]) -> dict[str, float]:
    """Each decoupling driver's jitter as the take recorded it (``positions`` ``(F, M, 3)`` mm,
    before cleaning smoothed it away; ``columns`` label -> column): the median over its markers'
    axes, a standard deviation (mm), what a side of its range must exceed to have been shown
    (:func:`learn_couplings`)."""
    out: dict[str, float] = {}
    for code in sorted({c for rule in mapping.rules for c in rule.decouple}):
        _, driver = driver_of(mapping, code)
        rows = [columns[m] for m in driver.markers if m in columns]
        if driver.kind == "marker" and rows:
            noise = jitter(positions[:, rows])
            if np.isfinite(noise).any():
                out[driver.key] = float(np.nanmedian(noise))
    return out


def _sides_shown(reach: tuple[float, float], noise: float | None) -> tuple[bool, bool]:
    """Whether a driver's range (``reach``: its units per normalised unit above and below rest)
    goes any way below and above rest beyond its jitter ``noise`` (a standard deviation in the
    same units; None unknown): a side no longer than :data:`mapping.profile.NOISE_FACTOR` times
    it is the jitter itself (a jaw closed at rest has no way up, 0.2 mm of its noise on the third
    performer: measured there, the mouth corners learnt to rise and fall with the lower lip's
    jitter).

    >>> _sides_shown((20.6, 0.19), 0.3), _sides_shown((20.6, 0.19), None)
    ((False, True), (True, True))
    """
    if noise is None or not np.isfinite(noise):
        return True, True
    up, down = reach
    return down > NOISE_FACTOR * noise, up > NOISE_FACTOR * noise


def decoupled(value: np.ndarray, source: Source, drivers: dict[str, np.ndarray], profile: Profile,
              reach: tuple[float, float] = (1.0, 1.0)) -> np.ndarray:
    """A source's normalised values ``(F,)`` less the share of each driver's normalised motion
    (``drivers``: driver source key -> ``(F,)``) the profile measured, taken away in the
    source's own units: ``reach``, what one unit of its value is on its positive and its
    negative side (:func:`mapping.plan.reach_of`). A driver not seen in a frame takes nothing away there."""
    up, down = reach
    units = np.where(value >= 0, value * up, value * down)
    for key, (below, above) in profile.couplings.get(source.key, {}).items():
        if key in drivers:
            d = np.nan_to_num(drivers[key], nan=0.0)
            carried = np.where(d < 0, below, above) * d  # a share of the side it moves the source to
            units = units - np.where(carried >= 0, carried * up, carried * down)
    return np.where(units >= 0, units / up, units / down)
