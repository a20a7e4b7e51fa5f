"""Every frame's shares at once from a solver's bases: the solve behind :meth:`mapping.solver.Solver.solve`.

Each frame is a bounded, robustly weighted least-squares fit of all motors to its seen markers
(the module docstring of :mod:`mapping.solver` says what and why). Two things make it cheap:

- **The normal equations come from the bases alone.** Each marker's Gram of every pair of bases
  is made once; a frame's weights sum them (one matrix product for all frames), and each frame's
  system is picked from the sums by the side each motor is on (one gather).
- **Motors that share no marker are solved apart.** A brow whose basis moves none of a lid's
  markers has a zero in the lid's row of every frame's Gram, whatever the weights, so the
  systems are block diagonal: each block (the motors linked through markers they both move) is
  solved on its own, the blocks of one size together, and a motor alone is a division. On
  toon32's layout the 19 motors fall into 13 blocks (ten alone, two pupils' pairs and the mouth's
  five), so a frame costs a 5 x 5 solve, not a 19 x 19 one. The shares are the same as the whole
  system's to rounding: the ridge is diagonal, and a block's equations hold none of another's
  unknowns.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mapping.solver_sides import ROBUST_FLOOR_MM, ROBUST_SCALE

#: Shares are clipped to this far past either end.
REACH = 1.25
#: The ridge towards rest, as a share of the sides' mean energy (what a side moves all markers
#: by, squared, averaged over the sides). It was this share of the first pass's basis when that
#: basis was, wrongly, half the sides' difference: a fifth to two fifths of this base on the
#: bench's performers. Chosen on the choice seeds (31-34, offline, solved; the mean fitted % of
#: own, second, third, fourth) among 1e-4 (1.092, 1.089, 1.419, 1.786), 3e-4
#: (1.091, 1.089, 1.414, 1.775), 1e-3 (1.089, 1.087, 1.401, 1.748), 3e-3 (1.103, 1.090, 1.386,
#: 1.722) and 1e-2 (1.230, 1.185, 1.396, 1.851), against 1.091, 1.087, 1.415, 1.769 before: 1e-3
#: is no worse for any performer; 3e-3 sums lower but costs the own and second performers (their
#: raw error 0.03-0.10 higher), as it shrinks the small motors (lids) towards rest.
RIDGE = 1e-3
ROBUST_PASSES = 2
#: Fewer frames than this are solved as one system each (the whole Gram, zeros and all): a block's
#: own calls cost more than its arithmetic saves.
FEW = 16


def blocks(up: np.ndarray, down: np.ndarray) -> list[np.ndarray]:
    """The motors that are solved together: those linked through markers both move, on either side.

    Parameters
    ----------
    up, down : ndarray, shape (K, M, 3)
        Each motor's basis on its high and low side.

    Returns
    -------
    list of ndarray of int, each shape (n, b)
        The blocks of ``b`` motors (indices into the K), ``n`` blocks of each size, smallest
        size first; every motor is in exactly one.
    """
    k = len(up)
    touch = (up != 0).any(axis=2) | (down != 0).any(axis=2)  # (K, M)
    linked = (touch.astype(int) @ touch.T.astype(int) > 0) | np.eye(k, dtype=bool)
    label = np.arange(k)
    while True:  # each motor takes the least label it is linked to, until none changes
        spread = np.where(linked, label[None, :], k).min(axis=1)
        if np.array_equal(spread, label):
            break
        label = spread
    members = [np.flatnonzero(label == lab) for lab in np.unique(label)]
    sizes = sorted({len(m) for m in members})
    return [np.array([m for m in members if len(m) == size]) for size in sizes]


@dataclass(frozen=True, eq=False)
class Layout:
    """What every solve with one set of bases shares, made once per solver (a live mapper solves
    one frame at a time with it).

    Attributes
    ----------
    used : ndarray of bool, shape (M,)
        The markers some basis moves: the others add nothing to any frame's equations, and the
        solve reads only these (``M'`` of them below).
    groups : list of ndarray of int, each shape (n, b)
        The blocks solved apart (:func:`blocks`).
    first, second : ndarray of int, shape (Q,)
        The ordered pairs of motors in one block: the only Gram entries that can be other than 0.
    places : list of ndarray of int, each shape (n, b, b)
        Where each group's blocks sit among the Q pairs.
    per_marker : ndarray, shape (M', P)
        Each marker's Gram of every pair of sides (high, low) of motors in one block.
    choice : ndarray of int, shape (Q, 4)
        Each motor pair's column of ``per_marker`` for its sides (high-high, high-low, low-high, low-low).
    per_mean : ndarray, shape (M', Q)
        Each marker's Gram of the motor pairs' mean bases (the first pass's).
    flat : ndarray, shape (2K, 3M')
        The sides' bases, high then low.
    energy : ndarray, shape (2K, M')
        What each side moves each marker, squared.
    ridge : float
        The ridge towards rest (:data:`RIDGE` of the sides' mean energy).
    """

    used: np.ndarray
    groups: list[np.ndarray]
    first: np.ndarray
    second: np.ndarray
    places: list[np.ndarray]
    per_marker: np.ndarray
    choice: np.ndarray
    per_mean: np.ndarray
    flat: np.ndarray
    energy: np.ndarray
    ridge: float

    @classmethod
    def of(cls, up: np.ndarray, down: np.ndarray) -> Layout:
        """The layout of bases ``up``, ``down`` ``(K, M, 3)`` (high side, low side)."""
        k = len(up)
        groups = blocks(up, down)
        first = np.concatenate([np.repeat(group, group.shape[1], axis=1).ravel() for group in groups])
        second = np.concatenate([np.tile(group, (1, group.shape[1])).ravel() for group in groups])
        ends = np.cumsum([0] + [group.size * group.shape[1] for group in groups])
        places = [np.arange(a, b).reshape(group.shape + group.shape[1:])
                  for a, b, group in zip(ends[:-1], ends[1:], groups, strict=True)]
        used = (up != 0).any(axis=(0, 2)) | (down != 0).any(axis=(0, 2))
        sides = np.concatenate([up, down])[:, used]  # (2K, M', 3): high, low
        rows, cols = np.triu_indices(2 * k)
        together = np.zeros((k, k), dtype=bool)
        together[first, second] = True
        inside = together[rows % k, cols % k]
        rows, cols = rows[inside], cols[inside]
        where = np.zeros((2 * k, 2 * k), dtype=np.intp)  # each pair of sides in one block: its column
        where[rows, cols] = where[cols, rows] = np.arange(len(rows))
        mean_basis = (up + down)[:, used] / 2  # a share s moves a marker by s * up or s * down
        return cls(used, groups, first, second, places, np.einsum("imc,jmc->mij", sides, sides)[:, rows, cols],
                   np.stack([where[first + k * a, second + k * b] for a in (0, 1) for b in (0, 1)], axis=1),
                   np.einsum("imc,jmc->mij", mean_basis, mean_basis)[:, first, second], sides.reshape(2 * k, -1),
                   np.einsum("imc,imc->im", sides, sides),
                   RIDGE * float(np.mean((sides ** 2).sum(axis=(1, 2)))))


def solve_frames(layout: Layout, noise: float, d: np.ndarray, weight: np.ndarray, counts: np.ndarray | None = None,
                 robust: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Shares and confidence for displacements from rest.

    Parameters
    ----------
    layout : Layout
        The bases' layout (:meth:`Layout.of`).
    noise : float
        The sweep's residual per marker (mm): the robust weights' scale.
    d : ndarray, shape (F, M', 3)
        Each used marker's head-frame displacement from rest (0 where unseen), mm.
    weight : ndarray, shape (F, M')
        How far each sample is believed, 0 (unseen) to 1.
    counts : ndarray, shape (F, M'), optional
        Each sample's part in the confidence (default ``weight``).
    robust : bool
        Whether to re-weight twice by the residual (Cauchy, :data:`ROBUST_SCALE` times ``noise``).

    Returns
    -------
    shares, confidence : ndarray, shape (F, K)
        Each motor's share, clipped to ±:data:`REACH`, and the share of its basis's motion on
        markers that counted.

    The first pass uses the two sides' mean basis; each later one each motor's basis of the side
    the pass before put it on.
    """
    flat, energy = layout.flat, layout.energy
    k, frames = len(flat) // 2, len(d)
    pairs = np.arange(len(layout.first))
    scale = max(ROBUST_SCALE * noise, ROBUST_FLOOR_MM)
    w = weight
    high: np.ndarray | None = None  # the side each motor is on (None: the mean of the two, the first pass)
    s = np.zeros((frames, k))
    passes = 2 + (ROBUST_PASSES if robust else 0)
    for step in range(passes):
        if step != 1:  # the second pass has the first's weights
            g = w @ layout.per_marker  # (F, P)
            r = ((d * w[..., None]).reshape(frames, -1) @ flat.T).reshape(frames, 2, k)
        if high is None:
            entries = w @ layout.per_mean  # (F, Q)
            rhs = (r[:, 0] + r[:, 1]) / 2
        else:  # each frame's entries picked from its pairs of sides by the side each motor is on: one gather
            low = (~high).astype(np.intp)
            entries = np.take_along_axis(g, layout.choice[pairs, 2 * low[:, layout.first] + low[:, layout.second]],
                                         axis=1)
            rhs = np.where(high, r[:, 0], r[:, 1])
        s = np.clip(_solve_blocks(entries, rhs, layout), -REACH, REACH)
        high = s >= 0
        if robust and 1 <= step < passes - 1:
            miss = d - (np.where(high, s, 0.0) @ flat[:k] + np.where(high, 0.0, s) @ flat[k:]).reshape(d.shape)
            w = weight / (1.0 + np.einsum("fmc,fmc->fm", miss, miss) / scale ** 2)
    assert high is not None
    counted = weight if counts is None else counts
    confidence = np.where(high, counted @ energy[:k].T, counted @ energy[k:].T) \
        / np.maximum(np.where(high, energy[:k].sum(axis=1), energy[k:].sum(axis=1)), 1e-12)
    return s, confidence


def _solve_blocks(entries: np.ndarray, rhs: np.ndarray, layout: Layout) -> np.ndarray:
    """Every frame's ``(gram + ridge * I) x = rhs``, the Gram block diagonal by the layout's groups
    and given by its blocks' ``entries`` ``(F, Q)``; ``rhs`` ``(F, K)``. Returns ``x`` ``(F, K)``."""
    if len(entries) < FEW:  # a live frame: one call for the whole Gram costs less than a call per block
        gram = np.zeros((len(entries), rhs.shape[1], rhs.shape[1]))
        gram[:, layout.first, layout.second] = entries
        return np.linalg.solve(gram + layout.ridge * np.eye(rhs.shape[1]), rhs[..., None])[..., 0]
    x = np.empty_like(rhs)
    for group, place in zip(layout.groups, layout.places, strict=True):
        a = entries[:, place] + layout.ridge * np.eye(group.shape[1])  # (F, n, b, b)
        x[:, group] = _spd_solve(a, rhs[:, group])
    return x


def _spd_solve(a: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``a x = y`` for many small symmetric positive definite systems, ``a`` ``(..., b, b)``,
    ``y`` ``(..., b)``: Gaussian elimination without pivoting (stable for such matrices), one
    step per row for all systems at once (a call per small system costs more than the system)."""
    a, y = a.copy(), y.copy()
    size = a.shape[-1]
    for j in range(size - 1):
        factor = a[..., j + 1:, j] / a[..., j, j, None]  # (..., b - j - 1)
        a[..., j + 1:, j + 1:] -= factor[..., :, None] * a[..., j, None, j + 1:]
        y[..., j + 1:] -= factor * y[..., j, None]
    x = np.empty_like(y)
    for j in range(size - 1, -1, -1):
        x[..., j] = (y[..., j] - (a[..., j, j + 1:] * x[..., j + 1:]).sum(axis=-1)) / a[..., j, j]
    return x
