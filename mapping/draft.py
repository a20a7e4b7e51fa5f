"""A draft mapping for a marker set toonface has not seen, from the presets it knows.

Each built-in mapping is a pattern of where a motor's markers sit on a face (the brows' above the
eyes, the mouth corners' beside the lips, the chin's below). A preset's marker set is laid over
the new one (both are in a head frame, so only a scale, an offset and a turn of a few degrees
are fitted, by alternating nearest neighbours and least squares); each marker the preset's
rules read is taken to be the new marker nearest it, if one is within :data:`MATCH_FRACTION` of
the face's size and no nearer preset marker claims it. The preset that finds the most of its
markers (one that finds the jaw's before any that does not) is the draft's pattern; motors whose
markers were not all found are left out and listed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture import MarkerSet, load_markerset
from common import builtin_names, data_path, read_document
from mapping.mapfile import Mapping, parse_mapping
from mapping.roles import mirror_partner

#: A preset marker is found in the new set within this share of the face's size (its RMS radius).
MATCH_FRACTION = 0.15
#: The most a preset is turned to lie over the new set (degrees).
MAX_TURN_DEGREES = 25.0


@dataclass(frozen=True)
class MappingDraft:
    """A mapping document for the new set and what was found.

    Attributes
    ----------
    doc : dict
        The mapping (``toonface.mapping/1``), the preset's rules with the new marker names.
    template : str
        The preset it follows.
    found : dict of str to str
        Preset marker -> new marker.
    unmapped : tuple of str
        Motors of the preset left out (a marker of theirs not found).
    fit_mm : float
        Mean distance (mm) between the found pairs after the fit.
    """

    doc: dict
    template: str
    found: dict[str, str]
    unmapped: tuple[str, ...]
    fit_mm: float


def _fit(source: np.ndarray, target: np.ndarray, rounds: int = 30) -> np.ndarray:
    """``source`` (K, 3) laid over ``target`` (N, 3) by a scale, a turn and an offset, alternating
    nearest neighbours and least squares (Umeyama's fit); the turn is kept within
    :data:`MAX_TURN_DEGREES` (two head frames drafted from data differ by a few degrees, not by
    a half turn). Returns the placed source, ``(K, 3)``."""
    def size(points: np.ndarray) -> float:
        return float(np.sqrt(np.mean(np.sum((points - points.mean(axis=0)) ** 2, axis=1))))
    scale, turn = size(target) / max(size(source), 1e-9), np.eye(3)
    offset = target.mean(axis=0) - scale * source.mean(axis=0)
    for _ in range(rounds):
        placed = scale * source @ turn.T + offset
        matched = target[np.linalg.norm(placed[:, None] - target[None], axis=2).argmin(axis=1)]
        a, b = source - source.mean(axis=0), matched - matched.mean(axis=0)
        u, singular, vt = np.linalg.svd(b.T @ a)
        fix = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
        turned = u @ fix @ vt
        if np.degrees(np.arccos(np.clip((np.trace(turned) - 1) / 2, -1, 1))) <= MAX_TURN_DEGREES:
            turn = turned
            scale = float(np.sum(singular * np.diag(fix)) / max(np.sum(a * a), 1e-9))
        else:
            scale = float(np.sum((a @ turn.T) * b) / max(np.sum(a * a), 1e-9))
        offset = matched.mean(axis=0) - scale * source.mean(axis=0) @ turn.T
    return scale * source @ turn.T + offset


def _rule_markers(mapping: Mapping) -> dict[str, set[str]]:
    """Each motor's markers, read from the parsed rules."""
    return {rule.code: {m for source in rule.sources for m in source.markers} for rule in mapping.rules}


def _rename(value, names: dict[str, str]):
    return names.get(value, value) if isinstance(value, str) else [names.get(v, v) for v in value]


def sparse_mapping(markerset: MarkerSet, markerset_ref: str) -> MappingDraft:
    """Rules for a layout of three markers without a head frame, a jaw and the mouth corners,
    found by position in its head frame: the corners are the two furthest from the midline
    (the left one at +x), the jaw the third. Without a head frame a nod would move every marker,
    so what can be is read between markers: MB from how far the jaw lies below the corners (a
    nod turns that difference a little, not the whole face's travel), MLH and MRH from the
    mouth's width, which no turn changes; the corners' heights (MLV, MRV) are read along y,
    where a nod still reaches them; the head's turn cannot be seen."""
    order = np.argsort(np.abs(markerset.neutral[:, 0]))
    jaw, corners = markerset.labels[order[0]], [markerset.labels[i] for i in order[1:]]
    left, right = sorted(corners, key=lambda label: -markerset.neutral_of(label)[0])
    loss = {"policy": "ease", "seconds": 0.5}
    motors = {"MB": {"sources": [{"difference": [left, jaw], "axis": "y"}, {"difference": [right, jaw], "axis": "y"}],
                     "combine": "mean", "loss": loss},
              "MLH": {"sources": [{"distance": [left, right]}], "loss": loss},
              "MLV": {"sources": [{"marker": left, "axis": "y"}], "loss": loss},
              "MRH": {"sources": [{"distance": [left, right]}], "loss": loss},
              "MRV": {"sources": [{"marker": right, "axis": "y"}], "loss": loss}}
    doc = {"format": "toonface.mapping/1", "name": markerset.name, "markerset": markerset_ref,
           "description": "drafted for a jaw and mouth corners (no head frame: head motion not removed)",
           "motor": motors}
    return MappingDraft(doc, "jaw-and-corners", {"jaw": jaw, "left corner": left, "right corner": right}, (), 0.0)


def draft_mapping(markerset: MarkerSet, markerset_ref: str) -> MappingDraft:
    """The best preset's rules for ``markerset``, which the mapping names as ``markerset_ref``
    (:func:`sparse_mapping` for three markers without a head frame)."""
    if not markerset.head_reference and len(markerset.labels) == 3:
        return sparse_mapping(markerset, markerset_ref)
    size = float(np.sqrt(np.mean(np.sum((markerset.neutral - markerset.neutral.mean(axis=0)) ** 2, axis=1))))
    best: MappingDraft | None = None
    for preset in builtin_names("mappings", ".toml"):
        path = data_path("mappings", f"{preset}.toml")
        doc = read_document(path)  # the rules are copied from the document, named after the parsed ones
        parsed = parse_mapping(doc, path)
        if any(source.kind == "blendshape" for source in parsed.sources()):
            continue  # scores a marker set cannot give (the face and arkit presets)
        known = load_markerset(parsed.markerset)
        markers = _rule_markers(parsed)
        placed = _fit(known.neutral, markerset.neutral)
        distance = np.linalg.norm(placed[:, None] - markerset.neutral[None], axis=2)
        found: dict[str, str] = {}
        gaps: list[float] = []
        for i in np.argsort(distance.min(axis=1)):  # nearest pairs first: each new marker once
            j = int(distance[i].argmin())
            label, target = known.labels[i], markerset.labels[j]
            if distance[i, j] <= MATCH_FRACTION * size and target not in found.values():
                found[label] = target
                gaps.append(float(distance[i, j]))
        motors = {}
        unmapped = []
        for code, rule in doc.get("motor", {}).items():
            if markers.get(code, set()) <= set(found):
                sources = [{k: (_rename(v, found) if k in ("marker", "distance", "difference", "angle") else v)
                            for k, v in source.items()} for source in rule.get("sources", [])]
                motors[code] = {**rule, "sources": sources}
            else:
                unmapped.append(code)
        for code, rule in motors.items():  # a motor decoupled from one left out: nothing to measure it by
            if "decouple" in rule:
                kept = [other for other in rule["decouple"] if other in motors]
                motors[code] = {k: v for k, v in rule.items() if k != "decouple"} | ({"decouple": kept} if kept else {})
            loss = motors[code].get("loss")
            if isinstance(loss, dict) and "near" in loss:  # ... or lost near one left out: nothing to read it by
                near = [other for other in loss["near"] if other in motors]
                loss = {k: v for k, v in loss.items() if k != "near"} | ({"near": near} if near else {})
                motors[code] = motors[code] | {"loss": loss}
        new = {**doc, "name": f"{markerset.name}", "markerset": markerset_ref, "motor": motors,
               "description": f"drafted from the {preset} preset"}
        used = set().union(*markers.values())
        draft = MappingDraft(new, preset, {k: v for k, v in found.items() if k in used}, tuple(unmapped),
                             float(np.mean(gaps)) if gaps else float("inf"))
        if best is None or _rank(draft) > _rank(best):
            best = draft
    assert best is not None
    return _mirror_missing(best, markerset, size)


def _rank(draft: MappingDraft) -> tuple[bool, int, float]:
    """Which draft is better: one that opens the jaw, then the most of the 21 motors (a preset
    that drives the head's tilt as well is no better a fit for it), then the closest fit."""
    from toon import MOTOR_CODES

    return "MB" in draft.doc["motor"], sum(code in MOTOR_CODES for code in draft.doc["motor"]), -draft.fit_mm


def _partner(markerset: MarkerSet, label: str, size: float) -> str | None:
    """The marker at ``label``'s mirror image, within :data:`MATCH_FRACTION` of the face's size
    (:func:`mapping.roles.mirror_partner`; a marker on the midline is its own)."""
    j = mirror_partner(markerset.neutral, markerset.labels.index(markerset.canonical(label)), MATCH_FRACTION * size,
                       itself=True)
    return None if j is None else markerset.labels[j]


def _mirror_missing(draft: MappingDraft, markerset: MarkerSet, size: float) -> MappingDraft:
    """A motor of one side left out while its twin on the other side was found (a preset laid
    over a face a little asymmetric finds one brow and not the other) gets its twin's rules on
    the mirror-image markers, x read the other way."""
    motors, still = dict(draft.doc["motor"]), []
    for code in draft.unmapped:
        twin = code[0] + {"R": "L", "L": "R"}.get(code[1], code[1]) + code[2:]
        rule = motors.get(twin)
        if twin == code or rule is None or any("angle" in source for source in rule.get("sources", [])):
            still.append(code)
            continue
        sources = []
        for source in rule.get("sources", []):
            names = {name: _partner(markerset, name, size) for key in ("marker", "distance", "difference")
                     if key in source for name in ([source[key]] if isinstance(source[key], str) else source[key])}
            found = {name: partner for name, partner in names.items() if partner is not None}
            if len(found) < len(names):
                break
            flipped = {k: (_rename(v, found) if k in ("marker", "distance", "difference") else v)
                       for k, v in source.items()}
            if flipped.get("axis") == "x":
                flipped["invert"] = not source.get("invert", False)
                if not flipped["invert"]:
                    del flipped["invert"]
            sources.append(flipped)
        else:
            motors[code] = {**rule, "sources": sources}
            continue
        still.append(code)
    if len(still) == len(draft.unmapped):
        return draft
    mirrored = [code for code in draft.unmapped if code not in still]
    doc = {**draft.doc, "motor": {code: motors[code] for code in sorted(motors, key=_motor_order)},
           "description": f"{draft.doc['description']}; {', '.join(mirrored)} mirrored from the other side"}
    return MappingDraft(doc, draft.template, draft.found, tuple(still), draft.fit_mm)


def _motor_order(code: str) -> int:
    from toon import MOTOR_CODES

    return MOTOR_CODES.index(code) if code in MOTOR_CODES else len(MOTOR_CODES)
