"""A face's items prepared for animation, and the plan of a frame's vertices.

:class:`~toon.rig.FaceRig` prepares each polygon (:class:`Polygon`) and component
(:class:`ComponentPrep`) once; :func:`plan_vertices` then lays every item's vertices out in one
array per frame, grouped by how they move (static, line- or arc-bound, pupil, point-attached,
component outline), so that a frame costs a few array operations per kind of vertex.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from itertools import pairwise

import numpy as np
from scipy import sparse

from toon.components import Component
from toon.face import PUPIL_EYES, PolygonSpec
from toon.formulas import ArcBinding, FeatureBinding
from toon.geometry import DrawItem
from toon.skeleton import EdgeCoupling, PointCoupling


@dataclass(frozen=True)
class Polygon:
    """A ToonFace polygon's rest vertices plus what moves it."""

    spec: PolygonSpec
    rest: np.ndarray
    depth: float
    mask_write: int
    mask_test: int | None
    line_rows: np.ndarray | None = None
    binding: FeatureBinding | None = None
    arc: ArcBinding | None = None  # eyes and mouth: the parabolas through their points
    v_max: np.ndarray | None = None
    pupil_row: int = -1


@dataclass(frozen=True)
class ComponentPrep:
    """A basic CharToon component bound for animation (see :mod:`toon.components`)."""

    spec: Component
    rows: np.ndarray  # (N,) control-point row per defining point; -1 for frozen and fixed points
    offset: np.ndarray  # (N, 2) added to that row's position (or to zero)
    #: (N, C) weights on every control point's motion from rest, less the row's own one: what a
    #: slave of several masters adds (None: none has several).
    blend: np.ndarray | None
    depth: float
    mask_write: int
    mask_test: int | None
    operator: np.ndarray | sparse.csr_array | None  # (S, N) outline operator; None: the points themselves
    edge_visible: np.ndarray | None
    skeleton: Skeleton | None = None


@dataclass(frozen=True)
class Skeleton:
    """A skeleton component's body at rest, its skeleton at rest and how the one moves the other."""

    body_rest: np.ndarray  # (B, 2)
    skeleton_rest: np.ndarray  # (N, 2)
    coupling: PointCoupling | EdgeCoupling

    def body(self, skeleton: np.ndarray) -> np.ndarray:
        """The body's points ``(B, 2)`` for the skeleton's points ``(N, 2)``."""
        return self.coupling.apply(self.body_rest, self.skeleton_rest, skeleton)


@dataclass(frozen=True)
class VertexPlan:
    """Where each kind of vertex sits in a frame's one array of vertices (items in drawing order)."""

    slices: tuple[slice, ...]  # each item's vertices
    size: int
    static_at: np.ndarray  # (K,) vertices that only a head turn moves: face and free polygons
    static_xy: np.ndarray  # (K, 2)
    lines: FeatureBinding | None  # every brow vertex, bound to control-point rows
    line_at: np.ndarray  # (L,)
    arcs: ArcBinding | None  # every eye and mouth vertex (holes and features), bound to their arcs
    arc_at: np.ndarray  # (A,)
    pupil_at: np.ndarray  # (Q,)
    pupil_row: np.ndarray  # (Q,) control-point row of the vertex's pupil point
    pupil_eye: np.ndarray  # (Q,) its pupil's place in PUPIL_EYES
    pupil_offset: np.ndarray  # (Q, 2) the vertex at rest minus its pupil point at rest
    point_at: np.ndarray  # (T,) point-attached vertices
    point_motor: np.ndarray  # (T,) the motor column that moves each
    point_min: np.ndarray  # (T, 2)
    point_max: np.ndarray  # (T, 2)
    defining_row: np.ndarray  # (D,) control-point row of each component point (-1: the origin)
    defining_offset: np.ndarray  # (D, 2) added to that row
    #: (D, C) what slaves of several masters add: weights on the control points' motion from rest
    defining_blend: sparse.csr_array | None
    direct_from: np.ndarray  # (E,) component points that are outline inputs as they are ...
    direct_to: np.ndarray  # (E,) ... and where they go among the inputs
    skeletons: tuple[tuple[Skeleton, slice, slice], ...]  # skeleton points taken, body points given
    operator: sparse.csr_array | None  # (S, I) every component's outline operator, block-diagonal
    component_at: np.ndarray  # (S,)
    moving_at: np.ndarray  # (M,) vertices standing in front of the outline: head turns move them
    moving_depth: np.ndarray  # (M,)


def outline_size(prep: Polygon | ComponentPrep) -> int:
    if isinstance(prep, Polygon):
        return len(prep.rest)
    if prep.operator is not None:
        return int(prep.operator.shape[0])
    return len(prep.skeleton.body_rest) if prep.skeleton is not None else len(prep.rows)


def plan_vertices(order: list[Polygon | ComponentPrep], rest: np.ndarray, columns: Mapping[str, int]) -> VertexPlan:
    """Index every vertex of a frame of ``order`` by how it moves (``rest``: control points at rest;
    ``columns``: each motor's and parameter's column in a frame's values)."""
    bounds = np.concatenate([[0], np.cumsum([outline_size(prep) for prep in order])]).astype(np.int64)
    slices = tuple(slice(int(a), int(b)) for a, b in pairwise(bounds))
    parts: dict[str, list] = {name: [] for name in (
        "static_at", "static_xy", "lines", "line_at", "arcs", "arc_at", "pupil_at", "pupil_row", "pupil_eye",
        "pupil_offset",
        "point_at", "point_motor", "point_min", "point_max", "defining_row", "defining_offset", "direct_from",
        "direct_to", "blocks", "component_at", "moving_at", "moving_depth")}
    skeletons: list[tuple[Skeleton, slice, slice]] = []
    blends: list = []
    defined = given = 0
    for prep, where in zip(order, slices, strict=True):
        at = np.arange(where.start, where.stop)
        if prep.depth:
            parts["moving_at"].append(at)
            parts["moving_depth"].append(np.full(len(at), prep.depth))
        if isinstance(prep, Polygon):
            if prep.arc is not None:
                parts["arcs"].append(prep.arc)
                parts["arc_at"].append(at)
            elif prep.binding is not None and prep.line_rows is not None:
                b = prep.binding
                parts["lines"].append(FeatureBinding(prep.line_rows[b.start], prep.line_rows[b.end], b.vrl, b.d))
                parts["line_at"].append(at)
            elif prep.pupil_row >= 0:
                parts["pupil_at"].append(at)
                parts["pupil_row"].append(np.full(len(at), prep.pupil_row))
                parts["pupil_eye"].append(np.full(len(at), list(PUPIL_EYES).index(prep.spec.attach)))
                parts["pupil_offset"].append(prep.rest - rest[prep.pupil_row])
            elif prep.v_max is not None:
                parts["point_at"].append(at)
                parts["point_motor"].append(np.full(len(at), columns[prep.spec.attach]))
                parts["point_min"].append(prep.rest)
                parts["point_max"].append(prep.v_max)
            else:
                parts["static_at"].append(at)
                parts["static_xy"].append(prep.rest)
            continue
        n = len(prep.rows)
        inputs = len(prep.skeleton.body_rest) if prep.skeleton is not None else n
        parts["defining_row"].append(prep.rows)
        parts["defining_offset"].append(prep.offset)
        blends.append((prep.blend, n))
        if prep.skeleton is not None:
            skeletons.append((prep.skeleton, slice(defined, defined + n), slice(given, given + inputs)))
        else:
            parts["direct_from"].append(np.arange(defined, defined + n))
            parts["direct_to"].append(np.arange(given, given + inputs))
        parts["blocks"].append(prep.operator if prep.operator is not None else sparse.eye_array(inputs, format="csr"))
        parts["component_at"].append(at)
        defined, given = defined + n, given + inputs
    lines = parts.pop("lines")
    arcs = parts.pop("arcs")
    blocks = parts.pop("blocks")
    arrays = {name: _joined(items, 2 if name in ("static_xy", "pupil_offset", "point_min", "point_max",
                                                 "defining_offset") else 1)
              for name, items in parts.items()}
    merged = FeatureBinding(*(np.concatenate([getattr(p, f) for p in lines])
                              for f in ("start", "end", "vrl", "d"))) if lines else None
    merged_arcs = ArcBinding(*(np.concatenate([getattr(p, f) for p in arcs]) for f in (
        "a", "b", "m", "other", "upper", "vrl", "d", "gap"))) if arcs else None
    operator = sparse.csr_array(sparse.block_diag(blocks)) if blocks else None
    blend = None  # made only for a face that has a slave of several masters
    if any(b is not None for b, _ in blends):
        blend = sparse.csr_array(sparse.vstack([sparse.csr_array(b if b is not None else (n, len(rest)))
                                                for b, n in blends]))
    return VertexPlan(slices, int(bounds[-1]), lines=merged, arcs=merged_arcs, skeletons=tuple(skeletons),
                       operator=operator, defining_blend=blend, **arrays)


def _joined(parts: list[np.ndarray], columns: int) -> np.ndarray:
    """``parts`` one after another; an empty index (or ``(0, 2)`` array) when there are none."""
    if not parts:
        return np.empty((0, 2)) if columns == 2 else np.empty(0, dtype=np.int64)
    return np.concatenate(parts)


def template(prep: Polygon | ComponentPrep, key: int) -> DrawItem:
    """The item ``prep`` draws, at its rest vertices: each frame copies it with its own vertices."""
    if isinstance(prep, Polygon):
        polygon = prep.spec
        return DrawItem(prep.rest, polygon.color, polygon.stroke, polygon.width, True, None, polygon.kind,
                        prep.mask_write, prep.mask_test, key, polygon.name)
    spec = prep.spec
    if spec.kind == "image":
        return DrawItem(np.empty((0, 2)), None, None, 0.0, True, None, "image", 0, prep.mask_test, key, spec.name,
                        picture=spec.picture)
    return DrawItem(np.empty((0, 2)), spec.fill, spec.stroke, spec.width, spec.closed, prep.edge_visible,
                    "component", prep.mask_write, prep.mask_test, key, spec.name)
