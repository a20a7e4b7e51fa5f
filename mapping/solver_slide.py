"""The head frame the sweep was learned in, kept while a head reference is lost
(:meth:`mapping.solver.Solver.solve` uses it).

Real head references slide a little with the skin: a jaw opening drags the temples down and
back, raised brows the forehead up. With every reference seen, the head fit shares a slide out
among all of them, and the solver learns the face in that head frame. A head turned past 30
degrees hides the far temple; the fit on the others takes the near temple's slide, alone, as a
turn of the head, and every marker on the far side then moves with the jaw by that turn (the
fourth performer's: a lower lid 0.6 mm down for a jaw's full opening, a brow 1.7 mm, read as the
lid and brow moving; its lowest motor r 0.82). The cleaning's bridge
(:func:`mapping.reference_bridge.bridge_references`) carries the difference between the two fits
at the edges of the stretch across it, which holds while the slide stays as it was at the edges,
not while the jaw moves inside it.

The sweep shows what each motor does to the references in the head fitted on all of them (their
departures, a basis per motor and side like any marker's). So in a frame where some references
are lost, the departures the motors solved there give the seen ones imply how far the fit on
those alone sits from the fit on all (a small rigid motion, by least squares over the seen
references: :func:`rigid_shift`); that motion, less the one the bridge already carried across
(the same motion at the nearest frames either side that saw every reference, blended across the
stretch and faded into it as the bridge blends and fades them; a stretch with no such neighbour
the bridge left alone, and the whole motion is taken out), is taken out of every marker, and the
frame is solved again. The motion is the solved motors' alone, never the markers' jitter.

A sweep also teaches references that do not slide some motion (the head fit's jitter), so the
take must bear the slides out first (:func:`slide_gain`): over its frames that see every
reference, the slides its motors predict must explain how those references depart from rest.
Where they do not, or where a take has too few such frames to tell (live, a frame at a time),
nothing is taken out: the live mapper reads a lost reference's slide as the bridge-less head
fit has it, as before.

On the fourth performer (seeds 1-5 of ``python -m bench fidelity``, solver, fitted error) the
first seed's lowest motor r went 0.823 -> 0.894 (its left lower lid) and its error 1.533 ->
1.382 %; seeds 2 and 3 1.382 -> 1.367 and 2.080 -> 2.000; seeds 4 and 5 1.533 -> 1.550 and
1.921 -> 1.924. The other three performers' references do not slide, and nothing changes there.
"""

from __future__ import annotations

import numpy as np

from mapping.reference_bridge import across, enclosing, held, stretches

#: Frames that see every reference needed to bear the sweep's slides out (:func:`slide_gain`).
MIN_WHOLE = 100
#: ... and the share of the references' departures there that the slides must explain.
MIN_EXPLAINED = 0.25


def rigid_shift(rest: np.ndarray, departures: np.ndarray, seen: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The small rigid motion (rotation vector ``(F, 3)``, radians, and translation ``(F, 3)``,
    mm) that the head fitted on the references ``seen`` ``(K,)`` alone makes when they depart from
    their rest ``rest`` ``(K, 3)`` (head frame) by ``departures`` ``(F, K, 3)`` in the head fitted
    on all of them: the least-squares ``w, t`` with ``p + w x p + t = rest`` for each seen reference
    ``p = rest + departure`` (to first order in the small motion).

    >>> rest = np.array([[-60.0, 10, -30], [60, 10, -30], [0, 50, 10], [0, -40, 30]])
    >>> w, t = rigid_shift(rest, np.tile([0.0, 1.0, 0.0], (1, 4, 1)), np.ones(4, bool))
    >>> (np.round(w, 6) + 0.0).tolist(), (np.round(t, 6) + 0.0).tolist()  # all up by 1: the fit moves them back
    ([[0.0, 0.0, 0.0]], [[0.0, -1.0, 0.0]])
    """
    p = rest[seen]
    design = np.zeros((len(p), 3, 6))  # (k, coordinate, [w, t]): w x p = -p x w
    design[:, 0, 1], design[:, 0, 2] = p[:, 2], -p[:, 1]
    design[:, 1, 0], design[:, 1, 2] = -p[:, 2], p[:, 0]
    design[:, 2, 0], design[:, 2, 1] = p[:, 1], -p[:, 0]
    design[:, :, 3:] = np.eye(3)
    solution = -departures[:, seen].reshape(len(departures), -1) @ np.linalg.pinv(design.reshape(-1, 6)).T
    return solution[:, :3], solution[:, 3:]


def reference_shift(rest: np.ndarray, departures: np.ndarray, seen: np.ndarray, fade: float = np.inf) -> np.ndarray:
    """How far the head fitted on the references seen sits from the one fitted on all of them,
    less what the bridge carried across, in each frame: the small rigid motion ``(F, 6)`` (a
    rotation vector, radians, and a translation, mm: :func:`rigid_shift`) to take out of the
    head-frame markers (:func:`take_out`; see the module docstring).

    Parameters
    ----------
    rest : ndarray, shape (K, 3)
        The head references at rest, head frame.
    departures : ndarray, shape (F, K, 3)
        Where the solved motors put each reference, from its rest, in each frame.
    seen : ndarray of bool, shape (F, K)
        The references seen in each frame.
    fade : float
        Over how many frames the bridge faded what it carried
        (:func:`mapping.reference_bridge.held`; ``np.inf``: carried whole).

    Returns
    -------
    ndarray, shape (F, 6)
        0 in frames that see every reference or fewer than three.
    """
    frames = len(seen)
    out = np.zeros((frames, 6))
    whole = np.asarray(seen.all(axis=1), dtype=bool)
    lost = ~whole & (seen.sum(axis=1) >= 3)
    if not lost.any():
        return out
    whole_at = np.flatnonzero(whole)
    for start, end in stretches(~seen):
        if not lost[start]:
            continue
        first, last = enclosing(whole_at, frames, start, end)
        edges = [f for f in (first - 1, last) if 0 <= f < frames and whole[f]]
        motion = np.hstack(rigid_shift(rest, departures[[*range(start, end), *edges]], seen[start]))
        inside = motion[:end - start]
        if edges:  # the bridge carried the edges' difference across: blended and faded as it does
            part = slice(start - first, end - first)
            share, kept = across(first, last)[part, None], held(first, last, fade)[part, None]
            inside = inside - kept * ((1 - share) * motion[end - start] + share * motion[-1])
        out[start:end] = inside
    return out


def take_out(d: np.ndarray, rest: np.ndarray, motion: np.ndarray) -> np.ndarray:
    """Head-frame displacements ``d`` ``(F, M, 3)`` of markers resting at ``rest`` ``(M, 3)``
    with the small rigid ``motion`` ``(F, 6)`` of :func:`reference_shift` taken out."""
    return d - np.cross(motion[:, None, :3], rest[None]) - motion[:, None, 3:]


def slide_gain(predicted: np.ndarray, observed: np.ndarray, whole: np.ndarray) -> float:
    """How far the take bears out the slides the sweep taught, 0 to 1: the least-squares gain of
    the references' ``predicted`` departures ``(F, R, 3)`` on their ``observed`` ones over the
    frames ``whole`` ``(F,)`` that see them all (each from its mean there); 0 where the slides
    explain less than :data:`MIN_EXPLAINED` of the observed, or with fewer than
    :data:`MIN_WHOLE` such frames (nothing to bear them out).

    A sweep teaches every reference some motion with every motor, most of it the head fit's
    jitter (0.1-0.4 mm on the project's performers whose references do not slide), and taken
    out as a slide it cost one of them 0.14 of a percent of fitted error (the own performer's
    first seed). So the take is asked: over the frames that see every reference, the slides the
    motors solved there predict explain 0.44-0.85 of how the fourth performer's references depart
    from rest (its temples and forehead slide) and at most 0.09 of the other three performers'
    (each performer's choice seeds 31-34 and bench seeds 1-5; :data:`MIN_EXPLAINED` lies between)."""
    if whole.sum() < MIN_WHOLE:
        return 0.0
    p, o = predicted[whole], observed[whole]
    p, o = p - p.mean(axis=0), o - o.mean(axis=0)  # a reference resting a little off its rest is no slide
    gain = float(np.sum(p * o) / max(float(np.sum(p * p)), 1e-12))
    explained = 1.0 - float(np.sum((o - gain * p) ** 2)) / max(float(np.sum(o * o)), 1e-12)
    return float(np.clip(gain, 0.0, 1.0)) if explained >= MIN_EXPLAINED else 0.0


def reference_motion(shares: np.ndarray, up: np.ndarray, down: np.ndarray, rest: np.ndarray, seen: np.ndarray,
                     observed: np.ndarray, fade: float = np.inf) -> np.ndarray:
    """:func:`reference_shift` of the departures that motors at ``shares`` ``(F, K)`` give the
    references, times :func:`slide_gain`, ``(F, 6)``.

    Parameters
    ----------
    shares : ndarray, shape (F, K)
    up, down : ndarray, shape (K, R, 3)
        Each motor's motion of the references per unit of share on each side.
    rest : ndarray, shape (R, 3)
    seen : ndarray of bool, shape (F, R)
    observed : ndarray, shape (F, R, 3)
        The references' head-frame departures from ``rest`` as the take has them.
    fade : float
        As :func:`reference_shift` has it.
    """
    flat_up, flat_down = up.reshape(len(up), -1), down.reshape(len(down), -1)
    departures = (np.maximum(shares, 0.0) @ flat_up + np.minimum(shares, 0.0) @ flat_down).reshape(len(shares), -1, 3)
    gain = slide_gain(departures, observed, np.asarray(seen.all(axis=1), dtype=bool))
    return reference_shift(rest, gain * departures, seen, fade) if gain > 0 else np.zeros((len(shares), 6))
