"""A performer's face learned from a range-of-motion sweep, and every frame solved for all motors at once.

Per-channel rules read each motor from its own markers, so a face's cross-talk reads as motion
it is not: a smile pushes the lower lids up and reads as a lid raise, a jaw's hinge moves the
chin back as well as down. Production facial solvers learn each performer instead (blendshape
weight solving from a range of motion: Joshi et al. 2003; Lewis et al. 2014, "Practice and
Theory of Blendshape Facial Models"). Here:

**Learning** (:func:`learn_solver`). A range-of-motion sweep moves each group of motors (a
mirror pair, or a whole brow) to each end while the rest of the face stays at rest. Over the
sweep, the rules say how far along its way each motor is (its signed share, -1 at its low end,
+1 at its high end: :func:`mapping.mapper.rule_shares`). In each frame the motors within
:data:`TOGETHER` of the furthest along (at least :data:`MOVED` of its way) are the ones moving,
a share past the end of its way counting as the end (a sweep takes each group to its ends, no
further: a rule that reads more is reading another group's motion, and a lower lid read at 1.5
while the jaw opened, the jaw at 1.0, took the jaw's markers as its own);
each marker goes to the moving motor whose own markers (those its rule reads) are nearest, a
tie (the midline between a mirror pair) half each; and every marker's head-frame displacement
from rest is regressed through rest on its motor's share, one side of rest at a time: a basis
per motor and side, ``(markers, 3)``, which holds whatever the sweep showed that motor doing to
the markers near it (the lower lid a smile lifts, when no lid motor moves with the smile).
Only samples that were seen count (a filled gap would teach the filler's guess back), and the
regression is robust (:func:`mapping.solver_sides.side_basis`): a sweep has label swaps and spikes too. A marker that
is a motor's in under :data:`mapping.solver_sides.MOSTLY` of the frames that see it is not its. A side the sweep
showed without any of the motor's own markers in view, where its mirror motor's was seen, is the mirror's side
mirrored (:func:`mapping.solver_sides.from_mirror`; the profile's notes say which). A side the sweep did
not show, or a marker it did not see on one side, is the other side through rest (a marker
scaled as the motor's own markers reach on the two sides, :func:`mapping.solver_sides.either_side`). A marker a
motor moves by less than :data:`SMALL_SHARE` of its furthest one (:data:`WOBBLE_MM` at most; for
a marker another rule reads, :data:`OTHERS_SHARE` of what that rule's motor moves it by, if less),
or by less than :data:`SMALL_MM` (:data:`OTHERS_MM` for a marker its rule does not read), is not its;
and a side that then moves none of its own markers is not learned (a jaw's closing past rest that
moved only a corner by 0.16 mm read every frame as the jaw clenched far past its end). Where a
mapping says a rule's markers show another motor's motion (``decouple``: raised brows lift the
upper lids), that motor takes those markers while it moves in the sweep (and their own motor does
not; of several it names moving at once, the one named first), however near another mover's
markers are, and keeps what it does to them down to
:data:`SMALL_MM`: a whole brow swept at once gave the lid's lift to the nearest of its three
motors, not the one the mapping names, or dropped it below the wobble's threshold, and every
raised brow then read as the lid opening.

The rules' shares tell the moving motors apart only while no rule reads another group's motion
as more than :data:`TOGETHER` of its own range: a rule that reads a jaw's opening as a full
smile (its range on that side set by the jaw) moves with the jaw, and takes the jaw's markers
near it.

**Solving** (:meth:`Solver.solve`). Each frame's displacements are explained by all motors at
once: least squares over every seen marker, each motor's basis the one of the side its share is
on (chosen by a first solve with the two sides' mean), a little ridge towards rest, shares
clipped to ±:data:`mapping.solver_frames.REACH`. Markers the take lost that frame, or that
cleaning filled, are absent from it, not believed. Then twice, robust weights (Cauchy, at
:data:`mapping.solver_sides.ROBUST_SCALE` times the sweep's own residual) down-weight a marker
that the motors cannot explain (an outlier, a swapped label), and the frame is solved again
(:mod:`mapping.solver_frames`: motors that share no marker are solved apart). Each motor's
confidence is the share of its basis's motion on markers that counted; below
:data:`MIN_CONFIDENCE` the motor is unseen that frame
(NaN: the loss policy of :mod:`mapping.rules` takes over, as for a rule with no source seen).
Where the take lost a head reference, the head fitted on the others turns with the slide of
those left; the sweep's slides of the references, where the take bears them out, say by how
much, and those frames are solved again without it (:mod:`mapping.solver_slide`).

The solver gives each solved motor's share; the rest of a rule (gain, offset, curve, clamp) and
the per-frame rules (filters, loss) stay as they are, offline and live alike. A profile keeps its
solver (``calibrate --solve``; :meth:`Solver.to_dict`), so ``map --profile`` solves with it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from common.validate import Validator
from mapping.robust import column_nan_median
from mapping.solver_frames import Layout, solve_frames
from mapping.solver_sides import either_side, from_mirror, own_motion, side_basis
from mapping.solver_slide import MIN_WHOLE, reference_motion, take_out

#: A motor this far along its way (a share) and leading the face shows what it does.
MOVED = 0.3
#: Motors at least this share of the leader's way move together in that frame (a group swept at once).
TOGETHER = 0.7
#: A marker within this (mm) of being as near one moving motor's markers as another's is shared.
TIE_MM = 1.0
#: A marker a motor moves by less than this share of its furthest marker's motion, or by less than
#: this (mm per unit of share), is not moved by it: a head fit's wobble moves the chin by a few
#: tenths of a millimetre with whatever moves, and left in a lid's basis it reads speech as a squint.
SMALL_SHARE = 0.1
SMALL_MM = 0.15
#: ... but a motor that moves a marker by more than this (mm per unit of share) moves it: a head
#: fit's wobble is a few tenths, and a tenth of a jaw's chin (5 mm) left out the mouth corners'
#: drop as the jaw opens, which the solver then read as the corners pulled down (MRV).
WOBBLE_MM = 1.0
#: A marker that is not one the motor's rule reads is its only from this (mm per unit of share): a
#: head fit's wobble with a lid's 3 mm sweep moved the lips by 0.3-0.5 mm, past a tenth of the lid,
#: and speech then read as the lid moving (the third performer's lowest r 0.941 -> 0.955 on the
#: bench's seeds, 0.895 -> 0.950 on four others).
OTHERS_MM = 0.5
#: ... and it is from that, however far the motor moves its own, where the motor moves it by this
#: share of what the marker's own motor does: the fourth performer's smile lifts a lower lid
#: 0.7-0.8 mm a share, under a tenth of the mouth corner's 9 but a fifth to a third of the lid's
#: own 2.3-4.1, and left out, the solver read every smile as the lid raised. Chosen on draws kept
#: apart from the bench's seeds (31-34) among 0.1, 0.15, 0.25 and 0.35: the fourth performer's mean
#: 1.975 -> 1.938 % (0.1 the same, 0.25: 1.941, 0.35: 1.970), the other three's unchanged.
OTHERS_SHARE = 0.15
#: Frames on a side of rest needed to learn that side.
MIN_FRAMES = 8
#: A motor whose seen share of its basis's motion is below this is unseen in that frame.
MIN_CONFIDENCE = 0.25
#: A motor whose basis moves the markers less than this (mm, summed in quadrature) is not
#: observable from the markers the take has.
MIN_MOTION_MM = 0.5
#: A lost reference's slide (:mod:`mapping.solver_slide`) that moves no marker by more than this
#: (mm) leaves the frame as it was solved.
SHIFT_MM = 0.02
#: Frames solved at once (bounds the memory: each frame's sums of its markers' Grams).
CHUNK = 2048


@dataclass(frozen=True, eq=False)
class Solver:
    """A performer's motors as marker motion (see the module docstring).

    Attributes
    ----------
    codes : tuple of str, length K
        The motors solved, in the order of the share columns.
    markers : tuple of str, length M
        The markers read.
    rest : ndarray, shape (M, 3)
        Where each marker rests, head frame, mm.
    up, down : ndarray, shape (K, M, 3)
        Each marker's displacement per unit of share on the high side (share > 0) and the low
        side (share < 0): a share ``s`` moves it by ``s * up`` or ``s * down``.
    noise : float
        The sweep's residual per marker (mm), the robust weights' scale.
    unobservable : tuple of str
        Motors the sweep moved but the markers did not show (left to the rules).
    unswept : tuple of str
        Motors read from markers that the sweep never moved alone (left to the rules).
    notes : dict
    references : tuple of str, length R
        The head references among ``markers`` (the head frame is fitted on them).
    slide_up, slide_down : ndarray, shape (K, R, 3)
        What each motor does to them, per unit of share on each side, in the head fitted on all
        of them (what the sweep showed, none of it left out): how a head fitted on fewer sits
        (:mod:`mapping.solver_slide`). ``(K, 0, 3)`` where the profile predates them.
    """

    codes: tuple[str, ...]
    markers: tuple[str, ...]
    rest: np.ndarray
    up: np.ndarray
    down: np.ndarray
    noise: float
    unobservable: tuple[str, ...] = ()
    notes: dict[str, str] = field(default_factory=dict)
    unswept: tuple[str, ...] = ()
    references: tuple[str, ...] = ()
    slide_up: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 3)))
    slide_down: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 3)))

    def to_dict(self) -> dict[str, Any]:
        """The solver as a profile's ``[solver]`` table (:func:`from_dict` reads it back equal)."""
        return {"codes": list(self.codes), "markers": list(self.markers), "noise": float(self.noise),
                "unobservable": list(self.unobservable), "unswept": list(self.unswept), "notes": dict(self.notes),
                "rest": np.round(self.rest, 6).tolist(), "up": np.round(self.up, 6).tolist(),
                "down": np.round(self.down, 6).tolist()} | ({} if not self.references else {
                    "references": list(self.references), "slide_up": np.round(self.slide_up, 6).tolist(),
                    "slide_down": np.round(self.slide_down, 6).tolist()})

    @classmethod
    def from_dict(cls, doc: Any, check: Validator) -> Solver:
        """A profile's ``[solver]`` table as a solver; a field that cannot be one raises
        :class:`InputError` naming it (through ``check``)."""
        table = check.fields(doc, {"codes", "markers", "noise", "unobservable", "unswept", "notes", "rest",
                                   "up", "down", "references", "slide_up", "slide_down"},
                             "solver", "a table")
        codes, markers = check.strings(table.get("codes", []), "solver.codes"), check.strings(
            table.get("markers", []), "solver.markers")
        references = check.strings(table.get("references", []), "solver.references")
        check.require(set(references) <= set(markers), "expected markers the solver reads", "solver.references")
        slides = (("slide_up", (len(codes), len(references), 3)),
                  ("slide_down", (len(codes), len(references), 3))) if references else ()
        # a profile written before the slides has none: its references are taken as still
        arrays: dict[str, np.ndarray] = {name: np.zeros((len(codes), 0, 3)) for name in ("slide_up", "slide_down")}
        for name, shape in (("rest", (len(markers), 3)), ("up", (len(codes), len(markers), 3)),
                            ("down", (len(codes), len(markers), 3)), *slides):
            try:
                arrays[name] = np.asarray(table.get(name), dtype=float)
            except (TypeError, ValueError):
                arrays[name] = np.zeros(0)
            check.require(arrays[name].shape == shape and bool(np.isfinite(arrays[name]).all()),
                          f"expected {' x '.join(map(str, shape))} finite numbers", f"solver.{name}")
        notes = table.get("notes", {})
        return cls(tuple(codes), tuple(markers), arrays["rest"], arrays["up"], arrays["down"],
                   check.number(table.get("noise", 0.0), "solver.noise", 0.0),
                   tuple(check.strings(table.get("unobservable", []), "solver.unobservable")),
                   {str(k): str(v) for k, v in notes.items()} if isinstance(notes, dict) else {},
                   tuple(check.strings(table.get("unswept", []), "solver.unswept")), tuple(references),
                   arrays["slide_up"], arrays["slide_down"])

    def left_out(self) -> str:
        """What the solver leaves to the rules and why, and the sides it took from a mirror motor's
        (:func:`mapping.solver_sides.from_mirror`), for a note: ``""`` where nothing."""
        parts = ([f"{', '.join(self.unswept)} not moved alone by the sweep"] if self.unswept else []) + \
            ([f"{', '.join(self.unobservable)} not shown by the markers"] if self.unobservable else [])
        mirrored = self.notes.get("from_mirror")
        return (f"; {'; '.join(parts)} (left to the rules)" if parts else "") + (
            f"; {mirrored} taken from the mirror motor's (the sweep never saw the motor's own markers there)"
            if mirrored else "")

    def at_rest(self, rest: Mapping[str, np.ndarray]) -> Solver:
        """The same solver about another rest: ``rest`` (label -> head-frame position ``(3,)``,
        mm) where a marker rests now (a take's own rest, live or offline; a marker it lacks or
        that is not finite keeps the sweep's). What a motor does to each marker stays."""
        moved = self.rest.copy()
        for k, name in enumerate(self.markers):
            if name in rest and np.isfinite(rest[name]).all():
                moved[k] = rest[name]
        return replace(self, rest=moved)

    @cached_property
    def layout(self) -> Layout:
        """What every solve with these bases shares (:class:`mapping.solver_frames.Layout`), made once."""
        return Layout.of(self.up, self.down)

    def solve(self, local: np.ndarray, columns: dict[str, int], trust: np.ndarray | None = None,
              quality: np.ndarray | None = None, fade: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
        """Each solved motor's share and confidence, both ``(F, K)``, from head-frame markers
        ``local`` ``(F, N, 3)`` (``columns``: label -> column); ``trust`` ``(F, N)``: how far the
        fit believes each sample, 0 to 1 (default: 1 where finite); ``quality`` ``(F, N)``: what
        each sample counts for in the confidence (default: ``trust``); ``fade``: the frames the bridge
        faded over (:func:`mapping.reference_bridge.fade_frames` of the take's rate). A share is NaN
        where its confidence is below :data:`MIN_CONFIDENCE`."""
        used = self.layout.used  # the markers some motor moves: no other adds to a frame's equations
        cols, rest = np.array([columns[m] for m in self.markers])[used], self.rest[used]
        shares = np.empty((len(local), len(self.codes)))
        confidence = np.empty_like(shares)
        frames, motion = np.arange(len(local)), np.zeros((len(local), 6))
        for again in (False, True):  # again where a lost reference's slide moved the head (mapping.solver_slide)
            for start in range(0, len(frames), CHUNK):
                part = frames[start:start + CHUNK]
                rows = part[:, None]  # with ``cols``: each frame's used markers
                d = local[rows, cols] - rest
                d = take_out(d, rest, motion[part]) if again else d
                ok = np.isfinite(d).all(axis=2)
                weight = ok if trust is None else np.where(ok, trust[rows, cols], 0.0)
                counts = weight if quality is None else np.where(ok, quality[rows, cols], 0.0)
                shares[part], confidence[part] = solve_frames(self.layout, self.noise, np.where(ok[..., None], d, 0.0),
                                                              weight.astype(float), counts.astype(float))
            if again or not self.references or len(local) < MIN_WHOLE:  # too few frames to bear slides out: live
                break
            refs, at = [columns[m] for m in self.references], [self.markers.index(m) for m in self.references]
            seen = np.isfinite(local[:, refs]).all(axis=2) & (True if quality is None else quality[:, refs] >= 1.0)
            motion = reference_motion(shares, self.slide_up, self.slide_down, self.rest[at], seen,
                                      local[:, refs] - self.rest[at], fade)
            lever = float(np.abs(self.rest).max(initial=0.0))  # (mm) the furthest marker from the origin
            frames = np.flatnonzero(np.linalg.norm(motion[:, :3], axis=1) * lever
                                    + np.linalg.norm(motion[:, 3:], axis=1) > SHIFT_MM)
        return np.where(confidence >= MIN_CONFIDENCE, shares, np.nan), confidence


def rests_of(local: np.ndarray, columns: dict[str, int]) -> dict[str, np.ndarray]:
    """Each marker's rest, by label (``columns``: label -> column): its median over the frames of
    head-frame markers ``local`` ``(F, N, 3)`` where it was seen, ``(3,)``, NaN where it never
    was (:meth:`Solver.at_rest` keeps the sweep's there)."""
    at_rest = column_nan_median(local.reshape(len(local), -1)).reshape(local.shape[1:])
    return {label: at_rest[column] for label, column in columns.items()}


def learn_solver(codes: Sequence[str], own_markers: Sequence[Sequence[str]], local: np.ndarray,
                 columns: dict[str, int], seen: np.ndarray, shares: np.ndarray, rest: np.ndarray,
                 references: Sequence[str] = (), couples: Sequence[Sequence[str]] = ()) -> Solver | None:
    """A :class:`Solver` from a range-of-motion sweep (see the module docstring).

    Parameters
    ----------
    codes : sequence of str, length K
        The motors the sweep moves (the head's too: a face motor is not learned from frames
        where the head leads).
    own_markers : sequence of sequence of str, length K
        The markers each motor's rule reads; a motor with none (the head's) is not learned.
    local : ndarray, shape (F, N, 3)
        The sweep's head-frame markers.
    columns : dict
        Label -> column of ``local``; every marker in it is read.
    seen : ndarray of bool, shape (F, N)
        Samples seen (not lost, not filled).
    shares : ndarray, shape (F, K)
        Each motor's signed share of its way by the rules over the sweep (NaN unseen).
    rest : ndarray, shape (N, 3)
        Each marker at rest.
    references : sequence of str
        The head references: the head frame is fitted on them, so what they do in it is the
        fit's wobble, and they are no motor's but one whose rule reads them (third performer,
        a draw whose nose tip wobbled 0.5 mm in a lid's sweep: the lid then read the still nose
        as held shut, ERU r 0.78).
    couples : sequence of sequence of str, length K or empty
        The motors whose motion each motor's rule says its markers show (a mapping's
        ``decouple``: raised brows lift the upper lids): while such a motor moves in the sweep,
        those markers are its (of several moving at once, the first named's), however near
        another mover's markers are, and what it does to them is kept down to :data:`SMALL_MM`.

    Returns
    -------
    Solver or None
        None where no motor read from markers led the face anywhere in the sweep.
    """
    markers = tuple(sorted(columns, key=columns.__getitem__))
    cols = [columns[m] for m in markers]
    fixed = np.isin(markers, list(references))  # (M,): the head references
    d = local[:, cols] - rest[cols]
    ok = seen[:, cols] & np.isfinite(d).all(axis=2)
    d = np.where(ok[..., None], d, 0.0)
    size = np.minimum(np.abs(np.nan_to_num(shares, nan=0.0)), 1.0)  # past its end is at its end
    lead = size.max(axis=1, keepdims=True)
    movers = (lead >= MOVED) & (size >= TOGETHER * lead)  # (F, K): the motors the sweep moves in each frame
    learnable = [k for k in range(len(codes)) if any(m in columns for m in own_markers[k])]
    far = np.full((len(markers), len(codes)), np.inf)  # each marker's distance from each motor's own markers
    for k in learnable:
        own = rest[[columns[m] for m in own_markers[k] if m in columns]]
        far[:, k] = np.linalg.norm(rest[cols][:, None] - own[None], axis=2).min(axis=1)
    # each moving marker goes to the nearest mover (ties, such as the midline between a mirror pair, shared)
    reach = np.where(movers[:, None, :], far[None], np.inf)  # (F, M, K)
    nearest = reach.min(axis=2, keepdims=True)
    share = (reach <= nearest + TIE_MM) & np.isfinite(reach)
    share = share / np.maximum(share.sum(axis=2, keepdims=True), 1)
    driven = _driven(codes, own_markers, couples, markers)  # (M, K): 1 for the first named, 0 for none
    coupled = driven > 0
    if coupled.any():  # such a marker is its driver's while the driver moves and its own motor does not
        own_moves = (movers[:, None, :] & (far == 0.0)[None]).any(axis=2, keepdims=True)  # (F, M, 1)
        forced = movers[:, None, :] & coupled[None] & ~own_moves  # (F, M, K)
        first = np.where(forced, driven[None], np.iinfo(np.int64).max).min(axis=2, keepdims=True)
        forced &= driven[None] == first  # drivers moving together: the one the mapping names first
        share = np.where(forced.any(axis=2, keepdims=True), forced / np.maximum(forced.sum(axis=2, keepdims=True), 1),
                         share)
    up = np.zeros((len(codes), len(markers), 3))
    down = np.zeros_like(up)
    slide_up = np.zeros((len(codes), int(fixed.sum()), 3))
    slide_down = np.zeros_like(slide_up)
    learned: dict[int, list[tuple[np.ndarray, np.ndarray] | None]] = {}
    for k in learnable:
        learned[k] = []
        for sign in (1.0, -1.0):  # a side is what the frames where this motor moves that way show
            at = movers[:, k] & (sign * np.nan_to_num(shares[:, k]) >= MOVED)
            learned[k].append(side_basis(shares[at, k], ok[at], share[at, :, k], d[at]) if at.sum() >= MIN_FRAMES
                              else None)
    mirrored = from_mirror(codes, learned, far, rest[cols])
    shown = [k for k in learnable if learned[k][0] is not None or learned[k][1] is not None]
    for k in shown:
        up[k], down[k] = either_side(learned[k][0], learned[k][1], far[:, k] == 0.0)
    own_reach = own_motion(up, down, far == 0.0)  # (M,): what each marker's own motor moves it by
    share_of_own = np.where(own_reach > 0.0, OTHERS_SHARE * own_reach, np.inf)  # (M,): no rule's, no cap
    for k in shown:
        slide_up[k], slide_down[k] = up[k][fixed], down[k][fixed]  # all of it: the head fit's share-out
        furthest = float(np.linalg.norm(np.concatenate([up[k], down[k]]), axis=1).max())
        least = min(SMALL_SHARE * furthest, WOBBLE_MM)
        small = np.where(far[:, k] > 0.0, np.maximum(np.minimum(least, share_of_own), OTHERS_MM),
                         max(least, SMALL_MM))  # (M,): others, own
        small = np.where(coupled[:, k], SMALL_MM, small)  # (M,): a coupling the mapping declares, down to the noise
        for basis in (up[k], down[k]):  # what a motor does to a marker is what stands above the sweep's wobble
            basis[np.linalg.norm(basis, axis=1) < small] = 0.0
            basis[fixed & (far[:, k] > 0.0)] = 0.0
            if not np.linalg.norm(basis[far[:, k] == 0.0], axis=1).any():  # a side that moves none of its own
                basis[:] = 0.0  # markers is not the motor's: its share would run wild on another's tenths of a mm
    up, down = np.nan_to_num(up), np.nan_to_num(down)
    motion = np.sqrt(np.maximum((up ** 2).sum(axis=(1, 2)), (down ** 2).sum(axis=(1, 2))))
    observable = [k for k in shown if motion[k] >= MIN_MOTION_MM]
    if not observable:
        return None
    unswept = tuple(codes[k] for k in learnable if k not in shown)  # no side of it led the face long enough
    unobservable = tuple(codes[k] for k in shown if k not in observable)
    notes = {"from_mirror": ", ".join(mirrored)} if mirrored else {}
    solver = Solver(tuple(codes[k] for k in observable), markers, rest[cols], up[observable], down[observable], 1.0,
                    unobservable, notes, unswept, tuple(m for m, f in zip(markers, fixed, strict=True) if f),
                    np.nan_to_num(slide_up[observable]), np.nan_to_num(slide_down[observable]))
    used = solver.layout.used
    fitted, _ = solve_frames(solver.layout, solver.noise, d[:, used], ok[:, used].astype(float), robust=False)
    moved = fitted[..., None, None] * np.where(fitted[..., None, None] >= 0, solver.up, solver.down)
    residual = np.linalg.norm(d - moved.sum(axis=1), axis=2)[ok]
    noise = max(float(np.median(residual)), 0.05) if residual.size else 1.0
    return replace(solver, noise=noise)


def _driven(codes: Sequence[str], own_markers: Sequence[Sequence[str]], couples: Sequence[Sequence[str]],
            markers: Sequence[str]) -> np.ndarray:
    """``(M, K)``: where a motor's rule says its marker shows another motor's motion (``couples``,
    a mapping's ``decouple``), the driving motor's place in that list (1 for the first named) in
    the marker's row and the driver's column; 0 elsewhere."""
    out = np.zeros((len(markers), len(codes)), np.int64)
    for j, drivers in enumerate(couples):
        rows = [markers.index(m) for m in own_markers[j] if m in markers]
        for rank, code in enumerate(drivers, 1):
            if code in codes:
                out[rows, list(codes).index(code)] = rank
    return out
