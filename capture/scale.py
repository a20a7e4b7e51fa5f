"""Is a take in the units it was read in? A face's size says.

A CSV does not say its units, and a unit given by mistake (``--units m`` for millimetres) or a
file that states the wrong one scales every motion by ten or a thousand: the cartoon barely moves,
or gap filling meets numbers it cannot solve. Two figures tell, over frames spread through the
take:

* **against the marker set** (a built-in or drafted layout whose rest shape is in millimetres):
  the median ratio of distances between the markers the take and the set share, as the take
  has them over their distances in the set's neutral. A face differs from a layout's by a third
  at most; ten times is another unit.
* **against a face**: the extent of the marker cloud (the largest distance between two markers
  in a frame, median over frames), which on a face is 30-400 mm. This is the check for a layout
  drafted from the very take, whose rest shape shares the take's units.

:func:`check_scale` gives both, and the unit that would bring the take to a face's size.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture.markerset import MarkerSet
from capture.take import Take

#: The units a scale figure is explained by, in millimetres each.
UNITS: dict[str, float] = {"mm": 1.0, "cm": 10.0, "in": 25.4, "m": 1000.0}
#: A take whose shape is within this factor of its marker set's is in the set's units.
SHAPE_TOLERANCE = 2.5
#: The extent (mm) of a face's markers: the largest distance between two of them.
FACE_EXTENT_MM = (30.0, 400.0)
#: A typical face's extent (mm), to which a take too small or too large is compared.
TYPICAL_EXTENT_MM = 150.0
#: Frames looked at (evenly spread), enough for medians.
SAMPLE_FRAMES = 40
#: A unit's name explains a size that is within this factor of it.
NAMED_WITHIN = 1.6
#: Pairs of markers closer than this in the marker set (mm) say little about scale.
MIN_PAIR_MM = 10.0


@dataclass(frozen=True)
class ScaleCheck:
    """What a take's size says of its units.

    Attributes
    ----------
    ratio : float or None
        The take's distances over its marker set's (None: no marker set, or fewer than two
        shared markers seen).
    extent_mm : float or None
        The marker cloud's extent as read, mm (None: no frame with two markers).
    likely_unit : str or None
        The unit (of :data:`UNITS`) nearest to the one the take looks to be in, given the
        millimetres per unit it was read with; None where the take's size is plausible as read.
    factor : float
        By how much the positions as read are off: the size as read over the expected size.
    mm_per_unit : float
        The millimetres per unit the take was read with.
    markerset : str
        The marker set's name ("" without one), for messages.
    """

    ratio: float | None
    extent_mm: float | None
    likely_unit: str | None
    factor: float
    mm_per_unit: float = 1.0
    markerset: str = ""

    @property
    def off(self) -> bool:
        """Whether the take's size is implausible as read."""
        return self.likely_unit is not None

    @property
    def clear(self) -> bool:
        """Whether :attr:`likely_unit` explains the size within a factor :data:`NAMED_WITHIN`."""
        return self.likely_unit is not None and abs(np.log(UNITS[self.likely_unit] * self.factor
                                                           / self.mm_per_unit)) < np.log(NAMED_WITHIN)

    def likely(self) -> str:
        """The units the take looks to be in, as a ``--units`` value: ``"cm"``, or a number of
        millimetres per unit where no unit's name explains the size."""
        return str(self.likely_unit) if self.clear else f"{self.mm_per_unit / self.factor:.3g}"

    def figure(self) -> str:
        """The check's figures, for a report: ``"shape 1.02x marker set's, extent 164 mm"``."""
        parts = [] if self.ratio is None else [f"shape {self.ratio:.3g}x the marker set's"]
        if self.extent_mm is not None and self.off and self.clear:  # read in the wrong units: say both
            unit = str(self.likely_unit)
            parts.append(f"extent {self.extent_mm / self.mm_per_unit:.3g} {unit}, "
                         f"{self.extent_mm / self.mm_per_unit * UNITS[unit]:.3g} mm")
        elif self.extent_mm is not None:
            parts.append(f"extent {self.extent_mm:.3g} mm")
        return ", ".join(parts) or "nothing to measure"

    def words(self) -> str:
        """Why the size is implausible, and the units it looks to be in, in words."""
        if self.ratio is not None and not 1 / SHAPE_TOLERANCE <= self.ratio <= SHAPE_TOLERANCE:
            times, how = (self.ratio, "larger") if self.ratio > 1 else (1 / self.ratio, "smaller")
            size = f"its markers lie {times:.3g}x {how} than marker set {self.markerset}'s shape"
        else:
            size = (f"its markers span {self.extent_mm:.3g} mm, where a face's span "
                    f"{FACE_EXTENT_MM[0]:g}-{FACE_EXTENT_MM[1]:g} mm")
        unit = self.likely()
        return f"{size}: it looks to be in {unit if self.clear else f'about {unit} mm per unit'}"


def check_scale(take: Take, markerset: MarkerSet | None = None, mm_per_unit: float = 1.0) -> ScaleCheck:
    """Measure ``take``'s size against ``markerset``'s shape and a face's extent.

    Parameters
    ----------
    take : Take
        Positions ``(F, M, 3)`` in millimetres as read.
    markerset : MarkerSet, optional
        The layout the take is mapped with; its neutral is in millimetres.
    mm_per_unit : float
        The millimetres per unit the take was read with, to name the unit it looks to be in.

    Returns
    -------
    ScaleCheck
    """
    frames = np.unique(np.linspace(0, take.frames - 1, min(take.frames, SAMPLE_FRAMES)).astype(int))
    positions = take.positions[frames][:, :, :take.dims]  # (S, M, dims)
    apart = np.sqrt(np.sum((positions[:, :, None] - positions[:, None]) ** 2, axis=3))  # (S, M, M), NaN: unseen
    extent = _extent(apart)
    ratio = _shape_ratio(apart, take, markerset) if markerset is not None else None
    name = markerset.name if markerset is not None else ""
    if ratio is not None and not 1 / SHAPE_TOLERANCE <= ratio <= SHAPE_TOLERANCE:
        factor = ratio
    elif extent is not None and not FACE_EXTENT_MM[0] <= extent <= FACE_EXTENT_MM[1]:
        factor = extent / TYPICAL_EXTENT_MM  # a drafted set shares the take's units: only a face's size tells
    else:
        return ScaleCheck(ratio, extent, None, 1.0, mm_per_unit, name)
    unit = min(UNITS, key=lambda u: abs(np.log(UNITS[u] * factor / mm_per_unit)))
    return ScaleCheck(ratio, extent, unit, factor, mm_per_unit, name)


def _extent(apart: np.ndarray) -> float | None:
    """Median over frames of the largest distance between two seen markers, from distances
    ``(S, M, M)`` (NaN where either is unseen); None if no frame sees two."""
    largest = np.max(np.where(np.isfinite(apart), apart, -np.inf).reshape(len(apart), -1), axis=1, initial=-np.inf)
    usable = largest > 0
    return float(np.median(largest[usable])) if usable.any() else None


def _shape_ratio(apart: np.ndarray, take: Take, markerset: MarkerSet) -> float | None:
    """Median of (distance in the take / distance in the set) over shared marker pairs that are
    at least :data:`MIN_PAIR_MM` apart in the set, from the take's distances ``(S, M, M)``."""
    found = markerset.match(take.labels)
    if len(found) < 2:
        return None
    columns = [take.index(name) for name in found.values()]
    rest = np.array([markerset.neutral_of(label) for label in found])[:, :take.dims]
    rest_d = np.linalg.norm(rest[:, None] - rest[None], axis=2)
    upper = np.triu(np.ones_like(rest_d, dtype=bool), 1) & (rest_d >= MIN_PAIR_MM)
    if not upper.any():
        return None
    take_d = apart[:, columns][:, :, columns][:, upper]  # (S, pairs)
    ratios = take_d / rest_d[upper]
    ratios = ratios[np.isfinite(ratios) & (ratios > 0)]
    return float(np.median(ratios)) if len(ratios) else None
