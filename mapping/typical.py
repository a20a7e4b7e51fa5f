"""A take's own ranges bounded by what a typical face can do.

Without a range-of-motion calibration, a profile made on the take itself maps the take's 1st
and 99th percentiles onto each motor's ends. A take's extremes are not the performer's: one who
narrows the eyes by a quarter in a smile would get a cartoon whose eyes shut, and a sneer would
read as a full squint. :func:`bound_by_typical` widens each side of such a range to at least a
typical face's (the built-in typical profile of ``toon32``, :data:`TYPICAL`), scaled to the
performer's size, for every plain marker source whose motor ``toon32``'s mapping drives from the
same axis. Motion beyond the typical range is kept: the take shows the performer can do it.

An upper lid whose blinks the take shows (:mod:`mapping.blinks`) is not widened on its closing
side: its blinks say where it shuts (:func:`shut_lids`), and a lid widened past them blinked as a
squint (issue 69: the jaw take's four blinks dipped the cartoon's lids from 0.80 to 0.46-0.63).
"""

from __future__ import annotations

from collections.abc import Mapping as Lookup
from dataclasses import replace
from pathlib import Path

from common import data_path
from mapping.blinks import Blinks, find_blinks
from mapping.mapfile import Mapping, MotorRule, load_mapping
from mapping.profile import Profile, SourceRange, load_profile
from mapping.ready import Prepared
from mapping.sources import Source, measure

#: The layout whose built-in typical profile says what a typical face can do.
TYPICAL = "toon32"
#: The performer's size against the layout's own is trusted within these bounds.
SIZE_BOUNDS = (0.6, 1.6)
#: The motors whose lowest value is a shut upper lid (ToonFace's eyelids).
UPPER_LIDS = ("ERU", "ELU")


def builtin_profile(markerset: str) -> Path | None:
    """The built-in typical performer profile for a marker set, if there is one."""
    path = data_path("profiles", f"{markerset}.toml")
    return path if path.is_file() else None


def typical_profile(markerset: str) -> Profile | None:
    """The profile used when none is given: the marker set's built-in typical one, if it has one
    (else ``map`` and ``send`` calibrate on the take itself)."""
    path = builtin_profile(markerset)
    return None if path is None else load_profile(path)


def typical_sides(mapping: Mapping) -> dict[str, tuple[float, float]]:
    """Source key -> how far a typical face moves it below and above rest (mm; negative,
    positive), for the plain marker sources of ``mapping`` that drive a motor toon32 drives
    from the same axis, oriented by each rule's and source's ``invert``."""
    typical = typical_profile(TYPICAL)
    if typical is None:
        return {}
    reference = load_mapping(TYPICAL)
    rules = {rule.code: rule for rule in reference.rules}
    out: dict[str, tuple[float, float]] = {}
    for rule in mapping.rules:
        ref_rule = rules.get(rule.code)
        if ref_rule is None:
            continue
        for source in rule.sources:
            match = _same_axis(source, ref_rule)
            if source.kind != "marker" or match is None or match.key not in typical.sources:
                continue
            span = typical.sources[match.key]
            low, high = span.low - span.neutral, span.high - span.neutral
            if (source.invert != rule.invert) != (match.invert != ref_rule.invert):
                low, high = -high, -low
            out.setdefault(source.key, (low, high))
    return out


def _same_axis(source: Source, rule: MotorRule) -> Source | None:
    return next((s for s in rule.sources if s.kind == "marker" and s.axis == source.axis), None)


def shut_lids(mapping: Mapping, prepared: Prepared) -> dict[str, tuple[Blinks, float]]:
    """Source key -> the blinks it shows and its closing direction (-1: its value falls as the
    lid shuts; +1: rises), for the plain marker sources of ``mapping``'s upper-lid motors
    (:data:`UPPER_LIDS`) in the cleaned take ``prepared`` that show blinks
    (:func:`mapping.blinks.find_blinks`)."""
    out: dict[str, tuple[Blinks, float]] = {}
    for rule in mapping.rules:
        if rule.code not in UPPER_LIDS:
            continue
        for source in rule.sources:
            if source.kind != "marker" or any(m not in prepared.columns for m in source.markers):
                continue
            closing = 1.0 if source.invert != rule.invert else -1.0
            values = measure(source, prepared.stable.local, prepared.columns, None)
            found = find_blinks(values, prepared.take.rate, closing)
            if found is not None:
                out[source.key] = (found, closing)
    return out


def bound_by_typical(profile: Profile, mapping: Mapping, size: float = 1.0,
                     shut: Lookup[str, tuple[Blinks, float]] | None = None) -> tuple[Profile, list[str]]:
    """``profile`` with each side of its typical-bounded sources at least a typical face's,
    scaled by ``size`` (the performer's against the layout's, held within :data:`SIZE_BOUNDS`),
    except the closing side of the lids in ``shut`` (:func:`shut_lids`), which is where their
    blinks shut them; returns it and the keys widened."""
    scale = min(max(size, SIZE_BOUNDS[0]), SIZE_BOUNDS[1])
    sources, shut = dict(profile.sources), shut or {}
    widened = []
    for key, (below, above) in typical_sides(mapping).items():
        span = sources.get(key)
        if span is None:
            continue
        low, high = min(span.low, span.neutral + below * scale), max(span.high, span.neutral + above * scale)
        if key in shut:  # shut where the blinks shut it (a rest a blink passes is no side at all)
            blinks, closing = shut[key]
            if closing < 0:
                low = min(blinks.closed, span.neutral - 1e-6)
            else:
                high = max(blinks.closed, span.neutral + 1e-6)
        if (low, high) != (span.low, span.high):
            sources[key] = SourceRange(span.neutral, low, high)
        if low < span.low or high > span.high:
            widened.append(key)
    return replace(profile, sources=sources), widened


def shut_note(shut: Lookup[str, tuple[Blinks, float]], profile: Profile) -> str:
    """What :func:`bound_by_typical` did with the lids in ``shut``, for a take's notes."""
    told = [f"{key} at {abs(blinks.closed - profile.sources[key].neutral):.1f} mm from rest ({len(blinks.frames)} "
            f"blinks, the shallowest full one)" for key, (blinks, _) in shut.items() if key in profile.sources]
    return (f"lids shut where the take's own blinks shut them: {'; '.join(told)}; not widened to a typical face's "
            "on that side")
