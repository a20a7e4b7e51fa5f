"""Small array helpers shared by the frozen data objects."""

from __future__ import annotations

import numpy as np


def readonly(values: np.ndarray) -> np.ndarray:
    """A float64 copy of ``values`` that cannot be written to (frozen data objects hold these)."""
    out = np.array(values, dtype=np.float64, copy=True)
    out.setflags(write=False)
    return out
