"""The performer profile: where one performer's face rests and how far it moves.

A profile belongs to a performer, not to a character: one profile is re-used with every mapping
and every face. It holds, for every source a mapping may read (each marker coordinate in the
head frame, the head's yaw and pitch, and any derived measurement named when it was made), the
value at rest (``neutral``) and the range of motion (``low``, ``high``), plus the head's rest
rotation and the shape of the performer's head references. Saved as TOML (``format = "toonface.profile/1"``).

The neutral comes from a time range, a separate take, or the stillest window of the take; the
range from a calibration take (or a window of one) or from percentiles of the take itself.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from common import Failure, read_versioned, resolve_builtin, write_document
from common.validate import Validator
from mapping.head_axes import axes_note
from mapping.outliers import FRAMES_AT_ONCE
from mapping.robust import as_rows, column_groups, column_nan_median
from mapping.solver import Solver
from mapping.sources import Source, head_angles, measure, mm_scale
from mapping.stabilise import Stabilised, nearest_rotation

FORMAT = "toonface.profile/1"
#: A side of a range smaller than this (mm, or degrees for angles) counts as no motion.
MIN_RANGE = 0.5
#: A face source whose whole range is below this (mm, or degrees for angles) does not move in the
#: take: what it shows is incidental (a mouth corner drifting 1-4 mm while the brows act, measured
#: on the AnimFace takes, whose deliberate motions span 5-40 mm) and is not stretched to a range.
MIN_MOTION = 4.0
#: Such a source keeps at least this much either side of rest, so its drift moves its motor little.
STILL_SIDE = 10.0
#: Per kind of motor (a motor code's first letter), what its sources' :data:`MIN_MOTION` and
#: :data:`STILL_SIDE` are on a real face (mm): brows and the mouth move 10-40 mm, but lids travel
#: 2-10 mm (a lower lid 2-4) and pupils 3-6, so one threshold for all took a lower lid's whole
#: 3 mm squint for drift and kept it 10 mm either side of rest (its motor then hardly moved).
KIND_MOTION: dict[str, tuple[float, float]] = {"B": (MIN_MOTION, STILL_SIDE), "M": (MIN_MOTION, STILL_SIDE),
                                               "E": (1.0, 3.0), "P": (1.0, 4.0)}
#: A source moves if its range is this many times its own jitter, whatever its kind.
NOISE_FACTOR = 8.0


@dataclass(frozen=True)
class SourceRange:
    """A source's value at rest and the lowest and highest values of the performer's range."""

    neutral: float
    low: float
    high: float


@dataclass(frozen=True, eq=False)
class Profile:
    """A performer profile (see the module docstring).

    Attributes
    ----------
    markerset : str
    sources : dict of str to SourceRange
        Keyed by :attr:`Source.key`.
    rest_rotation : ndarray, shape (3, 3)
        The head at rest, head frame to world.
    performer : str
    notes : dict of str to str
        Where the neutral and the range came from, and sources left out for lack of motion.
    source : str
        The file it was read from ("" for one made in memory), for messages.
    full_range : bool
        The ranges come from a range-of-motion take (``calibrate --range``): the performer's
        whole range, which ``normalise = "calibrated"`` rules (the head's) then use.
    couplings : dict
        ``{source key: {driver source key: (below rest, above rest)}}``: how far a source moves,
        in shares of its range, per share of another motor's range (:mod:`mapping.coupling`).
    solver : Solver, optional
        What each motor does to every marker, learned from a range-of-motion sweep
        (:mod:`mapping.solver`): the motors it knows are solved all at once. Saved with the
        profile (its ``[solver]`` table) and read back.
    head_axes : ndarray, shape (3, 3), optional
        The head's own turning axes in the head frame, learnt from a range-of-motion take's head
        turns (:mod:`mapping.head_axes`): what the head's yaw and pitch are read about. Saved
        with the profile (``head_axes``); None: the head frame's axes.
    references : dict of str to ndarray, shape (3,)
        The performer's head references in the head frame (marker set label -> position, mm):
        the shape the calibration's head fit measured (:func:`mapping.stabilise.fit_head`), so
        that a live sender fits the head as the calibration did (:class:`mapping.stepwise.LiveMapper`).
        Saved with the profile (``references``); empty: the marker set's own shape.
    """

    markerset: str
    sources: dict[str, SourceRange]
    rest_rotation: np.ndarray
    performer: str = ""
    notes: dict[str, str] = field(default_factory=dict)
    source: str = ""
    full_range: bool = False
    couplings: dict[str, dict[str, tuple[float, float]]] = field(default_factory=dict)
    solver: Solver | None = None
    head_axes: np.ndarray | None = None
    references: dict[str, np.ndarray] = field(default_factory=dict)


def merge_profile(profile: Profile, own: Profile, missing: list[str], rest_from_take: bool,
                  rest: dict[str, np.ndarray] | None = None) -> Profile:
    """``profile`` with ``own``'s ranges for ``missing`` keys; with ``rest_from_take``, ``own``'s
    neutral values and rest rotation everywhere (the ranges' extents are kept around the new rest)
    and the solver's markers at ``rest`` (label -> head-frame position ``(3,)``, the take's own:
    :meth:`mapping.solver.Solver.at_rest`). The solver, couplings and notes are kept."""
    sources = dict(profile.sources)
    for key in missing:
        if key in own.sources:
            sources[key] = own.sources[key]
    rotation, solver = profile.rest_rotation, profile.solver
    if rest_from_take:
        rotation = own.rest_rotation
        for key, span in list(sources.items()):
            if key in own.sources:
                shift = own.sources[key].neutral - span.neutral
                sources[key] = type(span)(span.neutral + shift, span.low + shift, span.high + shift)
        if solver is not None and rest is not None:
            solver = solver.at_rest(rest)
    return replace(profile, sources=sources, rest_rotation=rotation, notes=dict(profile.notes), solver=solver)


def build_profile(neutral_take: Stabilised, neutral_times: np.ndarray, neutral_window: tuple[float, float],
                  range_take: Stabilised, range_frames: np.ndarray, columns: dict[str, int],
                  range_columns: dict[str, int], markerset: str, extra: Sequence[Source] = (),
                  percentiles: tuple[float, float] = (0.5, 99.5), performer: str = "",
                  notes: dict[str, str] | None = None, min_side: float = 0.0,
                  require_motion: bool = True, kinds: dict[str, str] | None = None,
                  head_axes: np.ndarray | None = None) -> Profile | Failure:
    """Measure a profile.

    Parameters
    ----------
    neutral_take, range_take : Stabilised
        Cleaned, head-stabilised takes (may be the same one) for the rest pose and the range;
        the range is measured on samples seen, not on gaps filled (``filled``), unless the gaps'
        guesses reach further: then the end itself was hidden, and a guess from neighbouring
        markers comes nearer it than the seen samples either side of the gap (the fourth
        performer's bench seed 5 lost both mouth corners at their widest: seen, the right one
        reached 4.1 mm of its 7.8; guessed, 7.7). The notes' ``from_guesses`` lists the ends of
        the mapping's sources (``extra``) that guesses took :data:`MIN_RANGE` or more further. A
        rest needs a sample seen in the rest window (:func:`seen_at`).
    neutral_times : ndarray, shape (F,)
        ``neutral_take``'s frame times.
    neutral_window : tuple of float
        Seconds ``[start, end)`` of ``neutral_take`` at rest.
    range_frames : ndarray of bool
        Frames of ``range_take`` to take the range from.
    columns, range_columns : dict
        Marker-set label -> column in each take.
    extra : list of Source
        Derived sources (distances, differences, angles) to measure besides every marker axis.
    percentiles : tuple of float
        Low and high percentiles of the range frames taken as the range's ends.
    require_motion : bool
        Fail when no face source moves (a calibration must see the range; a profile made only
        for its rest values need not).
    min_side : float
        Each side of a face source's range reaches at least this far from rest (mm, or degrees
        for angles), so that a take that hardly moves a marker does not stretch its jitter over
        the motor's whole range (for ranges taken from an ordinary take, not a calibration).
    kinds : dict of str to str, optional
        For a range-of-motion take: source key -> the kind of motor it drives
        (:data:`KIND_MOTION`'s letters), so that what counts as moving, and the range a still
        source keeps, follow its kind. A source moves when its range is at least its kind's
        minimum (:data:`MIN_MOTION` without a kind), or :data:`NOISE_FACTOR` times its own jitter
        (the median frame-to-frame change, as a standard deviation), whichever is larger.
    head_axes : ndarray, shape (3, 3), optional
        The head's own turning axes (:func:`mapping.head_axes.turning_axes`): the head's angles
        are read about them, and the profile keeps them (said in its notes).

    Returns
    -------
    Profile, or Failure saying why (no frame at rest with a head pose, no motion at all).
    """
    start, end = neutral_window
    at_rest = (neutral_times >= start) & (neutral_times < end) & neutral_take.ok
    if not at_rest.any():
        return Failure(f"no frame with a head pose in the neutral window {start:g}-{end:g} s")
    usable = range_frames & range_take.ok
    if usable.sum() < 2:
        return Failure("fewer than 2 frames with a head pose in the range frames")
    rest = nearest_rotation(neutral_take.rotation[at_rest].mean(axis=0))
    labels = [m for m in columns if m in range_columns]
    wanted = [Source("marker", (m,), axis) for m in labels for axis in range(3)]
    wanted += [Source("head", axis=a) for a in (0, 1)]
    wanted += [s for s in extra if all(m in columns and m in range_columns for m in s.markers)]
    rest_values = _measure_all(wanted, seen_at(neutral_take, at_rest), columns,
                               head_angles(neutral_take.rotation[at_rest], rest, head_axes),
                               {k: v[at_rest] for k, v in neutral_take.channels.items()})
    every = usable.all()  # the usual case: no copy of a long take's markers
    local = range_take.local if every else range_take.local[usable]
    head = head_angles(range_take.rotation if every else range_take.rotation[usable], rest, head_axes)
    channels = {k: v if every else v[usable] for k, v in range_take.channels.items()}
    made_up = None if range_take.filled is None else range_take.filled if every else range_take.filled[usable]
    low, high, jitter = (np.empty(len(wanted)) for _ in range(3))
    guessed_ends: set[str] = set()  # the ends of sources the mapping reads that guesses took further
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # sources never seen: all-NaN columns
        rest_value = column_nan_median(rest_values)
        for part in column_groups(len(wanted)):  # a few sources at a time: an hour's every source at once was
            group = [wanted[i] for i in part]   # 350 MB more of the take's peak memory
            values = _measure_all(group, local, range_columns, head, channels)
            guesses: dict[int, np.ndarray] = {}  # index in the group -> its values, guesses kept
            if made_up is not None:  # a range is what the performer was seen to do, not a gap's guess
                for i, source in enumerate(group):
                    if source.markers and np.isfinite(values[:, i]).any():
                        guessed = made_up[:, [range_columns[m] for m in source.markers]].any(axis=1)
                        if 0 < guessed.mean() < 0.5:  # a source seen so little keeps its guesses rather than nothing
                            guesses[i] = values[:, i].copy()
                            values[guessed, i] = np.nan
            low[part], high[part] = _nan_percentiles(values, percentiles)
            everything = np.arange(len(part))
            steps = np.abs(np.diff(as_rows(values, everything), axis=1)).T  # (F - 1, part), each column in order
            jitter[part] = 1.4826 * column_nan_median(steps) / np.sqrt(2)
            if guesses:  # unless the guesses reach further: then the end itself was hidden, and guessed
                at = part[list(guesses)]
                guess_low, guess_high = _nan_percentiles(np.column_stack(list(guesses.values())), percentiles)
                beyond = np.array([MIN_RANGE * mm_scale(wanted[i].key) for i in at])
                for which, grew in (("low", low[at] - guess_low > beyond), ("high", guess_high - high[at] > beyond)):
                    guessed_ends |= {f"{wanted[i].key} {which}" for i in at[grew] if wanted[i] in extra}
                low[at], high[at] = np.fmin(low[at], guess_low), np.fmax(high[at], guess_high)
    ranges: dict[str, SourceRange] = {}
    still: list[str] = []
    moving: list[str] = []  # face sources that move at all (a static take cannot be calibrated)
    for i, source in enumerate(wanted):
        if not np.isfinite([rest_value[i], low[i], high[i]]).all():
            continue
        lo, hi = min(low[i], rest_value[i]), max(high[i], rest_value[i])
        unit = mm_scale(source.key)  # thresholds in mm, as a blendshape score's worth
        if source.kind != "head" and hi - lo >= MIN_RANGE * unit:
            moving.append(source.key)
        if source.kind != "head":
            least, still_side = KIND_MOTION.get((kinds or {}).get(source.key, ""), (MIN_MOTION, STILL_SIDE))
            side = min_side * unit
            if hi - lo < max(least * unit, NOISE_FACTOR * jitter[i]):
                still.append(source.key)
                side = max(side, still_side * unit)
            lo, hi = min(lo, rest_value[i] - side), max(hi, rest_value[i] + side)
        elif hi - lo < MIN_RANGE:
            still.append(source.key)
        ranges[source.key] = SourceRange(float(rest_value[i]), float(lo), float(hi))
    if require_motion and not moving:
        return Failure(f"no motion: every face marker stays within {MIN_RANGE:g} mm of its rest over the range "
                       "frames")
    notes = dict(notes or {})
    if still:
        notes["no_motion"] = ", ".join(still)
    if guessed_ends:
        notes["from_guesses"] = ", ".join(sorted(guessed_ends))
    if head_axes is not None:
        notes["head_axes"] = axes_note(head_axes)
    return Profile(markerset, ranges, rest, performer, notes, head_axes=head_axes)


def save_profile(profile: Profile, path: str | os.PathLike) -> Path:
    """Write ``profile`` as TOML or JSON, as the suffix says (atomically)."""
    doc = {"format": FORMAT, "markerset": profile.markerset, "performer": profile.performer,
           "notes": dict(profile.notes), "rest_rotation": [[float(v) for v in row] for row in profile.rest_rotation],
           "sources": {k: {"neutral": r.neutral, "low": r.low, "high": r.high} for k, r in profile.sources.items()},
           "full_range": profile.full_range,
           "couplings": {k: {d: list(v) for d, v in drivers.items()} for k, drivers in profile.couplings.items()},
           **({"solver": profile.solver.to_dict()} if profile.solver is not None else {}),
           **({"head_axes": [[float(v) for v in row] for row in profile.head_axes]}
              if profile.head_axes is not None else {}),
           **({"references": {k: [float(v) for v in p] for k, p in profile.references.items()}}
              if profile.references else {})}
    return write_document(doc, path, "profile")


def load_profile(path: str | os.PathLike) -> Profile:
    """Read a profile (a file, or a built-in's bare name: ``toon32``, a typical face of that marker
    set); an unusable file raises :class:`InputError` naming the field."""
    path = resolve_builtin(path, "profiles", ".toml", "profile")
    doc = read_versioned(path, FORMAT, "profile")
    check = Validator(path)
    for key in ("markerset", "rest_rotation", "sources"):
        check.present(doc.get(key), key)
    rot = _rotation(check, doc["rest_rotation"], "rest_rotation")
    sources = check.fields(doc["sources"], doc["sources"] if isinstance(doc["sources"], dict) else (), "sources",
                           "a table of sources")
    ranges = {}
    for key, entry in sources.items():
        where = f'sources."{key}"'
        check.fields(entry, {"neutral", "low", "high"}, where, "a table { neutral, low, high }")
        neutral, low, high = (check.number(check.present(entry.get(k), f"{where}.{k}"), f"{where}.{k}")
                              for k in ("neutral", "low", "high"))
        check.require(low <= neutral <= high, f"expected low <= neutral <= high, got {low:g}, {neutral:g}, {high:g}",
                      where)
        ranges[key] = SourceRange(neutral, low, high)
    notes = doc.get("notes", {})
    return Profile(str(doc["markerset"]), ranges, rot, str(doc.get("performer", "")),
                   {str(k): str(v) for k, v in notes.items()} if isinstance(notes, dict) else {}, str(path),
                   check.boolean(doc.get("full_range", False), "full_range"),
                   _couplings(check, doc.get("couplings", {})),
                   Solver.from_dict(doc["solver"], check) if "solver" in doc else None,
                   _rotation(check, doc["head_axes"], "head_axes") if "head_axes" in doc else None,
                   _references(check, doc.get("references", {})))


def _rotation(check: Validator, doc: object, where: str) -> np.ndarray:
    rot = np.asarray(doc, dtype=float) if _is_matrix(doc) else None
    check.require(rot is not None and np.allclose(rot @ rot.T, np.eye(3), atol=1e-4), "expected a 3x3 rotation matrix",
                  where)
    assert rot is not None
    return rot


def _references(check: Validator, doc: object) -> dict[str, np.ndarray]:
    tables = check.fields(doc, doc if isinstance(doc, dict) else (), "references", "a table of markers")
    return {str(label): np.array(check.numbers(point, 3, f'references."{label}"')) for label, point in tables.items()}


def _couplings(check: Validator, doc: object) -> dict[str, dict[str, tuple[float, float]]]:
    tables = check.fields(doc, doc if isinstance(doc, dict) else (), "couplings", "a table of sources")
    out: dict[str, dict[str, tuple[float, float]]] = {}
    for key, drivers in tables.items():
        where = f'couplings."{key}"'
        for driver, pair in check.fields(drivers, drivers if isinstance(drivers, dict) else (), where).items():
            below, above = check.numbers(pair, 2, f'{where}."{driver}"')
            out.setdefault(str(key), {})[str(driver)] = (below, above)
    return out


def seen_at(stable: Stabilised, rows: np.ndarray) -> np.ndarray:
    """The head-frame markers of ``stable`` at ``rows`` (a mask or indices), ``(F, N, 3)``, all
    NaN for a marker seen at none of them (each of its samples there unseen or a gap filled): a
    rest is never wholly a gap's estimate (a marker lost through the whole rest window has no
    rest, and calibrating says so). A marker seen at some keeps its filled samples too: measured
    on the few seen alone, a rest came out noisier (fitted error of two bench takes up 0.015)."""
    local = stable.local[rows]
    if stable.filled is None:
        return local
    unseen = (stable.filled[rows] | ~np.isfinite(local).all(axis=2)).all(axis=0)  # (N,)
    return np.where(unseen[None, :, None], np.nan, local) if unseen.any() else local


def _measure_all(sources: list[Source], local: np.ndarray, columns: dict[str, int], head: np.ndarray,
                 channels: dict[str, np.ndarray]) -> np.ndarray:
    """Every source's values, ``(F, len(sources))``; marker axes in one gather."""
    out = np.empty((len(local), len(sources)))
    plain = [i for i, s in enumerate(sources) if s.kind == "marker"]
    if plain:
        rows = [columns[sources[i].markers[0]] for i in plain]
        axes = [sources[i].axis for i in plain]
        for first in range(0, len(local), FRAMES_AT_ONCE):  # a block of frames at a time: no whole-take copy
            out[first:first + FRAMES_AT_ONCE, plain] = local[first:first + FRAMES_AT_ONCE, rows, axes]
    for i, source in enumerate(sources):
        if source.kind != "marker":
            out[:, i] = measure(source, local, columns, head, channels)
    return out


def _is_matrix(value: object) -> bool:
    return (isinstance(value, list) and len(value) == 3
            and all(isinstance(r, list) and len(r) == 3 and all(isinstance(v, (int, float)) for v in r) for r in value))


def _nan_percentiles(values: np.ndarray, percentiles: tuple[float, float]) -> np.ndarray:
    """``np.nanpercentile(values, percentiles, axis=0)`` of ``(F, C)``, ``(2, C)``: the columns
    without NaN all at once (numpy takes a NaN-aware percentile one column at a time)."""
    out = np.empty((len(percentiles), values.shape[1]))
    for part in column_groups(values.shape[1]):  # a few at a time: a long take's sorted copies stay small
        rows = as_rows(values, part)  # each column's values in order: its partial sort runs through memory so
        whole = ~np.isnan(rows).any(axis=1)
        if whole.any():
            out[:, part[whole]] = np.percentile(rows[whole], percentiles, axis=1)
        if not whole.all():
            out[:, part[~whole]] = np.nanpercentile(rows[~whole], percentiles, axis=1)
    return out
