"""Motor values to drawable geometry: ToonFace's interpolation (A1.1-A1.6) and head turns.

Feature-attached vertices (A1.1-A1.4). Each vertex is bound, at the rest pose, to the line ``L``
between two consecutive control points of its feature, ``(h0, v0)`` and ``(h1, v1)``: the one
whose span is nearest to the vertex. The binding keeps ``vrl``, the vertex's relative horizontal
position between ``h0`` and ``h1``, and ``d``, its vertical distance from ``L``. When the points
move, ``SL = (v1 - v0) / (h1 - h0)`` (A1.1), ``IYL = v0 - SL * h0`` (A1.2),
``X = h0 + vrl * (h1 - h0)`` (A1.3) and ``Y = X * SL + IYL + d`` (A1.4). A line that is vertical
at rest cannot carry a binding (A1.1 divides by ``h1 - h0``); vertices go to the other lines.

Point-attached vertices (A1.5-A1.6): ``V = V_min + P_CTRL * (V_max - V_min)``.

Pupils: a pupil's control point sits ``eyes.radius * sin(angle)`` from its rest position for the
gaze angles of its two motors, and its polygons narrow by ``cos(angle)`` about that point, as the
disc of a turning eyeball would.

Drawing order: background layers -10..-1 (CharToon components that never move), then A1.2.2's
six steps (holes, pupils, the face polygon minus the holes, free, point- and feature-attached
polygons), then foreground layers 1..10; file order within each. CharToon components (described
in :mod:`toon.components`) are evaluated here, with the couplings of :mod:`toon.skeleton` and the
outline operators of :mod:`toon.curves`.

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
from toon.components import Component
from toon.curves import ellipse_operator, outline_operator
from toon.face import ANGLE_MOTORS, FEATURES, HOLE_FEATURES, KINDS, PUPIL_EYES, Face, PolygonSpec
from toon.formulas import FeatureBinding, bind_to_lines, follow_lines, head_turn, interpolate_states
from toon.motors import MOTORS, N_MOTORS, motor_index
from toon.skeleton import EdgeCoupling, PointCoupling, bind_edge_skeleton, bind_point_skeleton
from toon.validate import Color

#: Mask groups: holes write their group; pupils and clipped components draw only inside it.
MASK_GROUPS: dict[str, int] = {name: i + 1 for i, name in enumerate(HOLE_FEATURES)}


@dataclass(frozen=True)
class DrawItem:
    """One thing to draw: an outline, filled and/or stroked.

    Attributes
    ----------
    vertices : ndarray, shape (N, 2)
        The outline in face units, y up.
    fill, stroke : RGBA tuple or None
        Colours in ``[0, 1]``; ``None`` draws no fill or no stroke.
    width : float
        Stroke width in face units.
    closed : bool
        Whether the outline closes (only closed outlines are filled).
    edge_visible : ndarray of bool or None
        Per stroked edge (``N`` closed, ``N - 1`` open), whether it is drawn; ``None``: all.
    kind : str
        Its A1.2.2 step (``hole``, ``pupil``, ``face``, ``free``, ``point``, ``feature``) or
        ``component``.
    mask_write : int
        Mask group a hole opens (0: none).
    mask_test : int or None
        Draw only where the mask is this group (0: where no hole is); ``None``: everywhere.
    key : int
        The item's place in its face's drawing order, stable from frame to frame.
    name : str
    """

    vertices: np.ndarray
    fill: Color | None
    stroke: Color | None = None
    width: float = 0.0
    closed: bool = True
    edge_visible: np.ndarray | None = None
    kind: str = "free"
    mask_write: int = 0
    mask_test: int | None = None
    key: int = 0
    name: str = ""

    def with_vertices(self, vertices: np.ndarray) -> DrawItem:
        """The same item at ``vertices`` (shape of :attr:`vertices`); a field-by-field copy is
        several times faster than :func:`dataclasses.replace`, which matters per frame."""
        return DrawItem(vertices, self.fill, self.stroke, self.width, self.closed, self.edge_visible,
                        self.kind, self.mask_write, self.mask_test, self.key, self.name)


@dataclass(frozen=True)
class Geometry:
    """One frame of a face: items in drawing order plus the view."""

    items: tuple[DrawItem, ...]
    viewbox: tuple[float, float, float, float]
    background: Color


@dataclass(frozen=True)
class _Polygon:
    """A ToonFace polygon's rest vertices plus what moves it."""

    spec: PolygonSpec
    rest: np.ndarray
    depth: float
    mask_write: int
    mask_test: int | None
    line_rows: np.ndarray | None = None
    binding: FeatureBinding | None = None
    v_max: np.ndarray | None = None
    pupil_row: int = -1


@dataclass(frozen=True)
class _Component:
    """A basic CharToon component bound for animation (see :mod:`toon.components`)."""

    spec: Component
    rows: np.ndarray  # (N,) control-point row per defining point; -1 for frozen and fixed points
    offset: np.ndarray  # (N, 2) added to that row's position (or to zero)
    depth: float
    mask_write: int
    mask_test: int | None
    operator: np.ndarray | None  # (S, N) outline operator; None: the points themselves
    edge_visible: np.ndarray | None
    body_rest: np.ndarray | None = None
    skeleton_rest: np.ndarray | None = None
    coupling: PointCoupling | EdgeCoupling | None = None


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
                         *face.ranges[m.code]) for m in MOTORS if m.code not in ANGLE_MOTORS]
        self._head = [face.ranges["HH"], face.ranges["HV"]]
        self._pivot = np.array(face.head_pivot)
        order = sorted(range(len(face.polygons)), key=lambda i: KINDS.index(face.polygons[i].kind))  # stable
        polygons = [self._prepare_polygon(face.polygons[i], i) for i in order]
        components = [self._prepare_component(c, i) for i, c in enumerate(face.basic_components())]
        back = sorted((c for c in components if c.spec.layer < 0), key=lambda c: c.spec.layer)
        front = sorted((c for c in components if c.spec.layer > 0), key=lambda c: c.spec.layer)
        self._order: list[_Polygon | _Component] = [*back, *polygons, *front]
        self._depths = np.array([prep.depth for prep in self._order])
        # Every feature-attached vertex of the face in one binding, on control-point rows, so that
        # A1.1-A1.4 run once per frame for all of them; each polygon keeps its slice.
        self._line_slices: dict[int, slice] = {}
        parts, start = [], 0
        for key, prep in enumerate(self._order):
            if isinstance(prep, _Polygon) and prep.binding is not None:
                b = prep.binding
                parts.append(FeatureBinding(prep.line_rows[b.start], prep.line_rows[b.end], b.vrl, b.d))
                self._line_slices[key] = slice(start, start + len(b.vrl))
                start += len(b.vrl)
        self._all_lines = FeatureBinding(*(np.concatenate([getattr(p, f) for p in parts])
                                            for f in ("start", "end", "vrl", "d"))) if parts else None

    def control_points(self, values: np.ndarray) -> np.ndarray:
        """Control-point positions for one frame of motor values ``(21,)``; shape ``(P, 2)``."""
        pts = self._rest.copy()
        for col, row, axis, lo, hi in self._driven:
            pts[row, axis] = lo + values[col] * (hi - lo)
        for point in PUPIL_EYES:
            pts[self._index[point]] += self.face.eye_radius * np.sin(np.radians(self.gaze_degrees(values, point)))
        return pts

    def gaze_degrees(self, values: np.ndarray, point: str) -> np.ndarray:
        """Horizontal and vertical gaze angles of pupil ``point`` (PR or PL) in degrees, shape ``(2,)``."""
        side = "R" if point == "PR" else "L"
        return np.array([self._lerp(self.face.ranges[f"P{side}{a}"], values[motor_index(f"P{side}{a}")])
                         for a in "HV"])

    def geometry(self, values: np.ndarray) -> Geometry:
        """The items of one frame, in drawing order, for motor values of shape ``(21,)``."""
        values = np.asarray(values, dtype=np.float64)
        if values.shape != (N_MOTORS,):
            raise ValueError(f"expected {N_MOTORS} motor values, got shape {values.shape}")
        pts = self.control_points(values)
        moved = np.vstack([pts, np.zeros((1, 2))])  # row -1: the origin, for frozen and fixed points
        yaw = self._lerp(self._head[0], values[motor_index("HH")])
        pitch = self._lerp(self._head[1], values[motor_index("HV")])
        squash = {p: np.cos(np.radians(self.gaze_degrees(values, p))) for p in PUPIL_EYES}
        lines = follow_lines(self._all_lines, pts) if self._all_lines is not None else None
        out = []
        for key, prep in enumerate(self._order):
            if isinstance(prep, _Polygon):
                item = self._polygon_item(prep, pts, values, squash, key, lines)
            else:
                item = self._component_item(prep, moved, values, key)
                if item is None:
                    continue
            out.append(item)
        if yaw or pitch:
            out = self._turned(out, yaw, pitch)
        return Geometry(tuple(out), self.face.viewbox, self.face.background)

    def _turned(self, items: list[DrawItem], yaw: float, pitch: float) -> list[DrawItem]:
        """Items with every vertex standing in front of the outline turned (one vectorised pass)."""
        moving = [i for i, item in enumerate(items) if self._depths[item.key]]
        if not moving:
            return items
        counts = [len(items[i].vertices) for i in moving]
        stacked = np.concatenate([items[i].vertices for i in moving])
        depth = np.repeat(self._depths[[items[i].key for i in moving]], counts)
        turned = np.split(head_turn(stacked, depth, self._pivot, yaw, pitch), np.cumsum(counts)[:-1])
        out = list(items)
        for i, verts in zip(moving, turned):
            out[i] = items[i].with_vertices(verts)
        return out

    def _polygon_item(self, prep: _Polygon, pts: np.ndarray, values: np.ndarray,
                      squash: dict[str, np.ndarray], key: int, lines: np.ndarray | None) -> DrawItem:
        spec = prep.spec
        if prep.binding is not None:
            verts = lines[self._line_slices[key]]  # type: ignore[index]
        elif prep.pupil_row >= 0:
            centre = self._rest[prep.pupil_row]
            verts = centre + (prep.rest - centre) * squash[spec.attach] + (pts[prep.pupil_row] - centre)
        elif prep.v_max is not None:
            verts = interpolate_states(prep.rest, prep.v_max, values[motor_index(spec.attach)])
        else:
            verts = prep.rest
        return DrawItem(verts, spec.color, spec.stroke, spec.width, True, None, spec.kind, prep.mask_write,
                        prep.mask_test, key, spec.name)

    def _component_item(self, prep: _Component, moved: np.ndarray, values: np.ndarray, key: int
                        ) -> DrawItem | None:
        spec = prep.spec
        if spec.visible is not None:
            v = values[motor_index(spec.visible.motor)]
            if not spec.visible.low <= v <= spec.visible.high:
                return None
        pts = moved[prep.rows] + prep.offset
        if prep.coupling is not None:
            pts = prep.coupling.apply(prep.body_rest, prep.skeleton_rest, pts)
        if prep.operator is not None:
            pts = prep.operator @ pts
        if spec.scale is not None:
            factor = np.asarray(spec.scale.at0) + values[motor_index(spec.scale.motor)] * (
                np.asarray(spec.scale.at1) - spec.scale.at0)
            pts = np.asarray(spec.scale.origin) + (pts - spec.scale.origin) * factor
        if spec.translate is not None:
            pts = pts + np.asarray(spec.translate.at0) + values[motor_index(spec.translate.motor)] * (
                np.asarray(spec.translate.at1) - spec.translate.at0)
        return DrawItem(pts, spec.fill, spec.stroke, spec.width, spec.closed, prep.edge_visible, "component",
                        prep.mask_write, prep.mask_test, key, spec.name)

    @staticmethod
    def _lerp(bounds: tuple[float, float], value: float) -> float:
        return bounds[0] + value * (bounds[1] - bounds[0])

    def _prepare_polygon(self, spec: PolygonSpec, index: int) -> _Polygon:
        rest = np.array(spec.vertices, dtype=np.float64)
        flat = spec.kind in ("face", "free")
        depth = spec.depth if spec.depth is not None else (0.0 if flat else self.face.feature_depth)
        extra: dict = {}
        mask_write, mask_test = 0, None
        if spec.kind in ("hole", "feature"):
            names, closed = FEATURES[spec.attach]
            line_rows = np.array([self._index[n] for n in names])
            try:
                extra["binding"] = bind_to_lines(rest, self._rest[line_rows], closed)
            except ValueError as exc:  # the face file is at fault, so say where
                raise InputError(f"feature {spec.attach}: {exc}", self.face.meta.get("source"),
                                 f"polygons[{index}].attach") from None
            extra["line_rows"] = line_rows
        if spec.kind == "hole":
            mask_write = MASK_GROUPS[spec.attach]
        elif spec.kind == "pupil":
            mask_test = MASK_GROUPS[PUPIL_EYES[spec.attach]]
            extra["pupil_row"] = self._index[spec.attach]
        elif spec.kind == "face":
            mask_test = 0
        elif spec.kind == "point":
            extra["v_max"] = np.array(spec.vertices_max, dtype=np.float64)
        return _Polygon(spec, rest, depth, mask_write, mask_test, **extra)

    def _prepare_component(self, spec: Component, index: int) -> _Component:
        refs = spec.points
        rows = np.array([self._index[p.master] if p.animated else -1 for p in refs], dtype=np.int64)
        at = np.array([p.at for p in refs], dtype=np.float64).reshape(-1, 2)
        masters = self._rest[np.maximum(rows, 0)]
        offset = np.where((rows >= 0)[:, None], np.where(np.array([p.kind == "slave" for p in refs])[:, None],
                                                          at - masters, 0.0), at)
        rest_pts = np.where((rows >= 0)[:, None], masters, 0.0) + offset
        extra: dict = {}
        outline_rest = rest_pts
        if spec.kind == "skeleton":
            body = np.array([p.at for p in spec.body], dtype=np.float64)
            fixed = np.array([p.kind == "fixed" for p in spec.body])
            if spec.coupling == "point":
                coupling: PointCoupling | EdgeCoupling = bind_point_skeleton(body, rest_pts, fixed, rows >= 0)
            else:
                try:
                    coupling = bind_edge_skeleton(body, rest_pts, fixed, spec.skeleton_closed)
                except ValueError as exc:
                    raise InputError(str(exc), self.face.meta.get("source"), f"components[{index}].skeleton") from None
            extra = {"body_rest": body, "skeleton_rest": rest_pts, "coupling": coupling}
            outline_rest = body
        if spec.kind == "ellipse":
            operator: np.ndarray | None = ellipse_operator()
            edges = np.zeros(len(operator), dtype=np.int64)
        else:
            operator, edges = outline_operator(outline_rest, spec.closed, spec.smooth)
            if not spec.smooth:
                operator = None
        edge_visible = ~np.isin(edges, spec.hidden) if spec.hidden else None
        animated = spec.animated and spec.layer > 0
        depth = 0.0 if spec.layer < 0 else (spec.depth if spec.depth is not None
                                            else (self.face.feature_depth if animated else 0.0))
        mask_write = MASK_GROUPS[spec.hole] if spec.hole else 0
        mask_test = MASK_GROUPS[spec.clip] if spec.clip else None
        return _Component(spec, rows, offset, depth, mask_write, mask_test, operator, edge_visible, **extra)
