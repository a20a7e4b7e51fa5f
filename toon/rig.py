"""Motor values to drawable geometry: ToonFace's interpolation (A1.1-A1.6) and head turns.

Feature-attached vertices (A1.1-A1.4). Each vertex is bound, at the rest pose, to the line ``L``
between two consecutive control points of its feature, ``(h0, v0)`` and ``(h1, v1)``: the one
whose span is nearest to the vertex. The binding keeps ``vrl``, the vertex's relative horizontal
position between ``h0`` and ``h1``, and ``d``, its vertical distance from ``L``. When the points
move, ``SL = (v1 - v0) / (h1 - h0)`` (A1.1), ``IYL = v0 - SL * h0`` (A1.2),
``X = h0 + vrl * (h1 - h0)`` (A1.3) and ``Y = X * SL + IYL + d`` (A1.4). A line that is vertical
at rest cannot carry a binding (A1.1 divides by ``h1 - h0``); vertices go to the other lines.

Eyes and mouth (:func:`toon.formulas.bind_to_arcs`): the same rule with a smooth line, the
parabola through a corner, a middle point and the other corner; a hole's offsets shrink as its
middles meet, so a closed eye or mouth hides what it holds.

Point-attached vertices (A1.5-A1.6): ``V = V_min + P_CTRL * (V_max - V_min)``.

Lids that cross. A smile can push the lower lid above the upper one (real takes do this); a
crossed eye is a closed eye on every face. Where an upper lid's middle would sit below its lower
lid's, both middles meet half-way, so that holes and composite eyes close; and what a face shows
or hides by an upper lid's motor (a line face's pupil) reads how open the eye is: the upper lid's
value that would leave the same opening above the lower lid at rest (0 where the lids meet), at
most the lid's own value.

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

from collections.abc import Mapping

import numpy as np
from scipy import sparse

from common import InputError
from toon.components import Component
from toon.curves import ellipse_operator, outline_operator
from toon.face import ANGLE_MOTORS, FEATURES, HOLE_FEATURES, KINDS, PUPIL_EYES, Face, PolygonSpec
from toon.formulas import (
    bind_to_arcs,
    bind_to_lines,
    follow_arcs,
    follow_lines,
    head_turn,
    interpolate_states,
)
from toon.geometry import Geometry
from toon.images import CORNERS as IMAGE_CORNERS
from toon.motors import MOTOR_CODES, MOTORS, N_MOTORS, motor_index
from toon.plan import ComponentPrep, Polygon, Skeleton, plan_vertices, template
from toon.skeleton import EdgeCoupling, PointCoupling, bind_edge_skeleton, bind_point_skeleton

#: Features whose four points make two arcs (corners, upper and lower middles): eyes and mouth.
ARC_FEATURES: tuple[str, ...] = ("eye_right", "eye_left", "mouth")
#: Each eye's upper and lower lid motors (whose control points share their names).
LIDS: tuple[tuple[str, str], ...] = (("ERU", "ERL"), ("ELU", "ELL"))
#: Mask groups: holes write their group; pupils and clipped components draw only inside it.
MASK_GROUPS: dict[str, int] = {name: i + 1 for i, name in enumerate(HOLE_FEATURES)}


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
        self._order: list[Polygon | ComponentPrep] = [*back, *polygons, *front]
        # A frame's values: the 21 motors, then the face's extra parameters (HT, then its params).
        self.codes: tuple[str, ...] = (*MOTOR_CODES, *face.extra_codes)
        self._columns = {code: i for i, code in enumerate(self.codes)}
        extra_neutral = face.extra_neutral()
        self._extra_neutral = np.array([extra_neutral[c] for c in face.extra_codes], dtype=np.float64)
        self._moves = [(self._columns[p.code], self._index[m.point], np.array(m.at0), np.subtract(m.at1, m.at0))
                       for p in face.params for m in p.points]
        self._plan = plan_vertices(self._order, self._rest, self._columns)
        self._pupil_rows = [self._index[p] for p in PUPIL_EYES]
        self._gaze_columns = np.array([[motor_index(f"P{p[1]}{a}") for a in "HV"] for p in PUPIL_EYES])
        ranges = np.array([[face.ranges[f"P{p[1]}{a}"] for a in "HV"] for p in PUPIL_EYES])  # (2, 2, [lo, hi])
        self._gaze_range = (ranges[..., 0], ranges[..., 1] - ranges[..., 0])
        self.templates = [template(prep, key) for key, prep in enumerate(self._order)]
        self._switched = [(key, prep.spec.visible) for key, prep in enumerate(self._order)
                          if isinstance(prep, ComponentPrep) and prep.spec.visible is not None]
        self._animated = [(self._plan.slices[key], prep.spec) for key, prep in enumerate(self._order)
                          if isinstance(prep, ComponentPrep)
                          and (prep.spec.scale or prep.spec.translate or prep.spec.rotate)]
        # Per eye: the rows of its lid points, the upper lid's motor and range, the lower lid's rest height.
        self._lids = [(self._index[up], self._index[low], motor_index(up), face.ranges[up], face.points[low][1])
                      for up, low in LIDS]

    def control_points(self, values: np.ndarray, extra: Mapping[str, float] | None = None) -> np.ndarray:
        """Control-point positions for one frame of motor values ``(21,)`` and extra parameters
        (as for :meth:`geometry`); shape ``(P, 2)``."""
        full = self.full_values(values, extra)
        return self._control_points(full, self._gaze(full))

    def full_values(self, values: np.ndarray, extra: Mapping[str, float] | None = None) -> np.ndarray:
        """The 21 motor values ``(21,)`` and the face's extra parameters by code (one not given at
        its neutral; one the face lacks is an error naming it) as one row in :attr:`codes` order."""
        values = np.asarray(values, dtype=np.float64)
        if values.shape != (N_MOTORS,):
            raise ValueError(f"expected {N_MOTORS} motor values, got shape {values.shape}")
        full = np.concatenate([values, self._extra_neutral])
        if extra:
            unknown = [code for code in extra if code not in self._columns or code in MOTOR_CODES]
            if unknown:
                declared = ", ".join(self.face.extra_codes) or "none"
                raise InputError(f"face {self.face.name} has no parameter {', '.join(unknown)} "
                                 f"(it declares {declared})")
            for code, value in extra.items():
                full[self._columns[code]] = value
        return full

    def _control_points(self, values: np.ndarray, gaze: np.ndarray) -> np.ndarray:
        """:meth:`control_points` of a full row (:meth:`full_values`) with the pupils' gaze
        ``(2, 2)`` (radians) already known."""
        pts = self._rest.copy()
        for col, row, axis, lo, hi in self._driven:
            pts[row, axis] = lo + values[col] * (hi - lo)
        for col, row, at0, span in self._moves:  # the face's own parameters displace their points
            pts[row] += at0 + values[col] * span
        pts[self._pupil_rows] += self.face.eye_radius * np.sin(gaze)
        for up, low, *_ in self._lids:  # lids that cross meet half-way: a closed eye
            if pts[up, 1] < pts[low, 1]:
                pts[up, 1] = pts[low, 1] = (pts[up, 1] + pts[low, 1]) / 2
        return pts

    def shown_values(self, values: np.ndarray, pts: np.ndarray) -> np.ndarray:
        """The values that decide what is shown (``visible`` ranges), for a row ``values`` (the 21
        motors, and the extras after them as in :meth:`full_values`) whose control points are
        ``pts`` ``(P, 2)``: each upper lid's value is how open its eye is, the value that would
        leave the same opening above the lower lid at rest (see the module docstring), and never
        more than its own (a lowered lower lid does not open an eye); the same shape as ``values``."""
        shown = values.copy()
        for up, low, column, (lo, hi), rest in self._lids:
            if hi != lo:
                height = rest + max(pts[up, 1] - pts[low, 1], 0.0)
                shown[column] = min(values[column], (height - lo) / (hi - lo))
        return shown

    def head_degrees(self, values: np.ndarray) -> tuple[float, float]:
        """The head's yaw and pitch in degrees for motor values ``(21,)`` (HH and HV within the
        face's ranges)."""
        return (self._lerp(self._head[0], values[self._columns["HH"]]),
                self._lerp(self._head[1], values[self._columns["HV"]]))

    def gaze_degrees(self, values: np.ndarray, point: str) -> np.ndarray:
        """Horizontal and vertical gaze angles of pupil ``point`` (PR or PL) in degrees, shape ``(2,)``."""
        return np.degrees(self._gaze(values)[list(PUPIL_EYES).index(point)])

    def _gaze(self, values: np.ndarray) -> np.ndarray:
        """Gaze angles in radians, one row (horizontal, vertical) per pupil of PUPIL_EYES: ``(2, 2)``."""
        low, span = self._gaze_range
        return np.radians(low + values[self._gaze_columns] * span)

    def geometry(self, values: np.ndarray, extra: Mapping[str, float] | None = None) -> Geometry:
        """The items of one frame, in drawing order, for motor values of shape ``(21,)`` and the
        face's extra parameters by code (``{"HT": 0.7}``; one the face lacks is an error naming
        it, one not given holds its neutral).

        Every vertex of the frame is computed in one array, a few array operations per kind of
        vertex (see :class:`VertexPlan`); each item's vertices are a slice of it.
        """
        values = self.full_values(values, extra)
        plan = self._plan
        gaze = self._gaze(values)
        pts = self._control_points(values, gaze)
        out = np.empty((plan.size, 2))
        out[plan.static_at] = plan.static_xy
        if plan.lines is not None:
            out[plan.line_at] = follow_lines(plan.lines, pts)  # A1.1-A1.4
        if plan.arcs is not None:
            out[plan.arc_at] = follow_arcs(plan.arcs, pts)  # A1.3-A1.4 on the eyes' and mouth's arcs
        if len(plan.pupil_at):
            out[plan.pupil_at] = pts[plan.pupil_row] + plan.pupil_offset * np.cos(gaze)[plan.pupil_eye]
        if len(plan.point_at):  # A1.5-A1.6
            out[plan.point_at] = interpolate_states(plan.point_min, plan.point_max, values[plan.point_motor][:, None])
        if plan.operator is not None:
            out[plan.component_at] = plan.operator @ self._outline_inputs(pts)
        for where, spec in self._animated:
            if spec.scale is not None:
                factor = np.add(spec.scale.at0, values[self._columns[spec.scale.motor]] * np.subtract(
                    spec.scale.at1, spec.scale.at0))
                out[where] = np.asarray(spec.scale.origin) + (out[where] - spec.scale.origin) * factor
            if spec.rotate is not None:
                turn = np.radians(spec.rotate.at0[0] + values[self._columns[spec.rotate.motor]] * (
                    spec.rotate.at1[0] - spec.rotate.at0[0]))
                c, s = np.cos(turn), np.sin(turn)
                out[where] = np.asarray(spec.rotate.origin) + (out[where] - spec.rotate.origin) @ np.array(
                    [[c, s], [-s, c]])
            if spec.translate is not None:
                out[where] += np.add(spec.translate.at0, values[self._columns[spec.translate.motor]] * np.subtract(
                    spec.translate.at1, spec.translate.at0))
        yaw, pitch = self.head_degrees(values)
        if (yaw or pitch) and len(plan.moving_at):
            out[plan.moving_at] = head_turn(out[plan.moving_at], plan.moving_depth, self._pivot, yaw, pitch)
        if self.face.head_tilt and values[self._columns["HT"]] != 0.5:
            out[:] = self.tilted(out, values[self._columns["HT"]])
        decides = self.shown_values(values, pts) if self._switched else values
        hidden = {key for key, shown in self._switched
                  if not shown.low <= decides[self._columns[shown.motor]] <= shown.high}
        items = tuple(template.with_vertices(out[where]) for key, (template, where)
                      in enumerate(zip(self.templates, plan.slices, strict=True)) if key not in hidden)
        return Geometry(items, self.face.viewbox, self.face.background)

    def tilted(self, points: np.ndarray, tilt: float) -> np.ndarray:
        """``points`` ``(N, 2)`` rolled about the head pivot by ``tilt`` (HT: 0.5 upright, 1 the
        face's full tilt counter-clockwise as seen, 0 clockwise); ``points`` itself at 0.5."""
        if tilt == 0.5:
            return points
        angle = np.radians((2.0 * float(tilt) - 1.0) * self.face.head_tilt)
        c, s = np.cos(angle), np.sin(angle)
        return self._pivot + (points - self._pivot) @ np.array([[c, s], [-s, c]])

    def _outline_inputs(self, pts: np.ndarray) -> np.ndarray:
        """Every component's defining points (its body, for a skeleton) at control points ``pts``."""
        plan = self._plan
        moved = np.vstack([pts, np.zeros((1, 2))])[plan.defining_row] + plan.defining_offset  # row -1: origin
        if plan.defining_blend is not None:  # slaves of several masters: each one's share of the motion
            moved += plan.defining_blend @ (pts - self._rest)
        assert plan.operator is not None  # called only for faces with components
        inputs = np.empty((plan.operator.shape[1], 2))
        inputs[plan.direct_to] = moved[plan.direct_from]
        for skeleton, taken, given in plan.skeletons:
            inputs[given] = skeleton.body(moved[taken])
        return inputs

    @staticmethod
    def _lerp(bounds: tuple[float, float], value: float) -> float:
        return bounds[0] + value * (bounds[1] - bounds[0])

    def _prepare_polygon(self, spec: PolygonSpec, index: int) -> Polygon:
        rest = np.array(spec.vertices, dtype=np.float64)
        flat = spec.kind in ("face", "free")
        depth = spec.depth if spec.depth is not None else (0.0 if flat else self.face.feature_depth)
        extra: dict = {}
        mask_write, mask_test = 0, None
        if spec.kind in ("hole", "feature"):
            names, closed = FEATURES[spec.attach]
            line_rows = np.array([self._index[n] for n in names])
            try:
                if spec.attach in ARC_FEATURES:
                    extra["arc"] = bind_to_arcs(rest, self._rest[line_rows], line_rows, spec.kind == "hole")
                else:
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
        return Polygon(spec, rest, depth, mask_write, mask_test, **extra)

    def _prepare_component(self, spec: Component, index: int) -> ComponentPrep:
        refs = spec.points
        rows = np.array([self._index[p.master] if p.animated else -1 for p in refs], dtype=np.int64)
        at = np.array([p.at for p in refs], dtype=np.float64).reshape(-1, 2)
        masters = self._rest[np.maximum(rows, 0)]
        offset = np.where((rows >= 0)[:, None], np.where(np.array([p.kind == "slave" for p in refs])[:, None],
                                                          at - masters, 0.0), at)
        rest_pts = np.where((rows >= 0)[:, None], masters, 0.0) + offset
        blend = None
        if any(p.blend for p in refs):  # slaves of several masters: their weights, less the heaviest's own
            blend = np.zeros((len(refs), len(self._rest)))
            for i, p in enumerate(refs):
                for name, weight in p.blend:
                    blend[i, self._index[name]] += weight
                if p.blend:
                    blend[i, rows[i]] -= 1.0
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
            extra = {"skeleton": Skeleton(body, rest_pts, coupling)}
            outline_rest = body
        if spec.kind == "ellipse":
            ellipse = ellipse_operator()
            operator: np.ndarray | sparse.csr_array | None = ellipse
            edges = np.zeros(len(ellipse), dtype=np.int64)
        elif spec.kind == "image":  # its three points to its four corners
            operator, edges = IMAGE_CORNERS, np.arange(4)
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
        return ComponentPrep(spec, rows, offset, blend, depth, mask_write, mask_test, operator, edge_visible, **extra)
