"""What a user should know of a take once it is cleaned and in the head frame: its units as
settled, doubts about its marker set, head references that lie further from the marker set's
shape than another face's proportions explain (wrong labels, another layout), and head travel
the motors cannot show. ``map``'s report and ``calibrate`` say the same."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mapping.mapfile import Mapping
from mapping.profile import MIN_MOTION, STILL_SIDE, Profile
from mapping.ready import Prepared

#: Head references further than this (RMS, mm) from the marker set's shape, once another face's
#: proportions are allowed for (:func:`unexplained_mm`), are worth a warning.
REFERENCE_TOLERANCE = 5.0
#: The proportions a face may have against its marker set's: a stretch along each head axis
#: within these factors (faces differ in width, height and depth by 20-30 % either way).
FACE_STRETCH = (0.75, 1.33)


def unexplained_mm(found: np.ndarray, expected: np.ndarray) -> float:
    """How far (RMS, mm) markers ``found`` ``(K, 3)`` lie from ``expected`` ``(K, 3)`` (both in
    the head frame) once each is centred and ``expected`` is stretched along each head axis by
    the factor that fits best, kept within :data:`FACE_STRETCH`: what a wider, taller or deeper
    face explains is not a labelling mistake, while a swap (which no positive stretch explains)
    still is."""
    a, b = found - found.mean(axis=0), expected - expected.mean(axis=0)
    stretch = np.clip(np.sum(a * b, axis=0) / np.maximum(np.sum(b * b, axis=0), 1e-9), *FACE_STRETCH)
    return float(np.sqrt(np.mean(np.sum((a - b * stretch) ** 2, axis=1))))
#: Head travel (mm) beyond which the note says that only the head's rotation is kept.
TRAVEL_NOTE = 10.0


def stabilisation_notes(prepared: Prepared) -> list[str]:
    """What the user should know about the head fit: references whose shape on this take is far
    from the marker set's (wrong labels, another layout, a neutral not in head-frame mm), and head
    travel that the motors cannot show (only the rotation reaches HH and HV)."""
    units = prepared.units
    notes = list(units.notes) if units is not None else []
    notes += [f"warning: marker set {prepared.markerset.name}: {doubt}" for doubt in prepared.markerset.doubts()]
    if not prepared.markerset.labels:  # a voice: no head at all
        return notes
    if not prepared.markerset.head_reference:
        return [*notes, f"warning: marker set {prepared.markerset.name} has no head references: the head's motion "
                "is not removed, and a nod or a turn moves the motors as the face would"]
    refs = [r for r in prepared.markerset.head_reference if r in prepared.columns]
    expected = np.array([prepared.markerset.neutral_of(r) for r in refs])
    scale_off = units is not None and units.check.off and units.origin != "inferred"  # said already, in units
    if len(refs) == len(prepared.stable.reference) and not scale_off:
        off = unexplained_mm(prepared.stable.reference, expected)
        if off > REFERENCE_TOLERANCE:
            notes.append(f"warning: the take's head references ({', '.join(refs)}) lie {off:.0f} mm (RMS) from "
                         f"marker set {prepared.markerset.name}'s shape, more than another face's size and "
                         "proportions explain: are the labels in the right order for this file, and the marker "
                         "set's neutral in head-frame millimetres?")
    travel = prepared.stable.translation[prepared.stable.ok]
    if len(travel):
        extent = np.ptp(travel, axis=0)
        if extent.max() > TRAVEL_NOTE:
            axis = "xyz"[int(np.argmax(extent))]
            notes.append(f"the head moved up to {extent.max():.0f} mm (most along the take's {axis} axis); only its "
                         "rotation reaches the face (HH, HV)")
    return notes


def take_notes(takes: Sequence[Prepared], mapping: Mapping) -> list[str]:
    """What ``map`` and ``calibrate`` tell of their takes: each take's :func:`stabilisation_notes`
    (a take given twice is told once), then the motors ``mapping`` left out for want of markers."""
    notes = [note for k, prepared in enumerate(takes) if all(prepared is not other for other in takes[:k])
             for note in (*prepared.take.meta.get("notes", ()), *stabilisation_notes(prepared))]  # a voice's own
    left_out = mapping.left_out_note()
    return notes if left_out is None else [*notes, left_out]


def still_warning(profile: Profile, mapping: Mapping) -> str | None:
    """A calibration's warning about the sources ``mapping`` reads that did not move over the range
    frames (they keep a fixed range, so their motors move little); None where all moved."""
    still = set(profile.notes.get("no_motion", "").split(", "))
    idle = [src.key for src in mapping.sources() if src.key in still and not src.key.startswith("head.")]
    if not idle:
        return None
    kinds = "" if not profile.full_range else " (1 mm for lids and pupils, which keep 3-4 mm, in a range window)"
    return (f"warning: not moving over the range frames (under {MIN_MOTION:g} mm{kinds}): {', '.join(idle)}; "
            f"they keep a range of {STILL_SIDE:g} mm either side of rest, so the motors that follow them move little")


def solver_note(profile: Profile, mapping: Mapping) -> str | None:
    """What the profile's solver (``calibrate --solve``) maps in place of the rules, and what it
    leaves them; None without one."""
    solver = profile.solver
    if solver is None:
        return None
    solved = [r.code for r in mapping.rules if r.code in solver.codes]
    return (f"motors {', '.join(solved)} solved all at once by the profile's solver ({len(solver.markers)} markers, "
            f"learned from its range of motion){solver.left_out()}")


def range_notes(profile: Profile) -> list[str]:
    """What a calibration's ranges took from something other than the samples seen at their
    ends: ends the gap filler's guesses took further (the marker hidden at that end) and sides
    taken from the mirror side's (:mod:`mapping.sweep`); empty where neither."""
    said = {"from_guesses": "range ends as far as gap filling guessed, further than any sample seen (the marker "
                            "was hidden at that end)",
            "from_mirror": "range ends from the mirror side's (lost in the sweep while the mirror's was seen)"}
    return [f"{what}: {profile.notes[key]}" for key, what in said.items() if profile.notes.get(key)]
