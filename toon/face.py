"""Face files: the ToonFace face description, versioned JSON, validated on load.

A face (``"format": "toonface.face/1"``) holds:

- ``viewbox`` ``[xmin, ymin, xmax, ymax]`` in face units, x to the viewer's right, y up; the
  character's right is on the viewer's left;
- ``points``: the rest position of every control point (:data:`CONTROL_POINTS`); the face is
  drawn at rest, so a motor's neutral value is where its point rests within its range;
- ``motors``: ``[min, max]`` for each of the 21 motors: the coordinate of its point at value 0
  and 1 (degrees for the head motors HH and HV);
- ``head``: ``pivot`` of the head turn and ``feature_depth``, how far features stand in front of
  the outline (see :mod:`toon.rig`);
- ``polygons``: filled polygons with a ``kind`` that fixes how they move and when they are drawn
  (A1.2.2): ``hole`` (attached to an eye or the mouth), ``pupil`` (moves with PR or PL, clipped
  to its eye's holes), ``face`` (exactly one, drawn minus the holes), ``free`` (never moves),
  ``point`` (two states interpolated by one motor, A1.5-A1.6), ``feature`` (follows a feature's
  control-point lines, A1.1-A1.4).
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from common import InputError, atomic_path, builtin_names, read_document, resolve_builtin
from toon.motors import MOTORS, MOTOR_CODES

FORMAT = "toonface.face/1"

#: Features and their control points in line order; ``True`` where the lines close a loop.
FEATURES: dict[str, tuple[tuple[str, ...], bool]] = {
    "brow_right": (("BRM", "BRC", "BRL"), False),
    "brow_left": (("BLM", "BLC", "BLL"), False),
    "eye_right": (("ERI", "ERU", "ERO", "ERL"), True),
    "eye_left": (("ELI", "ELU", "ELO", "ELL"), True),
    "mouth": (("MR", "MT", "ML", "MB"), True),
}
#: The eye whose holes clip each pupil.
PUPIL_EYES: dict[str, str] = {"PR": "eye_right", "PL": "eye_left"}
CONTROL_POINTS: tuple[str, ...] = tuple(p for pts, _ in FEATURES.values() for p in pts) + ("PR", "PL")
#: Drawing order of A1.2.2.
KINDS: tuple[str, ...] = ("hole", "pupil", "face", "free", "point", "feature")
HOLE_FEATURES: tuple[str, ...] = ("eye_right", "eye_left", "mouth")

Color = tuple[float, float, float, float]
Vertices = tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class PolygonSpec:
    """One polygon of a face as written in its file (vertices at the rest pose)."""

    kind: str
    color: Color
    vertices: Vertices
    name: str = ""
    feature: str = ""  # hole, feature
    point: str = ""  # pupil
    motor: str = ""  # point
    vertices_max: Vertices = ()  # point: the state at motor value 1 (``vertices`` is value 0)
    depth: float | None = None  # head parallax; None = the face's default for the kind


@dataclass(frozen=True)
class Face:
    """A parsed, validated face. Build with :func:`load_face` or :func:`face_from_dict`."""

    name: str
    viewbox: tuple[float, float, float, float]
    background: Color
    points: dict[str, tuple[float, float]]
    ranges: dict[str, tuple[float, float]]
    polygons: tuple[PolygonSpec, ...]
    head_pivot: tuple[float, float] = (0.0, 0.0)
    feature_depth: float = 0.0
    description: str = ""
    meta: dict = field(default_factory=dict, compare=False)

    def neutral(self) -> np.ndarray:
        """Motor values at which the face shows its rest drawing, shape ``(21,)``."""
        out = np.empty(len(MOTORS))
        for i, m in enumerate(MOTORS):
            lo, hi = self.ranges[m.code]
            rest = 0.0 if m.point == "HEAD" else self.points[m.point][0 if m.axis == "x" else 1]
            out[i] = (rest - lo) / (hi - lo)
        return out

    def to_dict(self) -> dict[str, Any]:
        """The face as its JSON document."""
        polys = []
        for p in self.polygons:
            d: dict[str, Any] = {"kind": p.kind}
            if p.name:
                d["name"] = p.name
            for key in ("feature", "point", "motor"):
                if getattr(p, key):
                    d[key] = getattr(p, key)
            d["color"] = _format_color(p.color)
            if p.depth is not None:
                d["depth"] = p.depth
            d["vertices"] = [list(v) for v in p.vertices]
            if p.vertices_max:
                d["vertices_max"] = [list(v) for v in p.vertices_max]
            polys.append(d)
        return {
            "format": FORMAT, "name": self.name, "description": self.description,
            "viewbox": list(self.viewbox), "background": _format_color(self.background),
            "head": {"pivot": list(self.head_pivot), "feature_depth": self.feature_depth},
            "points": {k: list(v) for k, v in self.points.items()},
            "motors": {k: list(v) for k, v in self.ranges.items()},
            "polygons": polys,
        }


def builtin_faces() -> list[str]:
    """Names of the faces shipped in ``data/faces``."""
    return builtin_names("faces", ".json")


def load_face(name_or_path: str | os.PathLike) -> Face:
    """Load a face by built-in name (``"classic"``) or from a JSON file; validate it."""
    path = resolve_builtin(name_or_path, "faces", ".json", "face")
    doc = read_document(path)
    return face_from_dict(doc, source=path)


def save_face(face: Face, path: str | os.PathLike) -> Path:
    """Write ``face`` as JSON, atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(face.to_dict(), indent=1) + "\n", encoding="utf-8")
    return path


def face_from_dict(doc: Any, source: str | os.PathLike | None = None) -> Face:
    """Validate a face document; errors name ``source`` and the path of the bad field."""
    v = _Validator(source)
    v.require(isinstance(doc, dict), "a face file must hold a JSON object", "")
    v.require(doc.get("format") == FORMAT, f'unsupported format {doc.get("format")!r} (expected "{FORMAT}")',
              "format")
    v.require(isinstance(doc.get("points"), dict), "missing object", "points")
    points = {name: v.point(doc["points"].get(name), f"points.{name}") for name in CONTROL_POINTS}
    extra = sorted(set(doc["points"]) - set(CONTROL_POINTS))
    v.require(not extra, f"unknown control point(s) {extra} (known: {' '.join(CONTROL_POINTS)})", "points")
    v.require(isinstance(doc.get("motors"), dict), "missing object", "motors")
    ranges = {code: v.motor_range(doc["motors"].get(code), f"motors.{code}") for code in MOTOR_CODES}
    extra = sorted(set(doc["motors"]) - set(MOTOR_CODES))
    v.require(not extra, f"unknown motor(s) {extra}", "motors")
    for m in MOTORS:
        lo, hi = ranges[m.code]
        where = f"motors.{m.code}"
        if m.point == "HEAD":
            v.require(lo < 0 < hi, f"head range must run from negative to positive degrees, got [{lo}, {hi}]", where)
            continue
        v.require(np.sign(hi - lo) == m.increasing,
                  f"[min, max] = [{lo}, {hi}] runs the wrong way: value 1 must be "
                  f"{'larger' if m.increasing > 0 else 'smaller'} in {m.axis} ({m.description})", where)
        rest = points[m.point][0 if m.axis == "x" else 1]
        v.require(min(lo, hi) <= rest <= max(lo, hi),
                  f"control point {m.point} rests at {m.axis}={rest}, outside its range [{lo}, {hi}]", where)
    viewbox = tuple(v.numbers(doc.get("viewbox"), 4, "viewbox"))
    v.require(viewbox[2] > viewbox[0] and viewbox[3] > viewbox[1], "must be [xmin, ymin, xmax, ymax]", "viewbox")
    head = doc.get("head", {})
    v.require(isinstance(head, dict), "must be an object", "head")
    raw_polys = doc.get("polygons")
    v.require(isinstance(raw_polys, list) and raw_polys, "must be a non-empty list", "polygons")
    polygons = tuple(v.polygon(p, f"polygons[{i}]") for i, p in enumerate(raw_polys))
    n_face = sum(p.kind == "face" for p in polygons)
    v.require(n_face == 1, f"a face needs exactly one polygon of kind \"face\", found {n_face}", "polygons")
    names = [p.name for p in polygons if p.name]
    v.require(len(names) == len(set(names)), "polygon names must be unique", "polygons")
    return Face(
        name=str(doc.get("name") or Path(source or "face").stem), viewbox=viewbox,  # type: ignore[arg-type]
        background=v.color(doc.get("background", "#ffffff"), "background"),
        points=points, ranges=ranges, polygons=polygons,
        head_pivot=tuple(v.numbers(head.get("pivot", [0, 0]), 2, "head.pivot")),  # type: ignore[arg-type]
        feature_depth=v.numbers([head.get("feature_depth", 0.0)], 1, "head.feature_depth")[0],
        description=str(doc.get("description", "")),
        meta={} if source is None else {"source": str(source)},
    )


_HEX = re.compile(r"^#([0-9a-fA-F]{6})([0-9a-fA-F]{2})?$")


def _format_color(c: Color) -> str:
    rgb = "".join(f"{round(x * 255):02x}" for x in c[:3])
    return f"#{rgb}" if c[3] >= 1.0 else f"#{rgb}{round(c[3] * 255):02x}"


class _Validator:
    """Checks pieces of a face document, raising :class:`InputError` with the field's path."""

    def __init__(self, source: str | os.PathLike | None) -> None:
        self.source = source

    def require(self, ok: bool, message: str, where: str) -> None:
        if not ok:
            raise InputError(message, self.source, where or None)

    def numbers(self, value: Any, n: int, where: str) -> list[float]:
        ok = (isinstance(value, list) and len(value) == n
              and all(isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x) for x in value))
        self.require(ok, f"expected {n} finite number{'s' if n > 1 else ''}, got {value!r}", where)
        return [float(x) for x in value]

    def point(self, value: Any, where: str) -> tuple[float, float]:
        self.require(value is not None, "missing control point", where)
        x, y = self.numbers(value, 2, where)
        return (x, y)

    def motor_range(self, value: Any, where: str) -> tuple[float, float]:
        self.require(value is not None, "missing motor range [min, max]", where)
        lo, hi = self.numbers(value, 2, where)
        self.require(lo != hi, f"min and max are both {lo}", where)
        return (lo, hi)

    def color(self, value: Any, where: str) -> Color:
        m = _HEX.match(value) if isinstance(value, str) else None
        self.require(m is not None, f'expected a colour "#rrggbb" or "#rrggbbaa", got {value!r}', where)
        rgb = m.group(1)  # type: ignore[union-attr]
        alpha = int(m.group(2), 16) / 255 if m.group(2) else 1.0  # type: ignore[union-attr]
        return (int(rgb[0:2], 16) / 255, int(rgb[2:4], 16) / 255, int(rgb[4:6], 16) / 255, alpha)

    def vertices(self, value: Any, where: str) -> Vertices:
        self.require(isinstance(value, list) and len(value) >= 3, "a polygon needs a list of at least 3 [x, y]",
                     where)
        return tuple(tuple(self.numbers(p, 2, f"{where}[{i}]")) for i, p in enumerate(value))  # type: ignore[misc]

    def polygon(self, p: Any, where: str) -> PolygonSpec:
        self.require(isinstance(p, dict), "must be an object", where)
        kind = p.get("kind")
        self.require(kind in KINDS, f"unknown kind {kind!r} (one of {', '.join(KINDS)})", f"{where}.kind")
        allowed = {"kind", "name", "color", "vertices", "depth"} | {
            "hole": {"feature"}, "feature": {"feature"}, "pupil": {"point"},
            "point": {"motor", "vertices_max"}}.get(kind, set())
        extra = sorted(set(p) - allowed)
        self.require(not extra, f"unexpected field(s) {extra} for a {kind} polygon", where)
        spec: dict[str, Any] = {"kind": kind, "name": str(p.get("name", "")),
                                "color": self.color(p.get("color"), f"{where}.color"),
                                "vertices": self.vertices(p.get("vertices"), f"{where}.vertices")}
        if "depth" in p:
            spec["depth"] = self.numbers([p["depth"]], 1, f"{where}.depth")[0]
        if kind in ("hole", "feature"):
            options = HOLE_FEATURES if kind == "hole" else tuple(FEATURES)
            self.require(p.get("feature") in options,
                         f'unknown feature {p.get("feature")!r} (one of {", ".join(options)})', f"{where}.feature")
            spec["feature"] = p["feature"]
        elif kind == "pupil":
            self.require(p.get("point") in PUPIL_EYES,
                         f'unknown control point {p.get("point")!r} for a pupil (PR or PL)', f"{where}.point")
            spec["point"] = p["point"]
        elif kind == "point":
            self.require(p.get("motor") in MOTOR_CODES, f'unknown motor {p.get("motor")!r}', f"{where}.motor")
            spec["motor"] = p["motor"]
            spec["vertices_max"] = self.vertices(p.get("vertices_max"), f"{where}.vertices_max")
            self.require(len(spec["vertices_max"]) == len(spec["vertices"]),
                         f"vertices_max has {len(spec['vertices_max'])} points, vertices {len(spec['vertices'])}",
                         f"{where}.vertices_max")
        return PolygonSpec(**spec)
