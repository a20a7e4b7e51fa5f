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
