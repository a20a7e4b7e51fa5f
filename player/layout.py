"""A frame as four indices per primitive into its outline points, kept while the face's structure is.

A face's items keep their structure from frame to frame (which outlines, how many points each,
colours, widths, masks, which edges are drawn) while their points move. So per structure a
:class:`DrawLayout` is built once: every primitive of a frame as four indices into one array of
points, drawn as ``lines_adjacency`` through the renderer's geometry shader.

* A fill triangle is ``(a, b, c, marker)``: one triangle of the outline's triangulation.
* A stroke segment is ``(a, b, c, marker)``: the shader draws the quad of segment ``ab`` with butt
  ends and, when the next segment ``bc`` is drawn too, the miter or bevel join at ``b``
  (:func:`toon.curves.stroke_triangles`, the same triangles computed on the GPU); ``c = b`` where
  no drawn segment follows.

``marker`` is a point after all outline points that carries the primitive's colour, mask depth
and half stroke width (0 for fills). Per frame only the outline points change, so only they are
uploaded; a kept triangulation is re-used while every one of its triangles keeps the orientation
it had against the outline when made (for a simple outline that proves it still tiles it), so most
frames triangulate nothing and the index buffer stays as it is.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, replace

import mapbox_earcut
import numpy as np

from toon import DrawItem, Geometry

#: Indices per primitive (``lines_adjacency``).
CORNERS = 4
#: Attributes per point: ``r, g, b, a``, mask depth, half stroke width (only markers carry them).
ATTRIBUTES = 6
#: Depth of the cleared depth buffer: drawn where no hole is.
CLEAR_DEPTH = 1.0
#: Layouts kept per planner (one per structure seen: visibility switches change the structure).
KEPT_LAYOUTS = 8
#: A run's state that draws an image component's picture (``"picture K"``, K its item's index).
PICTURE = "picture"


def mask_depth(group: int) -> float:
    """Depth written by the holes of mask group ``group`` (1, 2, 3, ...); 1.0 means no hole."""
    return group / 16.0


def triangulate(vertices: np.ndarray) -> np.ndarray:
    """Triangle corner indices of a simple polygon ``(N, 2)``; shape ``(3 * T,)``."""
    return mapbox_earcut.triangulate_float64(np.ascontiguousarray(vertices, dtype=np.float64),
                                             np.array([len(vertices)], dtype=np.uint32))


class Triangulator:
    """Fill triangulations of a face's items, kept by item key from frame to frame.

    A kept triangulation is re-used while the outline has the same number of vertices and every
    one of its triangles keeps the orientation it had against the outline when it was made (earcut
    emits a clockwise outline's triangles counter-clockwise): index triangles that tile an N-gon
    tile any simple N-gon whose vertices leave them all so oriented (their winding numbers add up
    to the outline's). :meth:`DrawLayout.stale_fills` runs the check on a whole frame at once.
    """

    def __init__(self) -> None:
        self._cache: dict[int, tuple[int, np.ndarray, float]] = {}
        self.reused = 0
        self.computed = 0

    def get(self, item: DrawItem) -> tuple[np.ndarray, float]:
        """``item``'s kept triangulation ``(3T,)`` and its winding relation, made if none fits."""
        known = self._cache.get(item.key)
        if known is None or known[0] != len(item.vertices) or not len(known[1]):
            return self.compute(item)
        return known[1], known[2]

    def compute(self, item: DrawItem) -> tuple[np.ndarray, float]:
        """Triangulate ``item``'s outline afresh and keep the result (and its winding relation)."""
        indices = triangulate(item.vertices).astype(np.int64)
        relation = _winding_relation(item.vertices, indices)
        self._cache[item.key] = (len(item.vertices), indices, relation)
        self.computed += 1
        return indices, relation


def _winding_relation(outline: np.ndarray, indices: np.ndarray) -> float:
    """+1 if the triangles ``indices`` of ``outline`` (N, 2) wind as it does, -1 if against it."""
    if not len(indices):
        return 1.0
    x, y = outline[:, 0], outline[:, 1]
    area = np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    return 1.0 if np.sum(_triangle_cross(outline[indices])) * area >= 0 else -1.0


def _triangle_cross(corners: np.ndarray) -> np.ndarray:
    """Twice the signed area of each triangle of ``corners`` ``(3T, 2)``; shape ``(T,)``."""
    tris = corners.reshape(-1, 3, 2)
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    return e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]


def structure_of(geometry: Geometry) -> tuple:
    """What a layout depends on: every item's key, point count, colours, width, closure and masks."""
    return tuple((it.key, len(it.vertices), it.fill, it.stroke, it.width, it.closed, it.mask_write,
                  it.mask_test, None if it.edge_visible is None else it.edge_visible.tobytes(),
                  None if it.picture is None else id(it.picture))
                 for it in geometry.items)


@dataclass(frozen=True)
class _FillCheck:
    """The kept triangulations of a layout, arranged to be checked in one pass."""

    items: np.ndarray  # (C,) item index of each checked fill
    triangles: np.ndarray  # (F,) primitive rows of their triangles, grouped by fill
    first_triangle: np.ndarray  # (C,) where each fill's triangles start in ``triangles``
    ring: np.ndarray  # (R,) point indices of the checked outlines, one after another
    ring_next: np.ndarray  # (R,) the point that follows each in its outline
    ring_starts: np.ndarray  # (C,)
    relation: np.ndarray  # (C,) +1 / -1: see :class:`Triangulator`
    untiled: np.ndarray  # item indices of fills whose triangulation came out empty (degenerate)
    owner: np.ndarray  # (F,) which checked fill each triangle belongs to
    corners: np.ndarray  # (3, F) point indices of each triangle's corners


@dataclass(frozen=True)
class DrawLayout:
    """Index and attribute data for frames of one structure.

    Attributes
    ----------
    structure : tuple
        :func:`structure_of` the geometry it was built for.
    points : int
        ``N``: outline points per frame (item after item); the markers follow them.
    item_starts : ndarray of int, shape (M,)
        Where each item's points start.
    attributes : ndarray of float32, shape (N + K, 6)
        Zero for outline points; colour, mask depth and half stroke width for the K markers.
    indices : ndarray of uint32, shape (P, 4)
        The frame's primitives in drawing order.
    runs : list of ((mode, blend), first, count)
        Consecutive primitives drawn with the same depth mode (``write``, ``test`` or ``none``) and
        the same need for blending (a colour that is not opaque).
    """

    structure: tuple
    points: int
    item_starts: np.ndarray
    attributes: np.ndarray
    indices: np.ndarray
    runs: list[tuple[tuple[str, bool], int, int]]
    fills: _FillCheck

    def fill_corners(self, points: np.ndarray) -> np.ndarray:
        """Every fill triangle's corners at ``points`` ``(N, 2)``, in drawing order; shape ``(3F, 2)``."""
        return points[self.indices[self.fills.triangles, :3].ravel()]

    def stale_fills(self, points: np.ndarray) -> np.ndarray:
        """Item indices whose kept triangulation no longer tiles their outline at ``points`` ``(N, 2)``,
        and those of degenerate outlines that had none (tried again every frame)."""
        check = self.fills
        if not len(check.items):
            return check.untiled
        x, y = np.ascontiguousarray(points.T)
        area = np.add.reduceat(x[check.ring] * y[check.ring_next] - x[check.ring_next] * y[check.ring],
                               check.ring_starts)
        a, b, c = check.corners
        xa, ya = x[a], y[a]
        cross = (x[b] - xa) * (y[c] - ya) - (y[b] - ya) * (x[c] - xa)
        good = cross * (np.sign(area) * check.relation)[check.owner] > 0
        valid = np.minimum.reduceat(good, check.first_triangle) & (np.abs(area) > 1e-9)
        return np.concatenate([check.items[~valid], check.untiled])

    def refilled(self, fresh: dict[int, tuple[np.ndarray, float]]) -> DrawLayout | None:
        """This layout with the new triangulations ``fresh`` (item index -> indices, relation) in
        place of the kept ones; ``None`` where one has another triangle count (build it again).

        A re-triangulated outline almost always keeps its ``N - 2`` triangles, so the usual change
        is a copy of the index array with those rows replaced, not a new layout.
        """
        check = self.fills
        if any(len(fresh[k][0]) for k in check.untiled if k in fresh):
            return None
        changed = [k for k in fresh if k not in check.untiled]
        if not changed:
            return self
        indices, relation = self.indices.copy(), check.relation.copy()
        ends = np.append(check.first_triangle[1:], len(check.triangles))
        for k in changed:
            c = int(np.searchsorted(check.items, k))
            rows = check.triangles[check.first_triangle[c]:ends[c]]
            triangles, relation[c] = fresh[k]
            if len(triangles) != 3 * len(rows):
                return None
            indices[rows, :3] = triangles.reshape(-1, 3) + self.item_starts[k]
        return replace(self, indices=indices,
                       fills=replace(check, relation=relation, corners=indices[check.triangles, :3].T.astype(np.int64)))


def _mode(item: DrawItem, stroke: bool) -> str:
    if item.mask_write and not stroke:
        return "write"
    return "none" if item.mask_test is None else "test"


def build_layout(geometry: Geometry, triangulator: Triangulator) -> DrawLayout:
    """The layout of ``geometry``'s structure, with fills triangulated by ``triangulator``."""
    items = geometry.items
    sizes = np.array([len(it.vertices) for it in items], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    n_points = int(sizes.sum())
    rows: list[np.ndarray] = []
    markers: list[tuple[float, ...]] = []
    modes: list[tuple[str, bool]] = []
    fills: dict[str, list] = {"items": [], "rows": [], "rings": [], "relation": [], "untiled": []}
    count = 0
    for k, item in enumerate(items):
        begin = int(starts[k])
        parts: list[tuple[np.ndarray, tuple[float, float, float, float], float, bool]] = []
        if item.fill is not None and item.closed and len(item.vertices) >= 3:
            indices, relation = triangulator.get(item)
            if len(indices):
                parts.append((indices.reshape(-1, 3) + begin, item.fill, 0.0, False))
                fills["items"].append(k)
                fills["rows"].append(np.arange(count, count + len(indices) // 3))
                fills["rings"].append(np.arange(begin, begin + len(item.vertices)))
                fills["relation"].append(relation)
            else:
                fills["untiled"].append(k)
        if item.stroke is not None and item.width > 0 and len(item.vertices) >= 2:
            segments = _segments(len(item.vertices), item.closed, item.edge_visible) + begin
            if len(segments):
                parts.append((segments, item.stroke, item.width / 2, True))
        if item.picture is not None and len(item.vertices) == 4:  # a run of its own, drawn with its texture
            rows.append(np.empty((0, CORNERS), dtype=np.int64))
            modes.append((f"{PICTURE} {k}", True))
        for corners, color, half_width, stroke in parts:
            mode = _mode(item, stroke)
            group = item.mask_write if mode == "write" else (item.mask_test or 0)
            marker = np.full((len(corners), 1), n_points + len(markers), dtype=np.int64)
            rows.append(np.hstack([corners, marker]))
            markers.append((*color, mask_depth(group) if group else CLEAR_DEPTH, half_width))
            modes.append((mode, color[3] < 1.0))
            count += len(corners)
    indices = np.concatenate(rows).astype(np.uint32) if rows else np.empty((0, CORNERS), dtype=np.uint32)
    attributes = np.zeros((n_points + len(markers), ATTRIBUTES), dtype=np.float32)
    if markers:
        attributes[n_points:] = markers
    runs = _runs(modes, [len(r) for r in rows])
    return DrawLayout(structure_of(geometry), n_points, starts, attributes, indices, runs, _fill_check(fills, indices))


def _segments(n: int, closed: bool, edge_visible: np.ndarray | None) -> np.ndarray:
    """Drawn segments of an outline of ``n`` points as ``(a, b, c)`` rows; ``c = b`` where no drawn
    segment follows. Shape ``(S, 3)``.

    >>> _segments(4, False, np.array([True, False, True])).tolist()
    [[0, 1, 1], [2, 3, 3]]
    >>> _segments(3, True, None).tolist()
    [[0, 1, 2], [1, 2, 0], [2, 0, 1]]
    """
    m = n if closed else n - 1
    shown = np.ones(m, dtype=bool) if edge_visible is None else np.asarray(edge_visible, dtype=bool)[:m]
    i = np.arange(m)
    following = (i + 1) % m if closed else i + 1
    joined = following < m
    joined[joined] &= shown[following[joined]]
    a, b = i, (i + 1) % n
    c = np.where(joined, (i + 2) % n, b)
    return np.column_stack([a, b, c])[shown]


def _runs(modes: list[tuple[str, bool]], counts: list[int]) -> list[tuple[tuple[str, bool], int, int]]:
    """Merge consecutive parts that share a draw state into ``(state, first, count)`` runs."""
    runs: list[tuple[tuple[str, bool], int, int]] = []
    start = 0
    for mode, count in zip(modes, counts, strict=True):
        if runs and runs[-1][0] == mode:
            runs[-1] = (mode, runs[-1][1], runs[-1][2] + count)
        else:
            runs.append((mode, start, count))
        start += count
    return runs


def _fill_check(fills: dict[str, list], indices: np.ndarray) -> _FillCheck:
    untiled = np.array(fills["untiled"], dtype=np.int64)
    if not fills["items"]:
        empty = np.empty(0, dtype=np.int64)
        return _FillCheck(empty, empty, empty, empty, empty, empty, np.empty(0), untiled, empty,
                          np.empty((3, 0), dtype=np.int64))
    rings = fills["rings"]
    ring = np.concatenate(rings)
    ring_sizes = np.array([len(r) for r in rings])
    ring_starts = np.concatenate([[0], np.cumsum(ring_sizes)[:-1]])
    ring_next = np.concatenate([np.roll(r, -1) for r in rings])
    triangle_counts = np.array([len(r) for r in fills["rows"]])
    triangles = np.concatenate(fills["rows"])
    return _FillCheck(np.array(fills["items"], dtype=np.int64), triangles,
                      np.concatenate([[0], np.cumsum(triangle_counts)[:-1]]), ring, ring_next, ring_starts,
                      np.array(fills["relation"]), untiled, np.repeat(np.arange(len(triangle_counts)), triangle_counts),
                      indices[triangles, :3].T.astype(np.int64))


class FramePlanner:
    """Layouts by structure, and the triangulations in them, from frame to frame.

    :meth:`plan` gives each frame its layout and its points; a layout is rebuilt only when the
    structure is new or a kept triangulation stopped tiling its outline.
    """

    def __init__(self) -> None:
        self.triangulator = Triangulator()
        self._layouts: OrderedDict[tuple, DrawLayout] = OrderedDict()

    def plan(self, geometry: Geometry) -> tuple[DrawLayout, np.ndarray]:
        """The layout for ``geometry`` and its outline points, float64 of shape ``(N, 2)``.

        Every frame's fills are checked against its points, a new layout's too: it may take
        triangulations kept from another structure (an item hidden or shown since).
        """
        structure = structure_of(geometry)
        items = geometry.items
        points = np.concatenate([it.vertices for it in items]) if items else np.empty((0, 2))
        layout = self._layouts.get(structure)
        made = 0  # fills triangulated afresh for this frame's layout: checked, but not re-used
        if layout is None:
            before = self.triangulator.computed
            layout = build_layout(geometry, self.triangulator)
            made = self.triangulator.computed - before - len(layout.fills.untiled)  # untiled: always made
        else:
            self._layouts.move_to_end(structure)
        stale = layout.stale_fills(points)
        self.triangulator.reused += len(layout.fills.items) - (len(stale) - len(layout.fills.untiled)) - made
        if len(stale):
            fresh = {int(k): self.triangulator.compute(items[k]) for k in stale}
            layout = layout.refilled(fresh) or build_layout(geometry, self.triangulator)
        self._layouts[structure] = layout
        while len(self._layouts) > KEPT_LAYOUTS:
            self._layouts.popitem(last=False)
        return layout, points
