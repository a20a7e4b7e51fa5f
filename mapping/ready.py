"""What a take becomes on its way to a motor track: cleaned and stabilised for one mapping
(:class:`Prepared`), then calibrated too (:class:`ReadyTake`). The steps are in
:mod:`mapping.workflow`; its report (:mod:`mapping.report`) reads these as well, so they sit below both.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture import MarkerSet, Take
from mapping.clean import reference_labels
from mapping.mapfile import Mapping
from mapping.profile import Profile
from mapping.stabilise import Stabilised
from mapping.units import Units


@dataclass(frozen=True, eq=False)
class Prepared:
    """A take cleaned and stabilised for one mapping: what calibration and mapping read."""

    take: Take
    markerset: MarkerSet
    stable: Stabilised
    columns: dict[str, int]
    units: Units | None = None

    def reference_shape(self) -> dict[str, np.ndarray]:
        """The performer's head references as the take's head fit measured them, by marker set
        label (``(3,)`` each, head frame, mm); empty where the take has no head references."""
        present = reference_labels(self.take.labels, self.markerset)
        shape = self.stable.reference
        return {label: shape[k].copy() for k, label in enumerate(present)} if len(present) == len(shape) else {}


@dataclass(frozen=True)
class ReadyTake:
    """A take cleaned, stabilised and calibrated for one mapping: everything mapping needs but
    the face, so that one take is cleaned once for all the faces it goes on."""

    prepared: Prepared
    mapping: Mapping
    profile: Profile
    notes: tuple[str, ...]
    rest: str = ""  # where the rest pose came from, for the report
    profile_kind: str = ""  # given, calibrated, typical or from the take, for the report
