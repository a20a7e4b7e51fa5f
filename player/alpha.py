"""Pictures with transparency: renderers draw premultiplied colour (what GL's blending and
Cairo's surfaces hold: a pixel half covered by white over nothing is ``(128, 128, 128, 128)``),
and files store straight colour (PNG, VP9's and ProRes's alpha: the same pixel is white at alpha
128). :func:`straight` turns one into the other; without it, every antialiased edge would be
darkened over whatever the picture is later laid on (the dark fringe).
"""

from __future__ import annotations

import numpy as np


def straight(premultiplied: np.ndarray) -> np.ndarray:
    """Straight RGBA ``uint8`` ``(height, width, 4)`` from premultiplied RGBA of the same shape:
    each colour divided by its alpha (rounded; 0 where nothing covers the pixel)."""
    rgba = np.asarray(premultiplied)
    alpha = rgba[..., 3:4].astype(np.uint16)
    colour = (rgba[..., :3].astype(np.uint16) * 255 + alpha // 2) // np.maximum(alpha, 1)
    out = np.empty_like(rgba)
    out[..., :3] = np.minimum(colour, 255)
    out[..., 3] = rgba[..., 3]
    return out


def over(rgba: np.ndarray, colour: np.ndarray | tuple[float, float, float]) -> np.ndarray:
    """Straight RGBA ``uint8`` ``(height, width, 4)`` laid over an opaque ``colour`` (0..255 each):
    RGB ``uint8`` ``(height, width, 3)``, for outputs that keep no alpha (a JPEG, a camera)."""
    alpha = rgba[..., 3:4].astype(np.float32) / 255.0
    background = np.asarray(colour, dtype=np.float32)
    return np.rint(rgba[..., :3] * alpha + background * (1.0 - alpha)).astype(np.uint8)


def premultiplied_clear(background: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """A background colour ``(r, g, b, a)`` (0..1, straight) as a renderer clears to it."""
    r, g, b, a = background
    return r * a, g * a, b * a, a
