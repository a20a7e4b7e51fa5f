"""CharToon's skeleton couplings (section 3.2 of the CharToon seed), bound once, applied per frame.

Point skeleton: each fixed body point is assigned, at rest, to the closest skeleton point and
keeps its initial vector from it; a body point whose closest skeleton point is a fixed point
(a joint) stays in place, as do frozen body points.

Edge skeleton: each fixed body point is projected, at rest, onto its closest skeleton edge. When
the skeleton moves, the projection keeps the ratio ``t`` of its distances to the edge's end points
(the edge may change length), and the body point keeps its signed distance ``d`` from the edge
along the edge's normal, so its actual projection always coincides with the moving one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PointCoupling:
    """Body points ``(B,)``: the skeleton point each follows, and whether it moves at all."""

    nearest: np.ndarray
    moves: np.ndarray

    def apply(self, body_rest: np.ndarray, skeleton_rest: np.ndarray, skeleton: np.ndarray) -> np.ndarray:
        """Body positions ``(B, 2)`` for skeleton positions ``(K, 2)``."""
        delta = skeleton - skeleton_rest
        return body_rest + delta[self.nearest] * self.moves[:, None]


@dataclass(frozen=True)
class EdgeCoupling:
    """Body points ``(B,)``: their edge (start, end indices), ratio ``t``, distance ``d``, mobility."""

    start: np.ndarray
    end: np.ndarray
    t: np.ndarray
    d: np.ndarray
    moves: np.ndarray

    def apply(self, body_rest: np.ndarray, skeleton_rest: np.ndarray, skeleton: np.ndarray) -> np.ndarray:
        """Body positions ``(B, 2)`` for skeleton positions ``(K, 2)``."""
        a, b = skeleton[self.start], skeleton[self.end]
        edge = b - a
        length = np.linalg.norm(edge, axis=1)
        unit = edge / np.where(length > 1e-12, length, 1.0)[:, None]
        normal = np.column_stack([-unit[:, 1], unit[:, 0]])
        moved = a + self.t[:, None] * edge + self.d[:, None] * normal
        return np.where(self.moves[:, None], moved, body_rest)


def bind_point_skeleton(body: np.ndarray, skeleton: np.ndarray, body_fixed: np.ndarray,
                        skeleton_driven: np.ndarray) -> PointCoupling:
    """Assign each body point to its closest skeleton point.

    Parameters
    ----------
    body : ndarray, shape (B, 2)
        Body points at rest.
    skeleton : ndarray, shape (K, 2)
        Skeleton points at rest.
    body_fixed : ndarray of bool, shape (B,)
        Fixed body points (frozen ones never move).
    skeleton_driven : ndarray of bool, shape (K,)
        Skeleton points moved by a control point (fixed skeleton points are joints).
    """
    dist = np.linalg.norm(body[:, None, :] - skeleton[None, :, :], axis=2)
    nearest = np.argmin(dist, axis=1)
    return PointCoupling(nearest, body_fixed & skeleton_driven[nearest])


def bind_edge_skeleton(body: np.ndarray, skeleton: np.ndarray, body_fixed: np.ndarray,
                       closed: bool) -> EdgeCoupling:
    """Project each body point on its closest skeleton edge.

    Parameters
    ----------
    body : ndarray, shape (B, 2)
    skeleton : ndarray, shape (K, 2), ``K >= 2``
    body_fixed : ndarray of bool, shape (B,)
    closed : bool
        Whether an edge also joins the last skeleton point to the first.

    Raises
    ------
    ValueError
        If every skeleton edge has zero length at rest.
    """
    k = len(skeleton)
    starts = np.arange(k if closed and k > 2 else k - 1)
    ends = (starts + 1) % k
    a, b = skeleton[starts], skeleton[ends]
    edge = b - a  # (E, 2)
    length2 = np.einsum("ij,ij->i", edge, edge)
    usable = length2 > 1e-18
    if not usable.any():
        raise ValueError("every skeleton edge has zero length at rest")
    rel = body[:, None, :] - a[None, :, :]  # (B, E, 2)
    t_line = np.einsum("bej,ej->be", rel, edge) / np.where(usable, length2, 1.0)
    # The closest edge is measured to the segment; the ratio kept is the projection on its line,
    # so a body point beyond an end of the skeleton keeps its place at rest.
    foot = a[None] + np.clip(t_line, 0.0, 1.0)[..., None] * edge[None]
    dist = np.where(usable[None], np.linalg.norm(body[:, None, :] - foot, axis=2), np.inf)
    best = np.argmin(dist, axis=1)
    rows = np.arange(len(body))
    t = t_line[rows, best]
    unit = edge[best] / np.sqrt(length2[best])[:, None]
    normal = np.column_stack([-unit[:, 1], unit[:, 0]])
    d = np.einsum("ij,ij->i", body - (a[best] + t[:, None] * edge[best]), normal)
    return EdgeCoupling(starts[best], ends[best], t, d, np.asarray(body_fixed, dtype=bool))
