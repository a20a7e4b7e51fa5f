"""CPU rasterisation: the reference the GL renderer is checked against, and view fitting."""

from __future__ import annotations

import numpy as np

from toon.curves import stroke_triangles
from toon.geometry import Geometry
from toon.images import pixel_affine


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


def rasterize_triangles(corners: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Pixels whose centres lie inside any of the triangles ``corners`` ``(3 * T, 2)`` (pixels)."""
    out = np.zeros(shape, dtype=bool)
    for tri in corners.reshape(-1, 3, 2):
        lo = np.maximum(np.floor(tri.min(axis=0) - 0.5).astype(int), 0)
        hi = np.minimum(np.ceil(tri.max(axis=0) + 0.5).astype(int), [shape[1], shape[0]])
        if (hi <= lo).any():
            continue
        local = rasterize_polygon(tri - lo, (hi[1] - lo[1], hi[0] - lo[0]))
        out[lo[1]:hi[1], lo[0]:hi[0]] |= local
    return out


def render_cpu(geometry: Geometry, size: tuple[int, int]) -> np.ndarray:
    """Draw one frame on the CPU, without antialiasing: the GL renderer's oracle.

    Follows the same drawing order and masking (A1.2.2): holes open their mask group, pupils
    and clipped components are drawn only inside their group, the face polygon everywhere except
    in holes, the rest everywhere. Fills use the even-odd rule; strokes are the triangles of
    :func:`toon.curves.stroke_triangles`. Colours are alpha-blended over the background.

    Returns
    -------
    ndarray of uint8, shape (height, width, 3)
    """
    width, height = size
    image = np.empty((height, width, 3))
    image[:] = geometry.background[:3]
    groups = np.zeros((height, width), dtype=np.int32)
    scale = fit_viewbox(geometry.viewbox, size)[0]
    for item in geometry.items:
        pixels = to_pixels(item.vertices, geometry.viewbox, size)
        allowed = np.ones((height, width), dtype=bool) if item.mask_test is None else groups == item.mask_test
        if item.fill is not None and item.closed:
            inside = rasterize_polygon(pixels, (height, width))
            if item.mask_write:
                groups[inside] = item.mask_write
            _blend(image, inside & allowed, item.fill)
        if item.stroke is not None and item.width > 0:
            corners = stroke_triangles(pixels, item.width * scale, item.closed, item.edge_visible)
            _blend(image, rasterize_triangles(corners, (height, width)) & allowed, item.stroke)
        if item.picture is not None and len(pixels) == 4:
            _picture(image, item.picture.pixels, pixels, allowed, item.opacity)
    return np.clip(np.round(image * 255), 0, 255).astype(np.uint8)


def _picture(image: np.ndarray, picture: np.ndarray, quad: np.ndarray, allowed: np.ndarray, opacity: float) -> None:
    """Blend ``picture`` (straight RGBA ``uint8`` ``(h, w, 4)``) over ``image`` where it lies:
    the parallelogram ``quad`` ``(4, 2)`` of output pixels (its corners: top-left, top-right,
    bottom-right, bottom-left), sampled bilinearly at each pixel's centre, its edges clamped."""
    h, w = picture.shape[:2]
    forward = np.vstack([pixel_affine(quad, (w, h)), [0.0, 0.0, 1.0]])
    if abs(np.linalg.det(forward[:2, :2])) < 1e-12:
        return  # the parallelogram has collapsed: nothing shows
    back = np.linalg.inv(forward)
    height, width = image.shape[:2]
    x0, y0 = np.maximum(np.floor(quad.min(axis=0)).astype(int), 0)
    x1, y1 = np.minimum(np.ceil(quad.max(axis=0)).astype(int), [width, height])
    if x0 >= x1 or y0 >= y1:
        return
    ys, xs = np.mgrid[y0:y1, x0:x1] + 0.5
    u = back[0, 0] * xs + back[0, 1] * ys + back[0, 2]
    v = back[1, 0] * xs + back[1, 1] * ys + back[1, 2]
    inside = (u >= 0) & (u < w) & (v >= 0) & (v < h) & allowed[y0:y1, x0:x1]
    fx, fy = np.clip(u - 0.5, 0, w - 1), np.clip(v - 0.5, 0, h - 1)
    ix, iy = np.minimum(fx.astype(int), w - 2 if w > 1 else 0), np.minimum(fy.astype(int), h - 2 if h > 1 else 0)
    tx, ty = (fx - ix)[..., None], (fy - iy)[..., None]
    rgba = picture.astype(float) / 255
    rgba[..., :3] *= rgba[..., 3:]  # premultiplied, as filtering needs
    right, down = np.minimum(ix + 1, w - 1), np.minimum(iy + 1, h - 1)
    sample = ((rgba[iy, ix] * (1 - tx) + rgba[iy, right] * tx) * (1 - ty)
              + (rgba[down, ix] * (1 - tx) + rgba[down, right] * tx) * ty) * opacity
    region = image[y0:y1, x0:x1]
    region[inside] = region[inside] * (1 - sample[inside][:, 3:]) + sample[inside][:, :3]


def _blend(image: np.ndarray, where: np.ndarray, color: tuple[float, float, float, float]) -> None:
    alpha = color[3]
    image[where] = image[where] * (1 - alpha) + np.asarray(color[:3]) * alpha
