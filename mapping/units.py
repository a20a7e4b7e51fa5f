"""The units a take is mapped in: checked against its marker set and a face's size, said aloud.

:func:`settle_units` runs before cleaning (:func:`mapping.workflow.prepare`). With the take's
size measured by :func:`capture.scale.check_scale`:

* a take whose size is plausible keeps its units, and the report says which and who said so;
* a table that does not say its units (read as millimetres by assumption, or in its marker set's
  ``[tables]`` units), whose shape against a known layout is clearly another unit's (10x for
  centimetres, 1000x for metres, 25.4x for inches), is read in that unit, with a note saying so;
* units given on the command line that make the face implausible are an error naming the
  likely units, before any work is done (``--units m`` for millimetres made gap filling fail);
* anything else implausible (a file that states the wrong units, a drafted layout, a unit no
  name explains) is a warning naming the likely units.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from capture import MarkerSet, Take
from capture.scale import UNITS, ScaleCheck, check_scale
from common import InputError


@dataclass(frozen=True)
class Units:
    """The units a take is mapped in, for the report.

    Attributes
    ----------
    mm_per_unit : float
        Millimetres per unit of the file.
    origin : str
        Who said so: ``"given"``, ``"file"``, ``"marker set NAME"``, ``"assumed"`` (a table that
        does not say) or ``"inferred"``.
    check : ScaleCheck
        The size check on the take as read.
    notes : tuple of str
        What the user should be told (``"warning: ..."`` or a plain note).
    """

    mm_per_unit: float
    origin: str
    check: ScaleCheck
    notes: tuple[str, ...] = ()

    @property
    def size(self) -> float:
        """The take's size against its marker set's as settled (1.0 where it has no figure): the
        shape ratio as read, in the units the take was settled in."""
        if self.check.ratio is None:
            return 1.0
        return self.check.ratio * self.mm_per_unit / self.check.mm_per_unit

    def name(self) -> str:
        """The unit's name (``"cm"``), or millimetres per unit as a number."""
        return next((u for u, mm in UNITS.items() if np.isclose(mm, self.mm_per_unit)), f"{self.mm_per_unit:g} mm/unit")

    def as_dict(self) -> dict[str, Any]:
        return {"unit": self.name(), "mm_per_unit": self.mm_per_unit, "from": self.origin,
                "check": ("as read, " if self.origin == "inferred" else "") + self.check.figure(),
                "plausible": not self.check.off or self.origin == "inferred"}


def settle_units(take: Take, markerset: MarkerSet) -> tuple[Take, Units]:
    """``take`` in the units its size says (see the module docstring), and what was decided.

    Raises
    ------
    InputError
        When units given by the user make the face implausible.
    """
    said = take.meta.get("units") or {"mm_per_unit": 1.0, "from": "file"}
    scale, origin = float(said["mm_per_unit"]), str(said["from"])
    check = check_scale(take, markerset, scale)
    if not check.off:
        return take, Units(scale, origin, check)
    file = take.meta.get("file", "the take")
    if origin == "given":
        raise InputError(f"--units {Units(scale, origin, check).name().split()[0]}: {check.words()}; give "
                         f"--units {check.likely()}", take.meta.get("file"))
    if (origin == "assumed" or origin.startswith("marker set")) and check.clear and check.ratio is not None:
        unit = str(check.likely_unit)
        moved = replace(take, positions=take.positions * (UNITS[unit] / scale),
                        meta={**take.meta, "units": {"mm_per_unit": UNITS[unit], "from": "inferred"}})
        said_by = "it does not say its units" if origin == "assumed" else f"its {origin} says {scale:g} mm per unit"
        return moved, Units(UNITS[unit], "inferred", check,
                            (f"units: {file} read in {unit} ({said_by}, and as read {check.words()}); "
                             "--units sets them",))
    stated = {"file": "in the units its file states", "assumed": "as millimetres, as it does not say"}.get(
        origin, f"as its {origin} says")
    return take, Units(scale, origin, check, (
        f"warning: units: {file} read {stated}, but {check.words()}" + (" (--units)" if origin != "file" else ""),))
