"""Marker sets: names, neutral positions, rigid head references and aliases, read from TOML.

Format ``toonface.markerset/1``::

    format = "toonface.markerset/1"
    name = "toon32"
    description = "..."
    head_reference = ["FOREHEAD", "TEMPLE_R", "TEMPLE_L"]   # at least 3, rigid with the skull
    independent = ["PUPIL_R", "PUPIL_L"]   # optional: gaps filled from each other only

    [markers]
    BROW_R_MED = { neutral = [-17.0, 20.0, 12.0], aliases = ["RBRO_IN"], mpeg4 = "4.2" }

``neutral`` is in the head frame, millimetres (x to the performer's left, y up, z out of the
face, origin between the eyes). ``aliases`` are other names the marker goes by (another
vendor's label); ``mpeg4`` is its MPEG-4 facial feature point ("group.index"). Markers listed
as ``independent`` move on their own (a gaze is not foretold by the lids or the lips): their
gaps are filled from each other, or straight across where none of them is seen, and never
from the other markers (:mod:`mapping.gaps`). A take whose labels carry a subject prefix
(Vicon's ``Subject:LABEL``) still matches.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field

import numpy as np

from capture.take import UNIT_MM
from common import InputError, builtin_names, read_versioned, resolve_builtin
from common.validate import Validator, at, is_number

FORMAT = "toonface.markerset/1"
_MPEG4 = re.compile(r"^\d{1,2}\.\d{1,2}$")


@dataclass(frozen=True, eq=False)
class MarkerSet:
    """A named layout of markers on a performer's face.

    Attributes
    ----------
    name : str
    labels : tuple of str, length M
    neutral : ndarray, shape (M, 3)
        Rest positions in the head frame, millimetres (x to the performer's left, y up, z out of
        the face, origin between the eyes).
    head_reference : tuple of str
        Markers that move rigidly with the skull, used to remove head motion: three or more, or
        none for a sparse layout that cannot fix a head frame (its head motion is not removed,
        :func:`mapping.clean.fixed_frame`).
    description : str
    aliases : dict of str to str
        Other name -> label.
    mpeg4 : dict of str to str
        Label -> MPEG-4 feature point number, for the markers that have one.
    table_rate : float or None
        The frame rate of this set's tables that do not state one (the ``[tables]`` section's
        ``rate``), used when a CSV has no time column and no ``--rate`` is given.
    table_units : str or None
        The units of this set's tables (``[tables]`` ``units``: a unit name or millimetres per
        unit), used when no ``--units`` is given.
    independent : tuple of str
        Markers filled only from each other (see the module docstring).
    """

    name: str
    labels: tuple[str, ...]
    neutral: np.ndarray
    head_reference: tuple[str, ...]
    description: str = ""
    aliases: dict[str, str] = field(default_factory=dict)
    mpeg4: dict[str, str] = field(default_factory=dict)
    table_rate: float | None = None
    table_units: str | None = None
    independent: tuple[str, ...] = ()

    def doubts(self) -> list[str]:
        """Reasons to think the neutral is not in head-frame millimetres, each a sentence (none
        for a plausible set): the head frame has its origin between the eyes, x to the
        performer's left, y up and z out of the face."""
        found: list[str] = []
        if not self.labels:  # no markers (a voice): no frame to doubt
            return found
        refs = np.array([self.neutral_of(r) for r in self.head_reference] or [np.zeros(3)])
        centre = refs.mean(axis=0)
        if np.linalg.norm(centre) > FAR_FROM_ORIGIN_MM:
            found.append(f"its head references are centred at ({', '.join(f'{v:.0f}' for v in centre)}) mm, "
                         "far from the head frame's origin between the eyes: were camera coordinates pasted?")
        extent = np.ptp(self.neutral, axis=0)
        if extent[2] > DEPTH_DOUBT * max(extent[0], extent[1]):  # markers at the ears make a layout as deep as tall
            found.append(f"it is deeper (z: {extent[2]:.0f} mm) than it is wide (x: {extent[0]:.0f}) and tall "
                         f"(y: {extent[1]:.0f}): z should point out of the face")
        sides = {side: [i for i, label in enumerate(self.labels) if _side(label) == side] for side in "LR"}
        if len(sides["L"]) >= 2 and len(sides["R"]) >= 2:
            left, right = (float(self.neutral[sides[s], 0].mean()) for s in "LR")
            if left < right:
                found.append(f"its left-named markers sit at x = {left:.0f} mm and its right-named ones at "
                             f"{right:.0f} mm: x points to the performer's left, so left and right are swapped")
        return found

    def neutral_of(self, label: str) -> np.ndarray:
        """Rest position of one marker, shape ``(3,)``."""
        return self.neutral[self.labels.index(self.canonical(label))]

    def canonical(self, name: str) -> str:
        """This set's label for ``name``: a label, an alias, or either behind a ``Subject:`` prefix.

        Raises
        ------
        InputError
            If the set has no such marker.
        """
        for candidate in (name, name.rsplit(":", 1)[-1]):
            if candidate in self.labels:
                return candidate
            if candidate in self.aliases:
                return self.aliases[candidate]
        raise InputError(f'marker "{name}" is not in marker set "{self.name}"')

    def match(self, take_labels: tuple[str, ...] | list[str]) -> dict[str, str]:
        """For each of this set's labels found among ``take_labels`` (directly, by alias or behind a
        subject prefix), the take's label: ``{set label: take label}``."""
        found: dict[str, str] = {}
        for take_label in take_labels:
            try:
                label = self.canonical(take_label)
            except InputError:
                continue
            found.setdefault(label, take_label)
        return found


#: Head references centred further than this from the origin are not in the head frame.
FAR_FROM_ORIGIN_MM = 150.0
#: A set deeper than this share of both its width and its height has z on a wrong axis (a real
#: layout with markers at the ears is as deep as it is tall, and that is no doubt).
DEPTH_DOUBT = 1.0
_SIDE_WORDS = {"l": "L", "left": "L", "lt": "L", "r": "R", "right": "R", "rt": "R"}


def _side(label: str) -> str | None:
    """``"L"`` or ``"R"`` for a label that names a side (``BROW_L_IN``, ``ForeHead_L``,
    ``Leye_Up``, ``left_cheek``), else None."""
    words = [w for w in re.split(r"[_\s\-.:]+|(?<=[a-z])(?=[A-Z])", label) if w]
    for word in words:
        if word.lower() in _SIDE_WORDS:
            return _SIDE_WORDS[word.lower()]
    match = re.match(r"^([LR])(?:eye|brow|eyebrow|cheek|lid|ear|temple|mouth|lip|nose|nostril|jaw)", label,
                     re.IGNORECASE)
    return match.group(1).upper() if match and label[0] in "LR" else None


def load_markerset(name_or_path: str | os.PathLike) -> MarkerSet:
    """Load a built-in marker set by name (``"toon32"``, ``"animface41"``, ``"gluedots16"``) or a TOML file."""
    path = resolve_builtin(name_or_path, "markersets", ".toml", "marker set")
    doc = read_versioned(path, FORMAT, "marker set")
    check = Validator(path)
    markers = doc.get("markers")
    markerless = doc.get("head_reference") == []  # a source with no markers at all (a voice) says so
    check.require(isinstance(markers, dict) and (bool(markers) or markerless), "missing [markers] table", "markers")
    assert isinstance(markers, dict)
    labels = tuple(markers)
    neutral = np.empty((len(labels), 3))
    aliases: dict[str, str] = {}
    mpeg4: dict[str, str] = {}
    for i, label in enumerate(labels):
        where = at("markers", label)
        entry = check.fields(markers[label], {"neutral", "aliases", "mpeg4"}, where, "a table with neutral = [x, y, z]")
        neutral[i] = check.numbers(check.present(entry.get("neutral"), at(where, "neutral")), 3, at(where, "neutral"))
        for alias in check.strings(entry.get("aliases", []), at(where, "aliases")):
            check.require(alias not in labels and alias not in aliases,
                          f'alias "{alias}" is already a label or another marker\'s alias', at(where, "aliases"))
            aliases[alias] = label
        if "mpeg4" in entry:
            code = entry["mpeg4"]
            check.require(isinstance(code, str) and bool(_MPEG4.match(code)),
                          f'expected an MPEG-4 feature point such as "4.1", got {code!r}', at(where, "mpeg4"))
            mpeg4[label] = code
    refs = tuple(check.strings(doc.get("head_reference", []), "head_reference"))
    unknown_refs = [r for r in refs if r not in labels]
    sparse = "head_reference" in doc and not refs  # said empty: a few markers with no head frame to fix
    check.require(not unknown_refs and (len(refs) >= 3 or sparse),
                  f"expected at least 3 head reference markers of this set (or head_reference = [] for a layout "
                  f"that cannot fix a head frame); unknown {unknown_refs}", "head_reference")
    independent = tuple(check.strings(doc.get("independent", []), "independent"))
    unknown = [m for m in independent if m not in labels]
    check.require(not unknown, f"expected markers of this set; unknown {unknown}", "independent")
    neutral.setflags(write=False)
    tables = check.fields(doc.get("tables", {}), {"rate", "units"}, "tables")
    rate = tables.get("rate")
    if rate is not None:
        check.require(check.number(rate, "tables.rate", 0, 100_000) > 0, "expected a number above 0, got 0",
                      "tables.rate")
    units = tables.get("units")
    check.require(units is None or isinstance(units, str) and units in UNIT_MM or is_number(units) and units > 0,
                  f"expected a unit ({', '.join(UNIT_MM)}) or millimetres per unit, got {units!r}", "tables.units")
    return MarkerSet(str(doc.get("name", path.stem)), labels, neutral, refs, str(doc.get("description", "")),
                     aliases, mpeg4, None if rate is None else float(rate), None if units is None else str(units),
                     independent)


def find_markerset(labels: tuple[str, ...] | list[str], min_share: float = 0.5) -> MarkerSet | None:
    """The built-in marker set that names most of ``labels`` (at least ``min_share`` of them,
    and at least 3 of its head references), or None. Between sets that name as many, the one
    more of whose own markers are there wins (a toon32 take is toon32's, not the larger face set's)."""
    best, best_key = None, (0, 0.0)
    for name in builtin_names("markersets", ".toml"):
        markerset = load_markerset(name)
        if not markerset.labels:  # a voice's: no markers to recognise
            continue
        found = markerset.match(labels)
        key = (len(found), len(found) / len(markerset.labels))
        if sum(r in found for r in markerset.head_reference) >= 3 and key > best_key:
            best, best_key = markerset, key
    best_count = best_key[0]
    return best if best is not None and best_count >= min_share * len(labels) else None
