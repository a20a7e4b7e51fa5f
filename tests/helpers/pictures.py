"""Picture helpers the renderer tests share."""

import numpy as np


def near_an_edge(image: np.ndarray) -> np.ndarray:
    """Pixels of ``image`` ``(h, w, 3)`` with a neighbour (8-connected) of another colour:
    where two renderers may disagree about coverage; ``(h, w)`` bool."""
    padded = np.pad(image.astype(int), ((1, 1), (1, 1), (0, 0)), mode="edge")
    h, w = image.shape[:2]
    out = np.zeros((h, w), dtype=bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            out |= np.any(padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] != image, axis=2)
    return out
