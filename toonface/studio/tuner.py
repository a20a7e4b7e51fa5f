"""The studio's mapping tuner: a take mapped again at each change of its mapping or profile.

The mapping is edited as its ``toonface.mapping/1`` document and the profile as its source
ranges; every change is validated (:func:`mapping.parse_mapping`, the profile's own checks) and
the take, cleaned once, is mapped again (:func:`mapping.workflow.map_ready`, what ``toonface map``
runs), so that the face shows the change at once. Both save as their usual files: a mapping
saved here maps the take exactly as ``toonface map --mapping`` does with it.
"""

from __future__ import annotations

import copy
import os
from dataclasses import replace
from pathlib import Path

import numpy as np

from capture.takefile import load_take_or_video
from common import InputError, read_document, write_toml
from mapping import parse_mapping, save_profile
from mapping.mapfile import MotorRule
from mapping.mapper import normalise
from mapping.plan import resolved_mode
from mapping.profile import SourceRange
from mapping.sources import Source, head_angles, measure
from mapping.workflow import ReadyTake, map_ready, ready_take
from toon import MOTOR_CODES, MotorTrack

#: The fields of a motor's rule the tuner edits (their meanings: ``mapping/mapfile.py``).
RULE_FIELDS = ("gain", "offset", "scale", "invert", "clamp", "limits", "curve", "max_speed", "filter")
#: Points per curve sent to the page.
CURVE_POINTS = 600


class MappingTuner:
    """A take, its mapping document and its profile, mapped onto a face whose rest is ``neutral``.

    Parameters
    ----------
    take : str
        A take file (``toonface map`` reads the same ones), or a talking-head video, tracked
        without markers first (as ``toonface retarget`` tracks one).
    neutral : ndarray, shape (21,)
        The face's rest pose.
    mapping : str, optional
        A mapping's name or file; the preset matching the take's markers by default.
    units : str, optional
        The take's units where its file does not say (``cm``, ``m``...), as ``toonface map --units``.
    """

    def __init__(self, take: str, neutral: np.ndarray, mapping: str | None = None, units: str | None = None) -> None:
        self.path = Path(take)
        self.neutral = np.asarray(neutral, dtype=np.float64)
        self.ready: ReadyTake = ready_take(load_take_or_video(self.path, units), mapping)
        source = self.ready.mapping.source
        if not source or not Path(source).is_file():
            raise InputError(f"the mapping {self.ready.mapping.name} has no file to tune")
        self.doc = read_document(Path(source))
        self.track = self._map()

    def retarget(self, neutral: np.ndarray) -> None:
        """Map onto another face (whose rest pose is ``neutral``)."""
        self.neutral = np.asarray(neutral, dtype=np.float64)
        self.track = self._map()

    def _map(self) -> MotorTrack:
        return map_ready(self.ready, self.neutral)

    def set_rule(self, code: str, field: str, value: object) -> None:
        """A motor rule's ``field`` (one of :data:`RULE_FIELDS`) to ``value``; None restores the
        default. Refused with the parser's message (naming ``motor.CODE.field``) when invalid."""
        if field not in RULE_FIELDS:
            raise ValueError(f"the tuner edits {', '.join(RULE_FIELDS)}, not {field!r}")
        doc = copy.deepcopy(self.doc)
        rules = doc.setdefault("motor", {})
        if code not in rules:
            raise KeyError(f"the mapping does not drive {code}")
        if value is None:
            rules[code].pop(field, None)
        else:
            rules[code][field] = value
        mapping = parse_mapping(doc, "the tuned mapping")
        self.doc, self.ready = doc, replace(self.ready, mapping=mapping)
        self.track = self._map()

    def set_range(self, key: str, neutral: float, low: float, high: float) -> None:
        """The performer's range of source ``key`` (its rest and its two ends, in the source's units)."""
        values = [float(neutral), float(low), float(high)]
        if not all(np.isfinite(values)) or not low <= neutral <= high or low == high:
            raise ValueError(f"{key}: expected low <= neutral <= high, low below high, got {low:g}, {neutral:g}, "
                             f"{high:g}")
        if key not in self.ready.profile.sources:
            raise KeyError(f"the profile has no source {key!r}")
        sources = {**self.ready.profile.sources, key: SourceRange(*values)}
        self.ready = replace(self.ready, profile=replace(self.ready.profile, sources=sources))
        self.track = self._map()

    def values_at(self, t: float) -> np.ndarray:
        """The mapped motors at ``t`` seconds (the nearest frame), ``(21,)``."""
        frame = int(round(min(max(t, 0.0), self.duration) * self.track.rate))
        return self.track.values[min(frame, self.track.frames - 1)]

    @property
    def duration(self) -> float:
        return self.track.frames / self.track.rate

    def describe(self, code: str | None = None) -> dict:
        """What the tuner panel shows: the motors the mapping drives, each rule's tunable fields,
        the profile's ranges, and for ``code`` its output over the take (``CURVE_POINTS`` samples)."""
        rules = self.doc.get("motor", {})
        out: dict = {"take": str(self.path), "duration": self.duration, "mapping": self.ready.mapping.name,
                     "motors": [c for c in MOTOR_CODES if c in rules],
                     "rules": {c: {k: rules[c].get(k) for k in RULE_FIELDS} for c in rules},
                     "sources": {c: [s.key for s in r.sources] for c, r in
                                 ((r.code, r) for r in self.ready.mapping.rules)},
                     "ranges": {k: [r.neutral, r.low, r.high] for k, r in self.ready.profile.sources.items()}}
        rule = None if code is None else self._rule(code)
        if code is not None and rule is not None:
            column = self.track.values[:, MOTOR_CODES.index(code)]
            at = np.linspace(0, self.track.frames - 1, min(CURVE_POINTS, self.track.frames)).round().astype(int)
            raw = self.raw_values(code)  # measured once, then normalised as the mapping reads them
            out["curve"] = {"code": code, "times": (at / self.track.rate).round(4).tolist(),
                            "values": column[at].round(4).tolist(),
                            "sources": {key: np.nan_to_num(values[at], nan=0.0).round(4).tolist()
                                        for key, values in self.source_values(code, raw).items()},
                            "raw": {key: [None if np.isnan(v) else round(float(v), 3) for v in values[at]]
                                    for key, values in raw.items()},
                            "units": {source.key: source_unit(source) for source in rule.sources}}
        return out

    def source_values(self, code: str, raw: dict[str, np.ndarray] | None = None) -> dict[str, np.ndarray]:
        """Each source of ``code``'s rule over the take, ``(F,)``, normalised as the mapping reads it
        (with a profile: -1 at the performer's low, 0 at rest, 1 at high; NaN where unseen), from
        ``raw`` (:meth:`raw_values`) where the caller has measured them already."""
        rule = self._rule(code)
        if rule is None:
            return {}
        raw = self.raw_values(code) if raw is None else raw
        profile = self.ready.profile
        mode = resolved_mode(rule, profile)
        return {source.key: normalise(raw[source.key], source, rule, profile.sources.get(source.key), mode)
                for source in rule.sources}

    def raw_values(self, code: str) -> dict[str, np.ndarray]:
        """Each source of ``code``'s rule over the take as measured, ``(F,)``, in its own units
        (:func:`source_unit`): what the profile's ranges are written in."""
        rule = self._rule(code)
        if rule is None:
            return {}
        stable = self.ready.prepared.stable
        head = head_angles(stable.rotation, self.ready.profile.rest_rotation, self.ready.profile.head_axes)
        return {source.key: measure(source, stable.local, self.ready.prepared.columns, head, stable.channels)
                for source in rule.sources}

    def _rule(self, code: str) -> MotorRule | None:
        return next((r for r in self.ready.mapping.rules if r.code == code), None)

    def save_mapping(self, path: str | os.PathLike) -> Path:
        target = Path(path)
        if target.suffix.lower() != ".toml":
            raise InputError("a mapping is saved as .toml", target)
        return write_toml(self.doc, target)

    def save_profile(self, path: str | os.PathLike) -> Path:
        return save_profile(self.ready.profile, path)


def source_unit(source: Source) -> str:
    """The unit a source is measured in: ``mm`` for positions and distances, ``°`` for angles and
    the head, ``score`` for blendshapes."""
    return {"angle": "°", "head": "°", "blendshape": "score"}.get(source.kind, "mm")
