"""Picture helpers the renderer tests share."""

import io

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


def png_bytes(pixels: np.ndarray) -> bytes:
    """Straight RGBA ``(height, width, 4)`` ``uint8`` as PNG bytes."""
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(pixels, dtype=np.uint8), "RGBA").save(out, format="PNG")
    return out.getvalue()
