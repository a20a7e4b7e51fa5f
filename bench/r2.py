"""The published peer for gap filling: Gløersen & Federolf (2016), strategy R2, written here from
the paper (PLoS ONE 11(3): e0152616; Federolf 2013 for the reconstruction step).

Markers are expressed relative to the mean trajectory of the markers with no gap (a frame moving
with the subject). Each marker with gaps is then reconstructed on its own: markers with gaps
that lie far from it (beyond half the mean inter-marker distance), or whose gaps overlap its
own, are left out; every coordinate is centred and scaled by the complete frames' statistics
and weighted by ``exp(-d^2 / (2 sigma^2))`` of its marker's distance ``d`` to the marker being
filled (0.02 for the marker itself); the principal components of the complete frames (keeping
99 % of the summed singular values), and of the same frames with the gap marker zeroed, map a
frame's visible coordinates onto the missing ones.
"""

from __future__ import annotations

import numpy as np

SIGMA_MM = 200.0
GAP_WEIGHT = 0.02
DISTAL = 0.5
KEEP = 0.99


def fill_r2(positions: np.ndarray) -> np.ndarray:
    """``positions`` ``(F, M, 3)`` (NaN: missing) with every gap R2 can fill, filled."""
    frames, markers, _ = positions.shape
    missing = np.isnan(positions).any(axis=2)
    complete = ~missing.any(axis=0)
    if not complete.any() or not missing.any():
        return positions.copy()
    centre = positions[:, complete].mean(axis=1, keepdims=True)  # (F, 1, 3): the subject's own frame
    local = positions - centre
    mean_distance = np.nanmean(np.linalg.norm(local[:, :, None] - local[:, None], axis=3), axis=0)  # (M, M)
    out = local.copy()
    for m in map(int, np.flatnonzero(missing.any(axis=0))):
        gaps = missing[:, m]
        near = mean_distance[m] <= DISTAL * np.nanmean(mean_distance)
        use = (~missing.any(axis=0) | (near & ~(missing & gaps[:, None]).any(axis=0)))
        use[m] = True
        cols = np.flatnonzero(use)
        data = local[:, cols].reshape(frames, -1)
        known = ~np.isnan(data).any(axis=1)
        wanted = gaps & ~np.isnan(np.delete(data, _columns(cols, m), axis=1)).any(axis=1)
        if known.sum() < 3 or not wanted.any():
            continue
        weights = np.repeat(np.exp(-mean_distance[m, cols] ** 2 / (2 * SIGMA_MM ** 2)), 3)
        weights[_columns(cols, m)] = GAP_WEIGHT
        filled = _reconstruct(data[known], data[wanted], _columns(cols, m), weights)
        out[wanted, m] = filled
    return out + centre


def _columns(cols: np.ndarray, m: int) -> list[int]:
    """Columns of marker ``m``'s three coordinates among the flattened ``cols`` markers."""
    at = int(np.flatnonzero(cols == m)[0])
    return [3 * at, 3 * at + 1, 3 * at + 2]


def _reconstruct(known: np.ndarray, gapped: np.ndarray, target: list[int], weights: np.ndarray) -> np.ndarray:
    """The ``target`` coordinates ``(G, 3)`` of the ``gapped`` rows, from the complete rows ``known``."""
    zeroed = known.copy()
    zeroed[:, target] = 0.0
    mean, zero_mean = known.mean(axis=0), zeroed.mean(axis=0)
    scale = known.std(axis=0)
    scale[scale == 0] = 1.0
    full = (known - mean) / scale * weights
    part = (zeroed - zero_mean) / scale * weights
    rows = gapped.copy()
    rows[:, target] = 0.0
    rows = (rows - zero_mean) / scale * weights
    full_pc, full_sv = _components(full)
    part_pc, part_sv = _components(part)
    keep = max(_count(full_sv), _count(part_sv))
    full_pc, part_pc = full_pc[:, :keep], part_pc[:, :keep]
    estimate = rows @ part_pc @ (part_pc.T @ full_pc) @ full_pc.T  # zeroed scores onto the full basis
    return (estimate * scale / weights + mean)[:, target]


def _components(data: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    _, values, vt = np.linalg.svd(data / np.sqrt(max(len(data) - 1, 1)), full_matrices=False)
    return vt.T, values


def _count(values: np.ndarray) -> int:
    return int(np.searchsorted(np.cumsum(values), KEEP * values.sum()) + 1)
