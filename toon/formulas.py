"""ToonFace's interpolation formulas (appendix A1.2.3) and the head turn, on plain arrays.

See :mod:`toon.rig` for how a face uses them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FeatureBinding:
    """Per-vertex line bindings: start/end control-point indices, ``vrl`` and ``d``, each (N,)."""

    start: np.ndarray
    end: np.ndarray
    vrl: np.ndarray
    d: np.ndarray


def bind_to_lines(vertices: np.ndarray, line_points: np.ndarray, closed: bool) -> FeatureBinding:
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
    starts = np.arange(k if closed and k > 2 else k - 1)
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
    return FeatureBinding(starts[best], ends[best], vrl[rows, best], d[rows, best])


def follow_lines(binding: FeatureBinding, line_points: np.ndarray) -> np.ndarray:
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


def head_turn(vertices: np.ndarray, depth: float | np.ndarray, pivot: np.ndarray, yaw_deg: float,
              pitch_deg: float) -> np.ndarray:
    """Turn vertices standing ``depth`` (scalar or per vertex) in front of the outline about ``pivot``; ``(N, 2)``."""
    yaw, pitch = np.radians(yaw_deg), np.radians(pitch_deg)
    x, y = vertices[:, 0] - pivot[0], vertices[:, 1] - pivot[1]
    y2 = y * np.cos(pitch) + depth * np.sin(pitch)
    z2 = -y * np.sin(pitch) + depth * np.cos(pitch)
    x2 = x * np.cos(yaw) + z2 * np.sin(yaw)
    return np.column_stack([x2 + pivot[0], y2 + pivot[1]])


@dataclass(frozen=True)
class ArcBinding:
    """Per-vertex bindings to the arcs of a closed four-point feature (eye or mouth), each (N,).

    The feature's points are corners ``a`` and ``b`` and two middles, upper and lower; each arc
    is the parabola through a corner, a middle and the other corner. ``m`` is the vertex's arc's
    middle and ``other`` the other middle (rows of the control points); ``upper`` says whether
    ``m`` is the upper one. ``gap`` is the rest height between the middles for the vertices of a
    hole polygon (0 for others): such a polygon closes to nothing as the middles meet.
    """

    a: np.ndarray
    b: np.ndarray
    m: np.ndarray
    other: np.ndarray
    upper: np.ndarray
    vrl: np.ndarray
    d: np.ndarray
    gap: np.ndarray


def _parabola(x: np.ndarray, xa: np.ndarray, ya: np.ndarray, xm: np.ndarray, ym: np.ndarray, xb: np.ndarray,
              yb: np.ndarray) -> np.ndarray:
    """The parabola through ``(xa, ya)``, ``(xm, ym)`` and ``(xb, yb)`` at ``x`` (Lagrange form)."""
    def safe(v: np.ndarray) -> np.ndarray:
        return np.where(np.abs(v) > 1e-9, v, 1e-9)
    return (ya * (x - xm) * (x - xb) / safe((xa - xm) * (xa - xb))
            + ym * (x - xa) * (x - xb) / safe((xm - xa) * (xm - xb))
            + yb * (x - xa) * (x - xm) / safe((xb - xa) * (xb - xm)))


def _polyline(x: np.ndarray, xa: float, ya: float, xm: float, ym: float, xb: float, yb: float) -> np.ndarray:
    """A1's two lines from corner ``a`` through the middle ``m`` to corner ``b`` at ``x`` (each
    line extended past its end point)."""
    first = ya + (x - xa) * (ym - ya) / (xm - xa)
    second = ym + (x - xm) * (yb - ym) / (xb - xm)
    on_first = (x - xm) * np.sign(xa - xm) >= 0  # on a's side of the middle
    return np.where(on_first, first, second)


def bind_to_arcs(vertices: np.ndarray, points: np.ndarray, rows: np.ndarray, hole: bool) -> ArcBinding:
    """Bind vertices to the arcs of a closed four-point feature (A1.3-A1.4 with the parabola
    through three of its points for the line: a smooth eye or mouth instead of a kite).

    Parameters
    ----------
    vertices : ndarray, shape (N, 2)
        The polygon's vertices at rest.
    points : ndarray, shape (4, 2)
        The feature's control points at rest: corner, upper middle, corner, lower middle.
    rows : ndarray, shape (4,)
        Their rows among all control points.
    hole : bool
        A hole polygon (the eye's white, the mouth's inside): its vertices follow the nearer
        arc, and it closes as the middles meet. Another polygon follows the arc nearer to it.
    """
    (xa, ya), (xu, yu), (xb, yb), (xl, yl) = points
    if abs(xb - xa) < 1e-9 or min(abs(xu - xa), abs(xu - xb), abs(xl - xa), abs(xl - xb)) < 1e-9:
        raise ValueError("the corners and middles of an eye or the mouth must differ in x")
    x, y = vertices[:, 0], vertices[:, 1]
    # Offsets from A1's lines through the three points, as the face was drawn; applied to the arc,
    # they keep the drawing's shape about a smooth line (a pointed lid apex would stay a bump).
    d_up = y - _polyline(x, xa, ya, xu, yu, xb, yb)
    d_low = y - _polyline(x, xa, ya, xl, yl, xb, yb)
    count = len(vertices)
    if hole:  # the outline of the opening: its top follows the upper arc, its bottom the lower
        upper = np.abs(d_up) <= np.abs(d_low)
    else:  # a lash, lid or lip follows one arc whole, or its ends would zigzag as the arcs part
        upper = np.full(count, np.abs(d_up).mean() <= np.abs(d_low).mean())
    return ArcBinding(np.full(count, rows[0]), np.full(count, rows[2]), np.where(upper, rows[1], rows[3]),
                      np.where(upper, rows[3], rows[1]), upper, (x - xa) / (xb - xa), np.where(upper, d_up, d_low),
                      np.full(count, max(yu - yl, 0.0) if hole else 0.0))


def follow_arcs(binding: ArcBinding, points: np.ndarray) -> np.ndarray:
    """Vertex positions for moved control points, shape ``(N, 2)`` (see :func:`bind_to_arcs`).

    A hole polygon's vertices keep their offset from the arc in proportion to how open the
    feature is (the middles' height over their rest height), so that the hole closes to nothing
    when the lids meet; where the upper middle passes below the lower one, the hole's arcs meet
    half-way between them.
    """
    xa, ya = points[binding.a, 0], points[binding.a, 1]
    xb, yb = points[binding.b, 0], points[binding.b, 1]
    xm, ym = points[binding.m, 0], points[binding.m, 1]
    y_other = points[binding.other, 1]
    hole = binding.gap > 0
    y_up, y_low = np.where(binding.upper, ym, y_other), np.where(binding.upper, y_other, ym)
    openness = np.clip((y_up - y_low) / np.where(hole, binding.gap, 1.0), 0.0, 1.0)
    crossed = hole & (y_up < y_low)
    ym = np.where(crossed, (y_up + y_low) / 2, ym)
    x = xa + binding.vrl * (xb - xa)  # A1.3
    y = _parabola(x, xa, ya, xm, ym, xb, yb) + binding.d * np.where(hole, openness, 1.0)  # A1.4 on the arc
    return np.column_stack([x, y])
