"""Head stabilisation: a rigid fit per frame on the head-reference markers."""

from __future__ import annotations

import numpy as np


def rigid_fit(source: np.ndarray, target: np.ndarray, min_points: int = 3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares rotations and translations mapping ``source`` onto each frame of ``target``.

    Kabsch's method per frame, using only the points seen in that frame.

    Parameters
    ----------
    source : ndarray, shape (K, 3)
        Reference points (for example the marker set's neutral head references).
    target : ndarray, shape (F, K, 3)
        Observed points, NaN where unseen.
    min_points : int
        Frames with fewer seen points get no pose.

    Returns
    -------
    rotation : ndarray, shape (F, 3, 3)
    translation : ndarray, shape (F, 3)
        ``target[f] ≈ source @ rotation[f].T + translation[f]``; NaN for frames without a pose.
    ok : ndarray of bool, shape (F,)
    """
    seen = ~np.isnan(target[..., 0])  # (F, K)
    ok = seen.sum(axis=1) >= min_points
    w = seen[..., None].astype(float)
    n = np.maximum(seen.sum(axis=1), 1)[:, None]
    tgt = np.where(seen[..., None], target, 0.0)
    src = np.broadcast_to(source, target.shape) * w
    src_c = src.sum(axis=1) / n
    tgt_c = tgt.sum(axis=1) / n
    a = (src - src_c[:, None]) * w
    b = (tgt - tgt_c[:, None]) * w
    cov = np.einsum("fki,fkj->fij", b, a)  # (F, 3, 3): target x source
    u, _, vt = np.linalg.svd(cov)
    d = np.sign(np.linalg.det(u @ vt))
    fix = np.ones((len(target), 3))
    fix[:, 2] = d
    rot = (u * fix[:, None, :]) @ vt
    trans = tgt_c - np.einsum("fij,fj->fi", rot, src_c)
    rot[~ok] = np.nan
    trans[~ok] = np.nan
    return rot, trans, ok


def to_head_frame(positions: np.ndarray, rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """Express world positions in the head frame: ``R.T @ (p - t)`` per frame; ``(F, M, 3)``."""
    return np.einsum("fji,fmj->fmi", rotation, positions - translation[:, None, :])


def yaw_pitch_degrees(rotation: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Yaw (toward +x) and pitch (face toward +y, chin up) of head rotations, degrees, ``(F,)`` each.

    Inverse of ``Ry(yaw) @ Rx(-pitch)``: the face direction ``R @ [0, 0, 1]`` is
    ``(cos p sin y, sin p, cos p cos y)``.
    """
    face = rotation[:, :, 2]
    yaw = np.degrees(np.arctan2(face[:, 0], face[:, 2]))
    pitch = np.degrees(np.arcsin(np.clip(face[:, 1], -1.0, 1.0)))
    return yaw, pitch
