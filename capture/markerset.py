"""Marker sets: names, neutral positions and rigid head references, read from TOML."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common import InputError, read_document, resolve_builtin

FORMAT = "toonface.markerset/1"


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
        Markers that move rigidly with the skull, used to remove head motion.
    """

    name: str
    labels: tuple[str, ...]
    neutral: np.ndarray
    head_reference: tuple[str, ...]
    description: str = ""

    def neutral_of(self, label: str) -> np.ndarray:
        """Rest position of one marker, shape ``(3,)``."""
        return self.neutral[self.labels.index(label)]


def load_markerset(name_or_path: str | os.PathLike) -> MarkerSet:
    """Load a built-in marker set by name (``"toon32"``) or a TOML file."""
    path = resolve_builtin(name_or_path, "markersets", ".toml", "marker set")
    doc = read_document(path)
    if doc.get("format") != FORMAT:
        raise InputError(f'unsupported format {doc.get("format")!r} (expected "{FORMAT}")', path, "format")
    markers = doc.get("markers")
    if not isinstance(markers, dict) or not markers:
        raise InputError("missing [markers] table", path, "markers")
    labels = tuple(markers)
    neutral = np.empty((len(labels), 3))
    for i, label in enumerate(labels):
        value = markers[label].get("neutral") if isinstance(markers[label], dict) else None
        if not (isinstance(value, list) and len(value) == 3 and all(isinstance(v, (int, float)) for v in value)):
            raise InputError(f"expected neutral = [x, y, z] in mm, got {value!r}", path, f"markers.{label}.neutral")
        neutral[i] = value
    refs = tuple(doc.get("head_reference", ()))
    unknown = [r for r in refs if r not in labels]
    if unknown or len(refs) < 3:
        raise InputError(f"needs at least 3 known head reference markers; unknown {unknown}", path, "head_reference")
    neutral.setflags(write=False)
    return MarkerSet(str(doc.get("name", path.stem)), labels, neutral, refs, str(doc.get("description", "")))
