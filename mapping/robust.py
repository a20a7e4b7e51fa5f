"""Robust statistics of a take's columns: each column's jitter, a NaN-aware median by columns or
element by element, and the grouping of columns that keeps a long take's copies small.

Shared by cleaning's spike tests (:mod:`mapping.outliers`), the head fit, the hold smoother and the
profile's ranges.
"""

from __future__ import annotations

import numpy as np

#: Columns worked on at once (:func:`column_groups`: :func:`jitter`'s differences, the profile's
#: percentiles): a whole-take copy of every column of an hour's take is hundreds of MB.
COLUMNS_AT_ONCE = 12
#: Frames gathered into rows at once by :func:`as_rows`: a block that stays in the cache.
ROWS_AT_ONCE = 4096


def jitter(values: np.ndarray, least: int = 1) -> np.ndarray:
    """Each column's jitter as a standard deviation, from ``values`` ``(F, ...)`` (NaN where
    unseen), ``(...)``: the median absolute second difference over three seen samples in a row,
    times 1.4826 / sqrt(6) (white noise's second difference has six times its variance; motion at
    a face's speeds hardly reaches it). NaN with fewer than ``least`` such differences.

    >>> rng = np.random.default_rng(0)
    >>> bool(abs(jitter(np.cumsum(rng.normal(0, 0.01, 4000)) + rng.normal(0, 0.3, 4000)) - 0.3) < 0.02)
    True
    """
    columns = values.reshape(len(values), -1)
    if len(columns) < 3:
        return np.full(values.shape[1:], np.nan)
    spread, counted = np.empty(columns.shape[1]), np.empty(columns.shape[1], int)
    for part in column_groups(columns.shape[1]):  # a few at a time: small copies
        second = np.abs(np.diff(as_rows(columns, part), n=2, axis=1)).T  # (F - 2, part), each column in order
        spread[part] = 1.4826 * column_nan_median(second) / np.sqrt(6.0)
        counted[part] = np.isfinite(second).sum(axis=0)
    return np.where(counted >= least, spread, np.nan).reshape(values.shape[1:])


def column_groups(columns: int) -> list[np.ndarray]:
    """Column numbers ``0 .. columns - 1`` in groups of at most :data:`COLUMNS_AT_ONCE`: a long
    take's per-column work a few columns at a time keeps its copies small."""
    return np.array_split(np.arange(columns), max(1, -(-columns // COLUMNS_AT_ONCE)))


def as_rows(columns: np.ndarray, part: np.ndarray) -> np.ndarray:
    """The columns ``part`` of ``columns`` ``(frames, channels)`` as rows, ``(len(part), frames)``,
    C order; a block of :data:`ROWS_AT_ONCE` frames at a time: the transpose of a long take's
    columns at once misses the cache at every frame (an hour's: a third of a second a pass), and
    work along a row (a filter, a sort) runs over memory in order."""
    rows = np.empty((len(part), len(columns)))
    for lo in range(0, len(columns), ROWS_AT_ONCE):
        rows[:, lo:lo + ROWS_AT_ONCE] = columns[lo:lo + ROWS_AT_ONCE, part].T
    return rows


def column_nan_median(values: np.ndarray) -> np.ndarray:
    """``np.nanmedian(values, axis=0)`` of ``(F, M)``, ``(M,)``, without a warning for a column
    that is all NaN (its median is NaN): the columns without NaN in one partial sort
    (``np.median``), the others one by one, each its seen values' partial sort (a sort of them
    all, NaN last, cost an hour's take most of a second)."""
    whole = ~np.isnan(values).any(axis=0)
    if whole.all():
        return np.median(values, axis=0) if len(values) else np.full(values.shape[1], np.nan)
    out = np.full(values.shape[1], np.nan)
    if whole.any():
        out[whole] = np.median(values[:, whole], axis=0)
    for c in np.flatnonzero(~whole):
        seen = values[:, c][~np.isnan(values[:, c])]
        if len(seen):
            out[c] = np.median(seen)
    return out


def nan_median(parts: list[np.ndarray], complete: bool = False) -> np.ndarray:
    """Element-wise median of a few same-shaped arrays ignoring NaN (NaN where all are NaN);
    ``complete``: the caller knows every value is finite.

    An odd-even transposition network sorts them element-wise (missing values, set to +inf,
    sort last): one pass per comparator over whole arrays, where sorting a stacked axis visits
    every element alone. The median is read at each element's count of finite values."""
    k = len(parts)
    if complete and k == 3:  # the common case, by a median network (4 passes)
        return np.maximum(np.minimum(parts[0], parts[1]), np.minimum(np.maximum(parts[0], parts[1]), parts[2]))
    finite = [] if complete else [np.isfinite(p) for p in parts]
    order = list(parts) if complete else [np.where(f, p, np.inf) for f, p in zip(finite, parts, strict=True)]
    for r in range(k):
        for i in range(r % 2, k - 1, 2):
            order[i], order[i + 1] = np.minimum(order[i], order[i + 1]), np.maximum(order[i], order[i + 1])
    median = order[k // 2].copy() if k % 2 else 0.5 * (order[k // 2 - 1] + order[k // 2])
    if complete:
        return median
    count = finite[0].astype(np.intp)
    for f in finite[1:]:
        count += f
    short = np.nonzero(count < k)
    if len(short[0]):
        have = count[short]
        ordered = np.stack([o[short] for o in order])  # (k, S)
        columns = np.arange(len(have))
        low, high = ordered[np.maximum(have - 1, 0) // 2, columns], ordered[np.minimum(have // 2, k - 1), columns]
        with np.errstate(invalid="ignore"):
            median[short] = np.where(have > 0, 0.5 * (low + high), np.nan)
    return median
