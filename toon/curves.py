"""Outlines as linear operators on their points, and strokes as triangles.

A component's drawn outline is a fixed linear function of its defining points: a spline through
them (CharToon's smoothing, over all or part of an outline) or an ellipse through four contour
points. Each is built once as a sparse matrix ``M`` of shape ``(S, N)`` so that a frame's outline is
``M @ points``; scipy's cubic spline evaluated on the identity basis gives the spline matrix (a
long stretch's in windows, so that memory grows with its points, not their square).

Strokes (outlines with a width) become triangles: one quad per visible segment with butt ends,
plus miter joins on the outer side of each turn, falling back to a bevel beyond SVG's default
miter limit of 4, so the GL picture matches the SVG export's ``stroke-linejoin="miter"``.
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.interpolate import CubicSpline

#: Output segments per input segment of a smoothed stretch.
SPLINE_STEPS = 8
#: Points on an ellipse outline.
ELLIPSE_STEPS = 48
#: SVG's default ``stroke-miterlimit``: miter length over stroke width.
MITER_LIMIT = 4.0


def _spline_basis(params: np.ndarray, closed: bool, samples: np.ndarray) -> np.ndarray:
    """Matrix ``(len(samples), K)`` of the cubic spline through K unit impulses at ``params``.

    Closed: ``params`` has ``K + 1`` entries, the last one where the loop returns to point 0.
    """
    k = len(params) - 1 if closed else len(params)
    basis = np.eye(k)
    if closed:
        spline = CubicSpline(params, np.vstack([basis, basis[:1]]), bc_type="periodic")
    elif k >= 4:
        spline = CubicSpline(params, basis, bc_type="not-a-knot")
    else:
        spline = CubicSpline(params, basis, bc_type="natural")
    return spline(samples)


#: A smoothed stretch of up to this many points is solved whole (every built-in face's are).
WHOLE_POINTS = 64
#: Longer stretches are solved a block of this many segments at a time...
BLOCK_SEGMENTS = 64
#: ... and each drawn point reads the points up to this many either side of its segment: a cubic
#: spline's reach falls by 2 - sqrt(3) (0.27) a point, so what lies beyond weighs under 1e-9 of a
#: point's motion. A drawn point then depends on at most ``2 * REACH + 2`` points, and a stretch
#: costs memory linear in its length.
REACH = 16
#: Weights below this are left out of a long stretch's sparse operator.
NEGLIGIBLE = 1e-12


def _stretch(rest: np.ndarray, idx: np.ndarray, closed: bool) -> tuple[sparse.csr_array, np.ndarray]:
    """The spline through the points ``rest[idx]`` (a loop back to the first where ``closed``),
    :data:`SPLINE_STEPS` samples a segment: its sparse operator ``(samples, len(rest))`` and the
    segment (an index into ``idx``) each sample belongs to."""
    k = len(idx)
    loop = np.append(idx, idx[0]) if closed else idx
    chords = np.linalg.norm(np.diff(rest[loop], axis=0), axis=1)
    params = np.concatenate([[0.0], np.cumsum(np.maximum(chords, 1e-9))])
    segments = len(params) - 1
    samples = (np.arange(SPLINE_STEPS) * (np.diff(params) / SPLINE_STEPS)[:, None] + params[:-1, None]).reshape(-1)
    owner = np.repeat(np.arange(segments), SPLINE_STEPS)
    if k <= WHOLE_POINTS:  # exactly as one solve
        local = _spline_basis(params, closed, samples)
        return sparse.csr_array(_placed(local, idx, len(rest))), owner
    rows, cols, vals = [], [], []
    total = params[-1]
    for first in range(0, segments, BLOCK_SEGMENTS):
        last = min(first + BLOCK_SEGMENTS, segments)  # segments first..last-1
        if closed:  # a window round the loop, its parameters unwrapped
            at = np.arange(first - REACH, last + REACH + 1)
            window = params[at % segments] + np.floor_divide(at, segments) * total
            columns = idx[at % k]
        else:
            at = np.arange(max(first - REACH, 0), min(last + REACH, k - 1) + 1)
            window, columns = params[at], idx[at]
        basis = np.eye(len(at))
        bc = "not-a-knot" if len(at) >= 4 else "natural"
        local = CubicSpline(window, basis, bc_type=bc)(samples[first * SPLINE_STEPS:last * SPLINE_STEPS])
        own = np.repeat(np.arange(first, last), SPLINE_STEPS) - at[0]  # each sample's segment in the window
        near = np.abs(np.arange(len(at))[None, :] - own[:, None] - 0.5) <= REACH + 0.5
        r, c = np.nonzero(near & (np.abs(local) >= NEGLIGIBLE))
        rows.append(r + first * SPLINE_STEPS)
        cols.append(columns[c])
        vals.append(local[r, c])
    operator = sparse.coo_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                shape=(len(samples), len(rest)))
    return sparse.csr_array(operator), owner  # (a loop's window may name a point twice: summed)


def _placed(local: np.ndarray, idx: np.ndarray, n: int) -> np.ndarray:
    block = np.zeros((len(local), n))
    block[:, idx] = local
    return block


def outline_operator(rest: np.ndarray, closed: bool, smooth: tuple[tuple[int, int], ...]
                     ) -> tuple[sparse.csr_array, np.ndarray]:
    """The matrix that turns an outline's points into the drawn outline, and each edge's origin.

    Parameters
    ----------
    rest : ndarray, shape (N, 2)
        The points at rest; chord lengths at rest parameterise the splines.
    closed : bool
        Whether the outline closes (a polygon) or not (a polyline).
    smooth : tuple of (first, last)
        Inclusive point-index stretches drawn as a spline instead of straight lines; ``(0, N - 1)``
        on a closed outline smooths it all the way round, without a corner at point 0.

    Returns
    -------
    operator : scipy.sparse.csr_array, shape (S, N)
        Drawn outline = ``operator @ points``. Sparse: its memory grows with N, not N squared
        (a stretch longer than :data:`WHOLE_POINTS` is solved in windows, see :data:`REACH`).
    edge_origin : ndarray of int, shape (E,)
        For each drawn edge (``E = S`` closed, ``S - 1`` open), the input segment it belongs to
        (segment ``i`` runs from point ``i`` to point ``i + 1``), so invisible segments stay so.
    """
    n = len(rest)
    if not smooth:
        edges = np.arange(n if closed else n - 1)
        return sparse.csr_array(sparse.eye_array(n, format="csr")), edges
    if closed and any(a == 0 and b == n - 1 for a, b in smooth):  # the whole loop
        return _stretch(rest, np.arange(n), True)
    stretch_at = {a: b for a, b in smooth}
    blocks: list[sparse.csr_array] = []
    origin: list[np.ndarray] = []
    i = 0
    last = n - 1
    while i < last or (i == last and not blocks):
        if i in stretch_at:
            a, b = i, stretch_at[i]
            block, owner = _stretch(rest, np.arange(a, b + 1), False)
            blocks.append(block)
            origin.append(owner + a)
            i = b
        else:
            blocks.append(_point_rows([i], n))
            origin.append(np.array([i]))
            i += 1
    blocks.append(_point_rows([last], n))
    if closed:
        origin.append(np.array([last]))  # the closing segment, from the last point back to the first
    operator = sparse.csr_array(sparse.vstack(blocks, format="csr"))
    return operator, np.concatenate(origin).astype(np.int64)


def _point_rows(points: list[int], n: int) -> sparse.csr_array:
    """Rows that copy ``points`` as they are."""
    return sparse.csr_array((np.ones(len(points)), (np.arange(len(points)), points)), shape=(len(points), n))


def ellipse_operator() -> np.ndarray:
    """Matrix ``(ELLIPSE_STEPS, 4)`` for an ellipse through contour points left, top, right, bottom.

    The ellipse is ``c + cos(t) u + sin(t) v`` with ``c`` the mean of the four points,
    ``u = (right - left) / 2`` and ``v = (top - bottom) / 2``: an affine image of a circle, so it
    may be tilted or sheared, and it passes through all four points whenever the left-right and
    top-bottom chords share their midpoint.
    """
    t = np.linspace(0.0, 2 * np.pi, ELLIPSE_STEPS, endpoint=False)[:, None]
    centre = np.full((1, 4), 0.25)
    u = np.array([[-0.5, 0.0, 0.5, 0.0]])
    v = np.array([[0.0, 0.5, 0.0, -0.5]])
    return centre + np.cos(t) * u + np.sin(t) * v


def stroke_triangles(points: np.ndarray, width: float, closed: bool,
                     visible: np.ndarray | None = None) -> np.ndarray:
    """Triangles covering a stroked outline: butt ends, miter joins with SVG's limit.

    Parameters
    ----------
    points : ndarray, shape (N, 2)
    width : float
        Stroke width in the same units.
    closed : bool
        Whether a segment joins the last point back to the first.
    visible : ndarray of bool, shape (E,), optional
        Which segments are drawn (``E = N`` closed, ``N - 1`` open); all by default.

    Returns
    -------
    ndarray, shape (3 * T, 2)
        Triangle corners; the triangles may overlap (draw them opaque).
    """
    return stroke_many([(points, width, closed, visible)])[0]


def stroke_many(strokes: list[tuple[np.ndarray, float, bool, np.ndarray | None]]) -> list[np.ndarray]:
    """:func:`stroke_triangles` for many outlines at once (one set of array operations).

    Parameters
    ----------
    strokes : list of (points, width, closed, visible)
        As the arguments of :func:`stroke_triangles`.

    Returns
    -------
    list of ndarray, each shape (3 * T_i, 2)
        The triangle corners of each outline, in the order given.
    """
    a_parts, b_parts, half, shown, owner, follow = [], [], [], [], [], []
    base = 0
    for k, (points, width, closed, visible) in enumerate(strokes):
        n = len(points)
        m = n if closed else n - 1
        if n < 2 or width <= 0:
            continue
        a_parts.append(points[:m])
        b_parts.append(points[np.arange(1, m + 1) % n])
        half.append(np.full(m, width / 2))
        shown.append(np.ones(m, dtype=bool) if visible is None else np.asarray(visible, dtype=bool)[:m])
        owner.append(np.full(m, k))
        nxt = np.arange(1, m + 1) + base
        if closed:
            nxt[-1] = base
        else:
            nxt[-1] = -1
        follow.append(nxt)
        base += m
    out = [np.empty((0, 2)) for _ in strokes]
    if not a_parts:
        return out
    a, b = np.concatenate(a_parts), np.concatenate(b_parts)
    h, vis = np.concatenate(half), np.concatenate(shown)
    who, nxt = np.concatenate(owner), np.concatenate(follow)
    seg = b - a
    length = np.hypot(seg[:, 0], seg[:, 1])
    vis &= length > 1e-12
    direction = seg / np.where(length > 1e-12, length, 1.0)[:, None]
    normal = np.column_stack([-direction[:, 1], direction[:, 0]]) * h[:, None]
    quads = np.stack([a + normal, b + normal, b - normal, a + normal, b - normal, a - normal], axis=1)[vis]
    quad_owner = who[vis]
    # Joins: at the end of segment i where the next segment of the same outline is also shown.
    cur = np.flatnonzero((nxt >= 0) & vis)
    cur = cur[vis[nxt[cur]]]
    nx = nxt[cur]
    cross = direction[cur, 0] * direction[nx, 1] - direction[cur, 1] * direction[nx, 0]
    turning = np.abs(cross) > 1e-9
    cur, nx, cross = cur[turning], nx[turning], cross[turning]
    vertex = b[cur]
    side = -np.sign(cross)[:, None]  # the outer side of the turn
    p0 = vertex + side * normal[cur]
    p1 = vertex + side * normal[nx]
    bisector = normal[cur] + normal[nx]
    bis_len = np.maximum(np.hypot(bisector[:, 0], bisector[:, 1]), 1e-12)
    cos_half = np.einsum("ij,ij->i", bisector, normal[cur]) / (bis_len * h[cur])
    ratio = 1.0 / np.maximum(cos_half, 1e-12)
    miter = ratio <= MITER_LIMIT
    tip = vertex + side * bisector / bis_len[:, None] * (h[cur] * ratio)[:, None]
    first = np.stack([vertex, p0, np.where(miter[:, None], tip, p1)], axis=1)
    second = np.stack([vertex[miter], tip[miter], p1[miter]], axis=1)
    tris = np.concatenate([quads.reshape(-1, 3, 2), first, second])
    tri_owner = np.concatenate([np.repeat(quad_owner, 2), who[cur], who[cur][miter]])
    order = np.argsort(tri_owner, kind="stable")
    tris, tri_owner = tris[order], tri_owner[order]
    bounds = np.searchsorted(tri_owner, np.arange(len(strokes) + 1))
    for k in range(len(strokes)):
        if bounds[k + 1] > bounds[k]:
            out[k] = tris[bounds[k]:bounds[k + 1]].reshape(-1, 2)
    return out


def visible_runs(edge_visible: np.ndarray, closed: bool) -> list[tuple[int, int]]:
    """Maximal runs of visible edges as ``(first_point, last_point)`` inclusive, for export.

    On a closed outline a run may wrap past point 0; then ``last_point < first_point``.
    ``(0, 0)`` with every edge of a closed outline visible means the whole closed loop.

    >>> visible_runs(np.array([True, True, False, True]), closed=False)
    [(0, 2), (3, 4)]
    >>> visible_runs(np.array([True, False, True, True]), closed=True)
    [(2, 1)]
    """
    e = len(edge_visible)
    if closed and edge_visible.all():
        return [(0, 0)]
    runs: list[tuple[int, int]] = []
    start = None
    order: list[int] | range = range(e)
    if closed:
        first_hidden = int(np.flatnonzero(~edge_visible)[0]) if (~edge_visible).any() else 0
        order = [(first_hidden + 1 + k) % e for k in range(e)]
    for i in order:
        if edge_visible[i] and start is None:
            start = i
        if not edge_visible[i] and start is not None:
            runs.append((start, i))
            start = None
    if start is not None:
        last = order[-1] + 1
        runs.append((start, last % e if closed else last))
    return runs
