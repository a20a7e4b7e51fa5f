"""Take -> motor track in one call: find the mapping, clean, calibrate, map.

With no mapping named, the built-in preset whose marker set matches the take's labels is used.
With no profile, the marker set's built-in typical profile is used if it has one
(``data/profiles/``), with the rest pose taken from the take; otherwise one is made from the take
itself. Rest poses from the take come from ``neutral_window``: seconds, ``"first"`` (the first
second with a head pose), ``"stillest"``, or by default one chosen from the take's motion and,
for a video, its sound (:mod:`mapping.rest`: where nobody speaks; else the first second where
it is still, else the stillest);
ranges from the take itself are its 1st to 99th percentiles, at least :data:`SELF_MIN_SIDE` either
side of rest and at least a typical face's (:mod:`mapping.typical`). A profile that lacks a derived
source the mapping reads gets it from the take the same way. The track's metadata says which.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from capture import MarkerSet, Take, load_markerset
from capture.markerset import find_markerset
from capture.take import SOUND_LEVEL
from common import InputError, data_path
from mapping.clean import CleanSettings, clean_stabilised
from mapping.coupling import learn_couplings, recorded_jitter
from mapping.head_axes import turning_axes
from mapping.life import LifeSettings, add_life, take_cues
from mapping.mapfile import Mapping, load_mapping
from mapping.mapper import map_stabilised, marker_quality, normalise, rule_shares
from mapping.plan import MotorPlan, resolved_mode
from mapping.profile import KIND_MOTION, Profile, build_profile, merge_profile, seen_at
from mapping.ready import Prepared, ReadyTake
from mapping.report import take_report
from mapping.rest import choose_rest, stillest_window
from mapping.solver import Solver, learn_solver, rests_of
from mapping.sources import head_angles, measure
from mapping.sweep import mirror_lost_sides
from mapping.take_notes import solver_note, take_notes
from mapping.typical import TYPICAL, bound_by_typical, shut_lids, shut_note, typical_profile
from mapping.units import settle_units
from toon import MotorTrack, standard_neutral
from toon.motors import MOTOR_CODES

#: Ranges taken from the take being mapped reach at least this far each side of rest (mm or degrees).
SELF_MIN_SIDE = 4.0


def choose_mapping(take: Take, mapping: Mapping | str | None = None) -> tuple[Mapping, MarkerSet]:
    """The mapping to use for ``take`` (named, or the preset matching its labels) and its marker set.

    Raises
    ------
    InputError
        When no preset matches, or the take lacks the mapping's markers.
    """
    found = None
    if mapping is None and not take.labels and "viseme_A" in take.channel_names:
        mapping = "voice"  # a voice's mouth shapes
    if mapping is None:
        found = find_markerset(take.labels)
        if found is None or not data_path("mappings", f"{found.name}.toml").is_file():
            raise InputError(f"no built-in mapping matches its {len(take.labels)} markers "
                             f"({', '.join(take.labels[:6])}...): name one (--mapping, or mapping in a batch job), "
                             "or draft one for this layout (toonface markerset draft TAKE, then markerset mapping)",
                             take.meta.get("file"))
        mapping = found.name
    chosen = load_mapping(mapping) if isinstance(mapping, str) else mapping
    markerset = found if found is not None and found.name == chosen.markerset else load_markerset(chosen.markerset)
    chosen = _without_absent_markers(chosen, markerset, take)
    check_markers(chosen, markerset, take)
    return chosen, markerset


def _without_absent_markers(mapping: Mapping, markerset: MarkerSet, take: Take) -> Mapping:
    """``mapping`` without the rules that read a marker of the marker set the take lacks (a rig
    that covers part of the face; a dot-marker video has no pupils): their motors named in
    ``left_out`` (they stay at the face's neutral, never driven from the nearest markers there
    are), the markers in ``absent``, and motors no longer there dropped from the others'
    ``decouple``. The head references stay required (:func:`check_markers` names one missing)."""
    found = markerset.match(take.labels)
    absent = {m for m in markerset.labels if m not in found and m not in markerset.head_reference}
    reads = [(rule, {m for s in rule.sources for m in s.markers}) for rule in mapping.rules]
    out = {rule.code for rule, markers in reads if markers & absent}
    if not out:
        return mapping
    kept = tuple(replace(rule, decouple=tuple(c for c in rule.decouple if c not in out))
                 for rule in mapping.rules if rule.code not in out)
    lacking = sorted({m for rule, markers in reads if rule.code in out for m in markers & absent},
                     key=markerset.labels.index)
    return replace(mapping, rules=kept, left_out=(*mapping.left_out, *(r.code for r in mapping.rules if r.code in out)),
                   absent=(*mapping.absent, *lacking))


def check_markers(mapping: Mapping, markerset: MarkerSet, take: Take | None = None) -> None:
    """Every marker the mapping reads must be in its marker set (and in ``take``, if given, with
    every channel its blendshape sources read)."""
    found = markerset.match(take.labels) if take is not None else None
    for rule in mapping.rules:
        for i, source in enumerate(rule.sources):
            where = f"mapping {mapping.name}: motor.{rule.code}.sources[{i}]"
            if source.kind == "blendshape" and take is not None and source.channel not in take.channel_names:
                raise InputError(f'the take has no blendshape channel "{source.channel}" (a markerless take '
                                 "written as .npz keeps them)", None, where)
            for marker in source.markers:
                if marker not in markerset.labels:
                    raise InputError(f'marker "{marker}" is not in marker set {markerset.name}', None, where)
                if found is not None and marker not in found:
                    raise InputError(f'the take has no marker "{marker}"', None, where)


def prepare(take: Take, markerset: MarkerSet, settings: CleanSettings = CleanSettings()) -> Prepared:
    """Settle the take's units (:func:`mapping.units.settle_units`), clean and stabilise; raises
    :class:`InputError` for units given that cannot be a face, or saying why the head cannot be
    found."""
    take, units = settle_units(take, markerset)
    result = clean_stabilised(take, markerset, settings)
    if not result:
        raise InputError(f"cannot remove head motion: {result}")
    found = markerset.match(take.labels)
    return Prepared(take, markerset, result[0], {label: take.index(name) for label, name in found.items()}, units)


NeutralSpec = tuple[float, float] | str | None


def rest_window(prepared: Prepared, spec: NeutralSpec) -> tuple[tuple[float, float], str]:
    """Where the take is at rest: ``spec`` seconds, ``"first"`` (its first second with the head
    seen), ``"stillest"`` (second), or None: chosen from its motion and sound
    (:func:`mapping.rest.choose_rest`); returns the window and how it was found."""
    times = prepared.take.times
    if isinstance(spec, tuple):
        return spec, "given"
    if spec == "stillest":
        return stillest_window(prepared.stable, times), "stillest second"
    if spec is None:
        return choose_rest(prepared.stable, times, prepared.stable.channels.get(SOUND_LEVEL))
    if spec != "first":
        raise InputError(f'neutral must be START:END, "first" or "stillest", got {spec!r}')
    posed = np.flatnonzero(prepared.stable.ok)
    start = float(times[posed[0]]) if len(posed) else float(times[0])
    return (start, start + 1.0), "first second with the head seen"


def calibrate(mapping: Mapping, neutral: Prepared, neutral_window: NeutralSpec = None,
              range_from: Prepared | None = None, range_window: tuple[float, float] | None = None,
              percentiles: tuple[float, float] = (0.5, 99.5), performer: str = "", min_side: float = 0.0,
              require_motion: bool = True, rest_only: bool = False, solve: bool = False) -> Profile:
    """A performer profile: neutral from ``neutral_window`` of ``neutral`` (see :func:`rest_window`),
    range from ``range_window`` of ``range_from`` (default: the neutral take, all of it), each side
    at least ``min_side`` from rest (see :func:`~mapping.profile.build_profile`). With
    ``rest_only``, only the rest is wanted: the ranges are measured over the rest window alone,
    which saves a pass over the take, and mean nothing. With ``solve``, a range-of-motion take
    (``range_from`` or ``range_window``) also teaches the profile what each motor does to every
    marker (:mod:`mapping.solver`), and mapping solves those motors all at once; off by default
    while it maps the synthetic performers less faithfully than the rules (``python -m bench
    fidelity``: ``fidelity.*_solver_*``).

    Raises
    ------
    InputError
        Saying why the calibration cannot be made.
    """
    window, how = rest_window(neutral, neutral_window)
    source = range_from or neutral
    times = source.take.times
    if rest_only:
        source, times = neutral, neutral.take.times
        frames = (times >= window[0]) & (times < window[1])
    elif range_window is None:
        frames = np.ones(len(times), bool)
    else:
        frames = (times >= range_window[0]) & (times < range_window[1])
        if not frames.any():
            raise InputError(f"cannot calibrate: no frames in the range window "
                             f"{range_window[0]:g}-{range_window[1]:g} s")
    notes = {"neutral": f"{round(window[0], 3):g}-{round(window[1], 3):g} s"  # a frame's time: 26.667, not 26.6667
                        + ("" if how == "given" else f" ({how})"),
             "range": f"percentiles {percentiles[0]:g}-{percentiles[1]:g}"
                      + (f" of {range_window[0]:g}-{range_window[1]:g} s" if range_window else "")}
    full = (range_from is not None or range_window is not None) and not rest_only
    # A range-of-motion take moves each part on purpose: a lid's 3 mm there is its range, where in
    # an ordinary take 3 mm may be drift, and the one threshold for every kind stays.
    kinds = source_kinds(mapping) if full else None
    profile = build_profile(neutral.stable, neutral.take.times, window, source.stable, frames, neutral.columns,
                            source.columns, neutral.markerset.name, mapping.sources(), percentiles, performer, notes,
                            min_side, require_motion, kinds,
                            turning_axes(source.stable.rotation, frames, source.take.rate) if full else None)
    if not profile:
        raise InputError(f"cannot calibrate: {profile}")
    _require_ranges(mapping, profile, neutral, window)
    profile = replace(profile, full_range=full, references=neutral.reference_shape())
    if full:  # a range-of-motion take: a side lost where the mirror's was seen takes the mirror's (mapping.sweep)
        profile, lost = mirror_lost_sides(mapping, profile, source.stable, source.columns, frames, percentiles)
        if lost:
            notes = {**profile.notes, "from_mirror": ", ".join(lost)}
            guessed = [end for end in notes.pop("from_guesses", "").split(", ") if end and end not in lost]
            if guessed:  # an end the mirror's gives is no longer the guesses'
                notes["from_guesses"] = ", ".join(guessed)
            profile = replace(profile, notes=notes)
    if full and any(r.decouple for r in mapping.rules):  # each group moved alone: couplings show
        profile = replace(profile, couplings=_couplings(mapping, source, frames, profile))
    if full and solve:  # the rest from the neutral take, in the range take's marker order
        at_rest = marker_rests(neutral, window)
        rest = np.full((source.stable.local.shape[1], 3), np.nan)
        for label, column in source.columns.items():
            if label in at_rest:
                rest[column] = at_rest[label]
        profile = replace(profile, solver=sweep_solver(mapping, source, frames, profile, rest))
    return profile


def marker_rests(prepared: Prepared, window: tuple[float, float]) -> dict[str, np.ndarray]:
    """Each marker's head-frame rest ``(3,)`` (mm): its median over the rest ``window`` (NaN
    where it was not seen there), by label."""
    return rests_of(seen_at(prepared.stable, prepared.take.window(*window)), prepared.columns)


def _require_ranges(mapping: Mapping, profile: Profile, neutral: Prepared, window: tuple[float, float]) -> None:
    """An :class:`InputError` naming each marker of the take a ``profile``-normalised rule reads
    that the calibration could not range (unseen throughout the neutral ``window``, so without a
    rest, or never seen at all), and what to do about it: mapping would fail on it later. (A
    ``calibrated`` rule without its range is scaled instead, as the report says.)"""
    missing = sorted({m for r in mapping.rules if r.normalise == "profile" for s in r.sources
                      if s.key not in profile.sources for m in s.markers if m in neutral.columns})
    if not missing:
        return
    at_rest = neutral.take.window(*window)
    seen = np.isfinite(seen_at(neutral.stable, at_rest)).all(axis=2).any(axis=0)  # (N,): each marker seen at rest
    unseen = [m for m in missing if not seen[neutral.columns[m]]]
    motors = sorted({r.code for r in mapping.rules for s in r.sources if set(s.markers) & set(missing)})
    where = (f"not seen in the neutral window {window[0]:g}-{window[1]:g} s" if unseen == missing else
             "not seen at rest or over the range frames")
    one = len(missing) == 1
    raise InputError(f"cannot calibrate: marker{'' if one else 's'} {', '.join(missing)} {'is' if one else 'are'} "
                     f"{where} (motor{'' if len(motors) == 1 else 's'} {', '.join(motors)} "
                     f"need{'s' if len(motors) == 1 else ''} {'its' if one else 'their'} rest and range): "
                     "give a neutral window where the face is at rest and every marker is seen (--neutral START:END)")


def sweep_solver(mapping: Mapping, prepared: Prepared, frames: np.ndarray, profile: Profile, rest: np.ndarray
                 ) -> Solver | None:
    """What the range-of-motion ``frames`` of ``prepared`` show each marker-read motor doing to
    every marker (:func:`mapping.solver.learn_solver`), markers at ``rest`` ``(M, 3)``."""
    rules = [r for r in mapping.rules if r.code in MOTOR_CODES and r.sources and resolved_mode(r, profile) == "profile"]
    if not any(all(s.markers for s in r.sources) for r in rules):  # the face's motors read from markers
        return None
    stable = prepared.stable
    quality = marker_quality(stable.local, stable.filled)
    plan = MotorPlan.of(mapping.rules, profile, prepared.columns)
    shares, _ = rule_shares(mapping, stable, prepared.columns, quality, profile, plan)
    index = {r.code: i for i, r in enumerate(mapping.rules)}
    own = [sorted({m for s in r.sources for m in s.markers}) if all(s.markers for s in r.sources) else []
           for r in rules]
    return learn_solver([r.code for r in rules], own, stable.local[frames], prepared.columns,
                        quality[frames] >= 1.0, shares[frames][:, [index[r.code] for r in rules]], rest,
                        prepared.markerset.head_reference, [r.decouple for r in rules])


def source_kinds(mapping: Mapping) -> dict[str, str]:
    """Each marker source the mapping reads (its key) -> the kind of motor it drives
    (:data:`mapping.profile.KIND_MOTION`'s letters; the smallest where it drives several).
    Blendshape scores keep the thresholds tuned in their own units."""
    order = {kind: i for i, kind in enumerate(sorted(KIND_MOTION, key=lambda k: KIND_MOTION[k]))}
    kinds: dict[str, str] = {}
    for rule in mapping.rules:
        kind = rule.code[0]
        if kind not in KIND_MOTION:
            continue
        for source in rule.sources:
            if not source.markers:
                continue
            if source.key not in kinds or order[kind] < order[kinds[source.key]]:
                kinds[source.key] = kind
    return kinds


def _couplings(mapping: Mapping, prepared: Prepared, frames: np.ndarray, profile: Profile
               ) -> dict[str, dict[str, tuple[float, float]]]:
    """The couplings a range-of-motion take's ``frames`` show (:mod:`mapping.coupling`)."""
    stable = prepared.stable
    head = head_angles(stable.rotation, profile.rest_rotation, profile.head_axes)
    made_up = stable.filled if stable.filled is not None else np.zeros(stable.local.shape[:2], dtype=bool)
    values: dict[str, np.ndarray] = {}
    for rule in mapping.rules:
        mode = resolved_mode(rule, profile)
        for source in rule.sources:
            raw = measure(source, stable.local, prepared.columns, head, stable.channels)
            if source.markers:  # only what was seen: a filled gap would teach its own guess back
                raw = np.where(made_up[:, [prepared.columns[m] for m in source.markers]].any(axis=1), np.nan, raw)
            values[source.key] = normalise(raw, source, rule, profile.sources.get(source.key), mode)[frames]
    noise = recorded_jitter(mapping, prepared.take.positions[frames], prepared.columns)
    return learn_couplings(mapping, profile, values, noise)


def ready_take(take: Take, mapping: Mapping | str | None = None, profile: Profile | None = None,
               neutral_window: NeutralSpec = None, settings: CleanSettings = CleanSettings(),
               mirror: bool = False) -> ReadyTake:
    """Clean ``take`` and settle its profile (given, typical or its own; see :func:`map_take`)."""
    chosen, markerset = choose_mapping(take, mapping)
    if mirror:
        chosen = replace(chosen, mirror=True)
    prepared = prepare(take, markerset, settings)
    notes = take_notes((prepared,), chosen)
    rest_from_take = neutral_window is not None
    typical = typical_profile(markerset.name) if profile is None else None
    if typical is not None:
        profile, rest_from_take, kind = typical, True, f"typical for {markerset.name} (built in)"
        notes.append(f"ranges from the built-in typical profile for {markerset.name}")
    if profile is None:
        profile = calibrate(chosen, prepared, neutral_window, percentiles=(1.0, 99.0), min_side=SELF_MIN_SIDE)
        notes.append(f"profile from the take itself ({profile.notes['neutral']}, {profile.notes['range']})")
        kind, rest = "from the take itself (1st-99th percentiles)", profile.notes["neutral"]
        size = prepared.units.size if prepared.units is not None else 1.0
        shut = shut_lids(chosen, prepared)
        profile, widened = bound_by_typical(profile, chosen, size, shut)
        notes.extend([shut_note(shut, profile)] if shut else [])
        if widened:
            kind += f", each side at least a typical face's (x{size:.2f})"
            notes.append(f"the take's own ranges of {', '.join(widened)} widened to a typical face's ({TYPICAL}'s "
                         f"typical profile, scaled x{size:.2f} to this performer): a take's extremes need not be the "
                         "performer's; calibrate on a range-of-motion take (--calibrate) for the performer's own")
    else:
        if typical is None:
            kind = (f"calibrated on a range of motion{f' ({profile.source})' if profile.source else ''}"
                    if profile.full_range else f"given ({profile.source or 'calibrated on a take'})")
        rest = f"the profile's ({profile.notes.get('neutral', 'its own')})"
        check_profile(profile, chosen, markerset.name)
        missing = [s.key for s in chosen.sources() if s.key not in profile.sources]
        ranged = {s.key for r in chosen.rules if r.normalise != "scale" for s in r.sources}  # scale: a rest only
        if missing or rest_from_take:
            own = calibrate(chosen, prepared, neutral_window, percentiles=(1.0, 99.0), min_side=SELF_MIN_SIDE,
                            require_motion=any(key in ranged for key in missing),  # a range needs motion
                            rest_only=not missing)  # its ranges only if missing
            rests = marker_rests(prepared, rest_window(prepared, neutral_window)[0]) \
                if rest_from_take and profile.solver is not None else None
            profile = merge_profile(profile, own, missing, rest_from_take, rests)
            if missing:
                notes.append(f"ranges from the take itself for {', '.join(missing)}")
            if rest_from_take:
                notes.append(f"neutral from the take ({own.notes['neutral']})")
                rest = own.notes["neutral"]
    notes.extend(filter(None, [solver_note(profile, chosen)]))
    return ReadyTake(prepared, chosen, profile, tuple(notes), rest, kind)


def map_ready(ready: ReadyTake, target_neutral: np.ndarray | None = None, life: bool | LifeSettings | None = None
              ) -> MotorTrack:
    """The motor track of a :class:`ReadyTake` on a face whose neutral is ``target_neutral``,
    with the life layer (:mod:`mapping.life`) on the motors the mapping does not drive where
    ``life`` says (True or its settings: on; None: on for a voice alone)."""
    take, stable = ready.prepared.take, ready.prepared.stable
    track = map_stabilised(stable, ready.prepared.columns, take.times, take.rate, ready.mapping, ready.profile,
                           target_neutral, stable.filled)
    meta = {**track.meta, "source": take.meta.get("source", ""), "notes": list(ready.notes)}
    mapped = replace(track, meta=meta)  # the extra parameters (HT) kept
    rest = standard_neutral() if target_neutral is None else target_neutral
    mapped.meta["report"] = take_report(ready, mapped, rest).as_dict()  # what was chosen, and how far to trust it
    if life is None:
        life = take.meta.get("source") == "voice"
    if life is not False:
        settings = life if isinstance(life, LifeSettings) else LifeSettings()
        channels = {name: take.channels[:, i] for i, name in enumerate(take.channel_names)}
        cues = take_cues(channels, mapped.frames, mapped.rate, settings)
        mapped = add_life(mapped, cues, {rule.code for rule in ready.mapping.rules}, settings)
    return mapped


def map_take(take: Take, mapping: Mapping | str | None = None, profile: Profile | None = None,
             neutral_window: NeutralSpec = None, target_neutral: np.ndarray | None = None,
             settings: CleanSettings = CleanSettings(), mirror: bool = False,
             life: bool | LifeSettings | None = None) -> MotorTrack:
    """Clean, calibrate (unless ``profile`` is given) and map ``take``.

    ``neutral_window`` (see :func:`rest_window`) sets the rest pose from the take even with a profile
    (its ranges are kept around the new rest), for a take whose head rests differently from the
    profile's session; None keeps a given profile's rest. ``mirror`` swaps the sides whatever the
    mapping says. ``life``: the life layer, as :func:`map_ready` takes it. The same as
    :func:`map_ready` of :func:`ready_take`.
    """
    return map_ready(ready_take(take, mapping, profile, neutral_window, settings, mirror), target_neutral, life)


def check_profile(profile: Profile, mapping: Mapping, markerset: str) -> None:
    """A profile must be for the marker set (named ``markerset``) the mapping reads; the error
    names both files."""
    if profile.markerset == markerset:
        return
    builtin = data_path("mappings", f"{mapping.name}.toml")
    which = (f"the built-in mapping {mapping.name}" if mapping.source and Path(mapping.source) == builtin
             else f"the mapping {mapping.source or mapping.name}")
    raise InputError(f"the profile {profile.source or '(given)'} is for marker set {profile.markerset}, but {which} "
                     f"reads marker set {markerset}: calibrate a profile on a {markerset} take "
                     f"(toonface calibrate), or use a mapping for {profile.markerset}")
