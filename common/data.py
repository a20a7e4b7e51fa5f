"""Where the built-in data (faces, marker sets, mappings) lives."""

from __future__ import annotations

import os
import sys
from pathlib import Path


def data_path(*parts: str) -> Path:
    """Path of a built-in data file, such as ``data_path("faces", "classic.json")``.

    Looked up in ``$TOONFACE_DATA`` if set, then in the source tree's ``data/`` folder (editable
    installs and checkouts), then in ``<prefix>/share/toonface`` (wheel installs).
    """
    candidates = []
    if env := os.environ.get("TOONFACE_DATA"):
        candidates.append(Path(env))
    candidates.append(Path(__file__).resolve().parents[1] / "data")
    candidates.append(Path(sys.prefix) / "share" / "toonface")
    for root in candidates:
        if root.is_dir():
            return root.joinpath(*parts)
    return candidates[-1].joinpath(*parts)
