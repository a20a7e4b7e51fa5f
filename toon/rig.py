"""Motor values to drawable geometry: ToonFace's interpolation (A1.1-A1.6) and head turns.

Feature-attached vertices (A1.1-A1.4). Each vertex is bound, at the rest pose, to the line ``L``
between two consecutive control points of its feature, ``(h0, v0)`` and ``(h1, v1)``: the one
whose span is nearest to the vertex. The binding keeps ``vrl``, the vertex's relative horizontal
position between ``h0`` and ``h1``, and ``d``, its vertical distance from ``L``. When the points
move, ``SL = (v1 - v0) / (h1 - h0)`` (A1.1), ``IYL = v0 - SL * h0`` (A1.2),
``X = h0 + vrl * (h1 - h0)`` (A1.3) and ``Y = X * SL + IYL + d`` (A1.4). A line that is vertical
at rest cannot carry a binding (A1.1 divides by ``h1 - h0``); vertices go to the other lines.

Point-attached vertices (A1.5-A1.6): ``V = V_min + P_CTRL * (V_max - V_min)``.

Head turns (HH, HV). A 2-D face has no 3-D head, so each polygon is given a depth ``z`` in front
of the outline (the face's ``feature_depth`` for holes, pupils, point- and feature-attached
polygons; 0 for the face polygon and free polygons, unless a polygon sets its own). Polygons at
depth 0 are the silhouette of a roughly round head, which a turn does not change: they stay put.
Every vertex ``(x, y, z)`` of the others is turned about the head's pivot by the pitch (HV, chin
up positive) and then the yaw (HH, toward the character's left positive) and projected
orthographically, so features slide across the outline by ``z * sin(angle)`` and narrow by
``cos(angle)``: the parallax that makes a flat drawing read as a turning head.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common import InputError
from toon.face import FEATURES, HOLE_FEATURES, KINDS, PUPIL_EYES, Face, PolygonSpec
from toon.motors import MOTORS, N_MOTORS, motor_index

#: Mask groups: holes write their group, pupils draw only inside their eye's group.
MASK_GROUPS: dict[str, int] = {name: i + 1 for i, name in enumerate(HOLE_FEATURES)}


@dataclass(frozen=True)
class DrawPolygon:
    """A polygon ready to fill.

    Attributes
    ----------
    vertices : ndarray, shape (N, 2)
        Face units, y up.
    color : tuple of 4 float
        RGBA in ``[0, 1]``.
    kind : str
        Its drawing step (A1.2.2).
    mask : int
        For holes, the mask group they open; for pupils, the group they are clipped to; else 0.
    """

    vertices: np.ndarray
    color: tuple[float, float, float, float]
    kind: str
    mask: int = 0


@dataclass(frozen=True)
class Geometry:
    """One frame of a face: polygons in drawing order plus the view."""

    polygons: tuple[DrawPolygon, ...]
    viewbox: tuple[float, float, float, float]
    background: tuple[float, float, float, float]

    @property
    def vertex_count(self) -> int:
        """Total polygon vertices."""
        return sum(len(p.vertices) for p in self.polygons)


@dataclass(frozen=True)
class _FeatureBinding:
    """Per-vertex line bindings: start/end control-point indices, ``vrl`` and ``d``, each (N,)."""

    start: np.ndarray
    end: np.ndarray
    vrl: np.ndarray
    d: np.ndarray


def bind_to_lines(vertices: np.ndarray, line_points: np.ndarray, closed: bool) -> _FeatureBinding:
    """Bind vertices to the lines between consecutive control points (A1.3-A1.4 inverted).

    Parameters
    ----------
    vertices : ndarray, shape (N, 2)
    line_points : ndarray, shape (K, 2)
        The feature's control points at rest, in line order, ``K >= 2``.
    closed : bool
        Whether a line also joins the last point to the first.
    """
    k = len(line_points)
    starts = np.arange(k if closed else k - 1)
    ends = (starts + 1) % k
    h0, v0 = line_points[starts, 0], line_points[starts, 1]
    h1, v1 = line_points[ends, 0], line_points[ends, 1]
    dh = h1 - h0
    usable = np.abs(dh) > 1e-9
    if not usable.any():
        raise ValueError("every line of the feature is vertical; A1.1 needs h1 != h0")
    safe = np.where(usable, dh, 1.0)
    x, y = vertices[:, :1], vertices[:, 1:]  # (N, 1) against lines (L,)
    vrl = (x - h0) / safe
    slope = (v1 - v0) / safe
    d = y - (slope * x + (v0 - slope * h0))
    outside = np.maximum(0.0, np.maximum(-vrl, vrl - 1.0)) * np.abs(safe)
    cost = np.where(usable, np.hypot(outside, d), np.inf)
    best = np.argmin(cost, axis=1)
    rows = np.arange(len(vertices))
    return _FeatureBinding(starts[best], ends[best], vrl[rows, best], d[rows, best])


def follow_lines(binding: _FeatureBinding, line_points: np.ndarray) -> np.ndarray:
    """Vertex positions for moved control points (A1.1-A1.4), shape ``(N, 2)``."""
    h0, v0 = line_points[binding.start, 0], line_points[binding.start, 1]
    h1, v1 = line_points[binding.end, 0], line_points[binding.end, 1]
    dh = np.where(np.abs(h1 - h0) > 1e-9, h1 - h0, 1e-9)
    slope = (v1 - v0) / dh  # A1.1
    intercept = v0 - slope * h0  # A1.2
    x = h0 + binding.vrl * (h1 - h0)  # A1.3
    y = x * slope + intercept + binding.d  # A1.4
    return np.column_stack([x, y])


def interpolate_states(v_min: np.ndarray, v_max: np.ndarray, p_ctrl: float) -> np.ndarray:
    """Point-attached polygon vertices (A1.5-A1.6), shape ``(N, 2)``."""
    return v_min + p_ctrl * (v_max - v_min)


def head_turn(vertices: np.ndarray, depth: float, pivot: np.ndarray, yaw_deg: float,
              pitch_deg: float) -> np.ndarray:
    """Turn vertices standing ``depth`` in front of the outline about ``pivot``; ``(N, 2)``."""
    yaw, pitch = np.radians(yaw_deg), np.radians(pitch_deg)
    x, y = vertices[:, 0] - pivot[0], vertices[:, 1] - pivot[1]
    y2 = y * np.cos(pitch) + depth * np.sin(pitch)
    z2 = -y * np.sin(pitch) + depth * np.cos(pitch)
    x2 = x * np.cos(yaw) + z2 * np.sin(yaw)
    return np.column_stack([x2 + pivot[0], y2 + pivot[1]])


@dataclass(frozen=True)
class _Prepared:
    """A polygon's rest vertices plus what moves them."""

    spec: PolygonSpec
    rest: np.ndarray
    depth: float
    mask: int
    line_rows: np.ndarray | None
    binding: _FeatureBinding | None
    v_max: np.ndarray | None


class FaceRig:
    """A face prepared for animation: bindings computed once, then :meth:`geometry` per frame.

    Parameters
    ----------
    face : Face
    """

    def __init__(self, face: Face) -> None:
        self.face = face
        self._point_names = tuple(face.points)
        self._rest = np.array([face.points[n] for n in self._point_names], dtype=np.float64)
        self._index = {n: i for i, n in enumerate(self._point_names)}
        self._driven = [(motor_index(m.code), self._index[m.point], 0 if m.axis == "x" else 1,
                         *face.ranges[m.code]) for m in MOTORS if m.point != "HEAD"]
        self._head = [face.ranges["HH"], face.ranges["HV"]]
        self._pivot = np.array(face.head_pivot)
        order = sorted(range(len(face.polygons)), key=lambda i: KINDS.index(face.polygons[i].kind))  # stable
        self._polygons = [self._prepare(face.polygons[i], i) for i in order]

    def control_points(self, values: np.ndarray) -> np.ndarray:
        """Control-point positions for one frame of motor values ``(21,)``; shape ``(P, 2)``."""
        pts = self._rest.copy()
        for col, row, axis, lo, hi in self._driven:
            pts[row, axis] = lo + values[col] * (hi - lo)
        return pts

    def geometry(self, values: np.ndarray) -> Geometry:
        """The polygons of one frame, in drawing order, for motor values of shape ``(21,)``."""
        values = np.asarray(values, dtype=np.float64)
        if values.shape != (N_MOTORS,):
            raise ValueError(f"expected {N_MOTORS} motor values, got shape {values.shape}")
        pts = self.control_points(values)
        yaw = self._lerp(self._head[0], values[motor_index("HH")])
        pitch = self._lerp(self._head[1], values[motor_index("HV")])
        out = []
        for prep in self._polygons:
            spec = prep.spec
            if prep.binding is not None:
                verts = follow_lines(prep.binding, pts[prep.line_rows])
            elif spec.kind == "pupil":
                row = self._index[spec.point]
                verts = prep.rest + (pts[row] - self._rest[row])
            elif prep.v_max is not None:
                verts = interpolate_states(prep.rest, prep.v_max, values[motor_index(spec.motor)])
            else:
                verts = prep.rest
            if prep.depth and (yaw or pitch):
                verts = head_turn(verts, prep.depth, self._pivot, yaw, pitch)
            out.append(DrawPolygon(verts, spec.color, spec.kind, prep.mask))
        return Geometry(tuple(out), self.face.viewbox, self.face.background)

    @staticmethod
    def _lerp(bounds: tuple[float, float], value: float) -> float:
        return bounds[0] + value * (bounds[1] - bounds[0])

    def _prepare(self, spec: PolygonSpec, index: int) -> _Prepared:
        rest = np.array(spec.vertices, dtype=np.float64)
        flat = spec.kind in ("face", "free")
        depth = spec.depth if spec.depth is not None else (0.0 if flat else self.face.feature_depth)
        line_rows = binding = v_max = None
        mask = 0
        if spec.kind in ("hole", "feature"):
            names, closed = FEATURES[spec.feature]
            line_rows = np.array([self._index[n] for n in names])
            try:
                binding = bind_to_lines(rest, self._rest[line_rows], closed)
            except ValueError as exc:  # the face file is at fault, so say where
                raise InputError(f"feature {spec.feature}: {exc}", self.face.meta.get("source"),
                                 f"polygons[{index}].feature") from None
        if spec.kind == "hole":
            mask = MASK_GROUPS[spec.feature]
        elif spec.kind == "pupil":
            mask = MASK_GROUPS[PUPIL_EYES[spec.point]]
        elif spec.kind == "point":
            v_max = np.array(spec.vertices_max, dtype=np.float64)
        return _Prepared(spec, rest, depth, mask, line_rows, binding, v_max)
