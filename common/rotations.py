"""The rotation that best aligns two point sets, for a whole take at once.

Kabsch's method takes an SVD of each frame's 3 × 3 covariance; numpy runs those one LAPACK
call per frame, which made them the largest single cost of cleaning. Horn's quaternion form
(Horn 1987) turns the same least-squares problem into the largest eigenvalue of a symmetric,
traceless 4 × 4 matrix; as in Theobald's QCP method (Theobald 2005; Liu, Agrafiotis & Theobald
2010) that eigenvalue is found by Newton's method on the characteristic polynomial, here for
every frame at once, and the quaternion read from the adjugate of ``N - λI``. Frames where the
best rotation is not unique (a degenerate point set) fall back to the SVD. :func:`rigid_fit` uses it for
the rotation and translation of every frame, for each stage that lays points over points.
"""

from __future__ import annotations

import numpy as np

#: Newton's method stops when every frame's eigenvalue moves less than this, relative to ‖N‖.
_TOLERANCE = 1e-14
_MAX_STEPS = 60
#: The adjugate's largest diagonal entry (about the product of the top eigenvalue's gaps to the
#: others, ‖N‖ = 1) below which a frame is left to the SVD: the quaternion's error grows as
#: machine precision over the square of the smallest gap.
_GAPS = 1e-4

#: Fewer frames than this go to the SVD: the vectorised form costs a few hundred numpy calls
#: whatever the count (the live sender fits one frame at a time).
_FEW = 32

#: Rows and columns left in the minor of each (row, column) of a 4 × 4 matrix.
_KEEP = [[i for i in range(4) if i != skip] for skip in range(4)]


def best_rotation(cross: np.ndarray) -> np.ndarray:
    """The proper rotation ``R`` maximising ``trace(R.T @ B)`` for each ``B``.

    For ``B = Σ b aᵀ`` over centred point pairs this is the least-squares rotation taking the
    ``a`` onto the ``b`` (Kabsch's); for ``B`` itself near a rotation, the nearest rotation.

    Parameters
    ----------
    cross : ndarray, shape (..., 3, 3)
        Finite.

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    shape = cross.shape
    b = np.asarray(cross, dtype=np.float64).reshape(-1, 3, 3)
    if len(b) < _FEW:
        return _by_svd(b).reshape(shape)
    n = _horn_matrix(b)
    scale = np.sqrt(sum((n[i][j] * n[i][j] for i in range(4) for j in range(4)), np.zeros(len(b))))
    usable = scale > 0
    inverse = 1.0 / np.where(usable, scale, 1.0)
    n = [[entry * inverse for entry in row] for row in n]  # ‖N‖ = 1: the bounds below are absolute
    top, settled = _largest_eigenvalue(n)
    quaternion, reliable = _eigenvector(n, top)
    rotation = _quaternion_matrix(quaternion)
    redo = ~(usable & reliable & settled)
    if redo.any():
        rotation[redo] = _by_svd(b[redo])
    return rotation.reshape(shape)


def _by_svd(b: np.ndarray) -> np.ndarray:
    """:func:`best_rotation` of ``(F, 3, 3)`` by Kabsch's SVD, the sign of the last axis fixed."""
    u, _, vt = np.linalg.svd(b)
    u[:, :, -1] *= np.where(np.linalg.det(u @ vt) < 0, -1.0, 1.0)[:, None]
    return u @ vt


Matrix4 = list[list[np.ndarray]]  # a 4 × 4 matrix per frame, entry by entry: (F,) each


def _horn_matrix(b: np.ndarray) -> Matrix4:
    """Horn's symmetric 4 × 4 matrix of each ``B`` ``(F, 3, 3)`` (with Horn's ``S = Bᵀ``)."""
    xx, yx, zx = b[:, 0, 0].copy(), b[:, 0, 1].copy(), b[:, 0, 2].copy()
    xy, yy, zy = b[:, 1, 0].copy(), b[:, 1, 1].copy(), b[:, 1, 2].copy()
    xz, yz, zz = b[:, 2, 0].copy(), b[:, 2, 1].copy(), b[:, 2, 2].copy()
    n01, n02, n03 = yz - zy, zx - xz, xy - yx
    n12, n13, n23 = xy + yx, zx + xz, yz + zy
    return [[xx + yy + zz, n01, n02, n03],
            [n01, xx - yy - zz, n12, n13],
            [n02, n12, -xx + yy - zz, n23],
            [n03, n13, n23, -xx - yy + zz]]


def _largest_eigenvalue(n: Matrix4) -> tuple[np.ndarray, np.ndarray]:
    """The largest eigenvalue of each traceless symmetric ``n`` with ‖n‖ ≤ 1, ``(F,)``, and
    whether it settled within the steps allowed.

    Its characteristic polynomial is ``λ⁴ + c2 λ² + c1 λ + c0`` with ``c2 = -tr(N²)/2``,
    ``c1 = -tr(N³)/3`` and ``c0 = det N``. All its roots are real, so beyond the largest one it
    rises and is convex: Newton's method started above it (at ‖N‖) comes down to it without
    overshooting."""
    square = [[sum(n[i][k] * n[k][j] for k in range(4)) for j in range(4)] for i in range(4)]
    c2 = -0.5 * sum(square[i][i] for i in range(4))
    c1 = -sum(square[i][j] * n[j][i] for i in range(4) for j in range(4)) / 3.0
    c0 = sum(n[0][j] * _cofactor(n, 0, j) for j in range(4))
    top = np.sqrt(np.maximum(-2.0 * c2, 0.0))  # ‖N‖ (Frobenius), 1 where N is not zero
    step = np.zeros_like(top)
    for _ in range(_MAX_STEPS):
        top2 = top * top
        value = (top2 + c2) * top2 + c1 * top + c0
        slope = (4.0 * top2 + 2.0 * c2) * top + c1
        with np.errstate(invalid="ignore", divide="ignore"):
            step = np.where(slope > 0, value / slope, 0.0)
        top = top - step
        if np.abs(step).max(initial=0.0) < _TOLERANCE:
            break
    return top, np.abs(step) < 1e-9


def _eigenvector(n: Matrix4, top: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit eigenvector of each ``n`` for its eigenvalue ``top`` ``(F,)``, as the column of
    the adjugate of ``n - top I`` with the largest diagonal entry (the adjugate is that vector's
    outer product times the other eigenvalues' gaps); ``(F, 4)`` and whether it could be read
    (not where ``top`` is a repeated eigenvalue: the adjugate vanishes)."""
    a = [[n[i][j] - top if i == j else n[i][j] for j in range(4)] for i in range(4)]
    adjugate = np.empty((len(top), 4, 4))
    for i in range(4):
        for j in range(i, 4):
            adjugate[:, i, j] = adjugate[:, j, i] = _cofactor(a, i, j)
    diagonal = np.abs(np.diagonal(adjugate, axis1=1, axis2=2))
    best = np.argmax(diagonal, axis=1)
    column = np.take_along_axis(adjugate, best[:, None, None], axis=2)[:, :, 0]
    length = np.sqrt((column * column).sum(axis=1))
    reliable = np.take_along_axis(diagonal, best[:, None], axis=1)[:, 0] > _GAPS
    return column / np.where(length > 0, length, 1.0)[:, None], reliable


def _cofactor(m: Matrix4, row: int, column: int) -> np.ndarray:
    """The (row, column) cofactor of each symmetric ``m``: the signed determinant of its 3 × 3
    minor, written out (one LAPACK call per frame costs more), ``(F,)``."""
    r, c = _KEEP[row], _KEEP[column]
    e = [[m[i][j] for j in c] for i in r]
    det = (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
           - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
           + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]))
    return det if (row + column) % 2 == 0 else -det


def _quaternion_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(F, 3, 3)`` of unit quaternions ``(F, 4)`` (w, x, y, z)."""
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    out = np.empty((len(q), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = 2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = 2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z
    return out


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
    rot = best_rotation(np.transpose(b, (0, 2, 1)) @ a)  # the covariance (F, 3, 3): target x source
    trans = tgt_c - rotate(src_c[:, None, :], rot)[:, 0]
    rot[~ok] = np.nan
    trans[~ok] = np.nan
    return rot, trans, ok


def rotate(points: np.ndarray, rotation: np.ndarray, inverse: bool = False) -> np.ndarray:
    """``R @ p`` (``R.T @ p`` with ``inverse``) for every point of each frame.

    Parameters
    ----------
    points : ndarray, shape (F, M, 3)
    rotation : ndarray, shape (F, 3, 3)

    Returns
    -------
    ndarray, shape (F, M, 3)
        Written out coordinate by coordinate: several times faster than ``einsum`` or a batched
        ``matmul`` of 3 × 3 matrices.
    """
    out = np.empty(np.broadcast_shapes(points.shape, (len(rotation), 1, 3)))
    for i in range(3):
        row = [rotation[:, j, i] if inverse else rotation[:, i, j] for j in range(3)]
        out[..., i] = points[..., 0] * row[0][:, None] + points[..., 1] * row[1][:, None] \
            + points[..., 2] * row[2][:, None]
    return out
