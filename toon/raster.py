"""CPU rasterisation: the reference the GL renderer is checked against, and view fitting."""

from __future__ import annotations

import numpy as np

from toon.rig import Geometry


def fit_viewbox(viewbox: tuple[float, float, float, float], size: tuple[int, int]) -> tuple[float, float, float]:
    """Scale (pixels per face unit) and pixel offsets that fit ``viewbox`` centred in ``size``.

    Parameters
    ----------
    viewbox : (xmin, ymin, xmax, ymax)
        Face units, y up.
    size : (width, height)
        Pixels.

    Returns
    -------
    scale, offset_x, offset_y : float
        ``px = (x - xmin) * scale + offset_x``, ``py = (ymax - y) * scale + offset_y``
        (pixel rows grow downward; pixel ``(i, j)`` has its centre at ``(j + 0.5, i + 0.5)``).
    """
    xmin, ymin, xmax, ymax = viewbox
    width, height = size
    scale = min(width / (xmax - xmin), height / (ymax - ymin))
    return scale, (width - (xmax - xmin) * scale) / 2, (height - (ymax - ymin) * scale) / 2


def to_pixels(vertices: np.ndarray, viewbox: tuple[float, float, float, float], size: tuple[int, int]) -> np.ndarray:
    """Face-unit vertices ``(N, 2)`` to pixel coordinates ``(N, 2)`` (x right, y down)."""
    scale, ox, oy = fit_viewbox(viewbox, size)
    return np.column_stack([(vertices[:, 0] - viewbox[0]) * scale + ox, (viewbox[3] - vertices[:, 1]) * scale + oy])


def rasterize_polygon(vertices: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Pixels whose centres lie inside a polygon (even-odd rule).

    Parameters
    ----------
    vertices : ndarray, shape (N, 2)
        ``(x, y)`` in pixel units, y down; pixel ``(i, j)`` is centred at ``(j + 0.5, i + 0.5)``.
    shape : (rows, cols)

    Returns
    -------
    ndarray of bool, shape ``shape``

    Examples
    --------
    >>> rasterize_polygon(np.array([[1, 0], [4, 0], [4, 3], [1, 3]]), (4, 5)).astype(int)
    array([[0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 0, 0, 0, 0]])
    >>> rasterize_polygon(np.array([[0, 0], [4, 0], [0, 4]]), (4, 4)).astype(int)
    array([[1, 1, 1, 0],
           [1, 1, 0, 0],
           [1, 0, 0, 0],
           [0, 0, 0, 0]])

    Centres exactly on an edge, like ``(3.5, 0.5)`` on the hypotenuse above, follow the
    half-open rule of the crossing test (as GL's tie rule does for this edge)."""
    rows, cols = shape
    x0, y0 = vertices[:, 0], vertices[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    yc = np.arange(rows) + 0.5  # (R,)
    xc = np.arange(cols) + 0.5  # (C,)
    lo, hi = np.minimum(y0, y1), np.maximum(y0, y1)
    crosses = (yc[None, :] >= lo[:, None]) & (yc[None, :] < hi[:, None])  # (E, R): half-open in y
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (yc[None, :] - y0[:, None]) / (y1 - y0)[:, None]
    x_at = x0[:, None] + t * (x1 - x0)[:, None]  # (E, R)
    x_at = np.where(crosses, x_at, np.inf)  # edges not crossing the row never count
    # A pixel is inside when an odd number of edge crossings lie at or left of its centre.
    count = (x_at[:, :, None] <= xc[None, None, :]).sum(axis=0)  # (R, C)
    return (count % 2) == 1


def render_cpu(geometry: Geometry, size: tuple[int, int]) -> np.ndarray:
    """Draw one frame on the CPU, without antialiasing: the GL renderer's oracle.

    Follows the same drawing order and masking (A1.2.2): holes open their mask group, pupils
    are drawn only inside their group, the face polygon everywhere except in holes, the rest
    everywhere. Colours are alpha-blended over the background.

    Returns
    -------
    ndarray of uint8, shape (height, width, 3)
    """
    width, height = size
    image = np.empty((height, width, 3))
    image[:] = geometry.background[:3]
    groups = np.zeros((height, width), dtype=np.int32)
    for poly in geometry.polygons:
        inside = rasterize_polygon(to_pixels(poly.vertices, geometry.viewbox, size), (height, width))
        if poly.kind == "hole":
            groups[inside] = poly.mask
        elif poly.kind == "pupil":
            inside &= groups == poly.mask
        elif poly.kind == "face":
            inside &= groups == 0
        alpha = poly.color[3]
        image[inside] = image[inside] * (1 - alpha) + np.asarray(poly.color[:3]) * alpha
    return np.clip(np.round(image * 255), 0, 255).astype(np.uint8)
