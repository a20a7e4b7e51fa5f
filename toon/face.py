"""Face files: the ToonFace face description plus CharToon components, versioned JSON.

A face (``"format": "toonface.face/1"``) holds:

- ``viewbox`` ``[xmin, ymin, xmax, ymax]`` in face units, x to the viewer's right, y up; the
  character's right is on the viewer's left;
- ``points``: the rest position of every control point (:data:`CONTROL_POINTS`); the face is
  drawn at rest, so a motor's neutral value is where its point rests within its range;
- ``motors``: ``[min, max]`` for each of the 21 motors (A1.2.1): the coordinate of its point at
  value 0 and 1, except that the pupils' and the head's limits are in degrees, (0, 0) straight
  out of the screen, left and up positive: a pupil moves ``eyes.radius * sin(angle)`` from its
  rest point and narrows by ``cos(angle)``;
- ``head``: ``pivot`` of the head turn and ``feature_depth``, how far features stand in front of
  the outline (see :mod:`toon.rig`), and ``tilt``, how many degrees the head rolls each way
  about the pivot for the extra parameter ``HT`` (0, absent: the face has no ``HT``);
  ``eyes``: ``radius`` of the eyeballs;
- ``params``: parameters beyond the 21 motors (:mod:`toon.params`): each moves control points,
  and drives components and point polygons as a motor does;
- ``physics``: drivers, damped springs that move parameters after the motors (:mod:`toon.physics`):
  hair that swings, a hat that bounces;
- ``polygons``: ToonFace's filled polygons, each with a ``kind`` that fixes how it moves and when
  it is drawn (A1.2.2) and what ``attach`` names: ``hole`` (a feature: an eye or the mouth),
  ``pupil`` (its control point, PR or PL; clipped to its eye's holes), ``face`` (at most one,
  drawn minus the holes), ``free`` (never moves), ``point`` (a motor or a parameter; two states
  ``vertices`` at 0 and ``vertices_max`` at 1, A1.5-A1.6), ``feature`` (a feature; follows its control-point
  lines, A1.1-A1.4); optional ``stroke`` colour and ``width`` draw its outline;
- ``components``: CharToon's components (:mod:`toon.components`), drawn in their layers.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from common import atomic_path, builtin_names, read_document, resolve_builtin
from toon.component_parser import ComponentParser
from toon.components import Component, flatten
from toon.motors import MOTOR_CODES, MOTORS
from toon.params import ParamSpec, parse_params
from toon.physics import Driver, parse_physics
from toon.validate import Color, ShapeValidator, Vertices, format_color

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
#: Motors whose limits are angles in degrees (A1.2.1: "for the eyes and head").
ANGLE_MOTORS: tuple[str, ...] = ("PLH", "PLV", "PRH", "PRV", "HH", "HV")


@dataclass(frozen=True)
class PolygonSpec:
    """One polygon of a face as written in its file (vertices at the rest pose)."""

    kind: str
    color: Color
    vertices: Vertices
    name: str = ""
    attach: str = ""  # hole, feature: a feature; pupil: PR or PL; point: a motor
    vertices_max: Vertices = ()  # point: the state at motor value 1 (``vertices`` is value 0)
    depth: float | None = None  # head parallax; None = the face's default for the kind
    stroke: Color | None = None
    width: float = 0.0


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
    eye_radius: float = 0.0
    head_tilt: float = 0.0
    params: tuple[ParamSpec, ...] = ()
    physics: tuple[Driver, ...] = ()
    components: tuple[Component, ...] = ()
    description: str = ""
    meta: dict = field(default_factory=dict, compare=False)

    def basic_components(self) -> list[Component]:
        """Every basic component, composites expanded and placed, in file order."""
        return flatten(self.components)

    def neutral(self) -> np.ndarray:
        """Motor values at which the face shows its rest drawing, shape ``(21,)``."""
        out = np.empty(len(MOTORS))
        for i, m in enumerate(MOTORS):
            lo, hi = self.ranges[m.code]
            rest = 0.0 if m.code in ANGLE_MOTORS else self.points[m.point][0 if m.axis == "x" else 1]
            out[i] = (rest - lo) / (hi - lo)
        return out

    @property
    def extra_codes(self) -> tuple[str, ...]:
        """The parameters beyond the 21 this face declares: ``HT`` where it tilts, then ``params``."""
        return (("HT",) if self.head_tilt else ()) + tuple(p.code for p in self.params)

    def extra_neutral(self) -> dict[str, float]:
        """Each extra parameter at which the face shows its rest drawing (``HT`` upright: 0.5)."""
        return {**({"HT": 0.5} if self.head_tilt else {}), **{p.code: p.neutral for p in self.params}}

    def to_dict(self) -> dict[str, Any]:
        """The face as its JSON document."""
        polys = []
        for p in self.polygons:
            d: dict[str, Any] = {"kind": p.kind}
            if p.name:
                d["name"] = p.name
            if p.attach:
                d["attach"] = p.attach
            d["color"] = format_color(p.color)
            if p.stroke is not None:
                d["stroke"], d["width"] = format_color(p.stroke), p.width
            if p.depth is not None:
                d["depth"] = p.depth
            d["vertices"] = [list(v) for v in p.vertices]
            if p.vertices_max:
                d["vertices_max"] = [list(v) for v in p.vertices_max]
            polys.append(d)
        doc = {
            "format": FORMAT, "name": self.name, "description": self.description,
            "viewbox": list(self.viewbox), "background": format_color(self.background),
            "head": {"pivot": list(self.head_pivot), "feature_depth": self.feature_depth,
                     **({"tilt": self.head_tilt} if self.head_tilt else {})},
            "eyes": {"radius": self.eye_radius},
            "points": {k: list(v) for k, v in self.points.items()},
            "motors": {k: list(v) for k, v in self.ranges.items()},
            "polygons": polys,
        }
        if self.params:
            doc["params"] = {p.code: p.to_dict() for p in self.params}
        if self.physics:
            doc["physics"] = [d.to_dict() for d in self.physics]
        if self.components:
            doc["components"] = [c.to_dict() for c in self.components]
        return doc


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
        tmp.write_text(face_text(face), encoding="utf-8")
    return path


def face_text(face: Face) -> str:
    """``face`` as the JSON :func:`save_face` writes."""
    return json.dumps(face.to_dict(), indent=1) + "\n"


def face_from_dict(doc: Any, source: str | os.PathLike | None = None) -> Face:
    """Validate a face document; errors name ``source`` and the path of the bad field."""
    v = ShapeValidator(source)
    v.require(isinstance(doc, dict), "a face file must hold a JSON object", "")
    v.require(doc.get("format") == FORMAT, f'unsupported format {doc.get("format")!r} (expected "{FORMAT}")',
              "format")
    v.fields(doc, {"format", "name", "description", "viewbox", "background", "head", "eyes", "points", "motors",
                   "params", "physics", "polygons", "components"}, "", "a face")
    v.require(isinstance(doc.get("points"), dict), "missing object", "points")
    for name in CONTROL_POINTS:
        v.require(name in doc["points"], "missing control point", f"points.{name}")
    points = {name: v.point(doc["points"][name], f"points.{name}") for name in CONTROL_POINTS}
    extra = sorted(set(doc["points"]) - set(CONTROL_POINTS))
    v.require(not extra, f"unknown control point(s) {extra} (known: {' '.join(CONTROL_POINTS)})", "points")
    v.require(isinstance(doc.get("motors"), dict), "missing object", "motors")
    ranges = {code: _motor_range(v, doc["motors"].get(code), f"motors.{code}") for code in MOTOR_CODES}
    extra = sorted(set(doc["motors"]) - set(MOTOR_CODES))
    v.require(not extra, f"unknown motor(s) {extra}", "motors")
    for m in MOTORS:
        lo, hi = ranges[m.code]
        where = f"motors.{m.code}"
        if m.code in ANGLE_MOTORS:
            v.require(lo < 0 < hi and hi - lo <= 180,
                      f"an angle range runs from negative to positive degrees, within 180, got [{lo}, {hi}]", where)
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
    v.fields(head, {"pivot", "feature_depth", "tilt"}, "head", "head")
    eyes = doc.get("eyes", {})
    v.fields(eyes, {"radius"}, "eyes", "eyes")
    params = parse_params(doc.get("params"), v, CONTROL_POINTS)
    drivers = (*MOTOR_CODES, *(("HT",) if head.get("tilt") else ()), *(p.code for p in params))
    physics = parse_physics(doc.get("physics"), v, drivers, drivers[len(MOTOR_CODES):])
    raw_polys = doc.get("polygons", [])
    v.require(isinstance(raw_polys, list), "must be a list", "polygons")
    polygons = tuple(_polygon(v, p, f"polygons[{i}]", drivers) for i, p in enumerate(raw_polys))
    n_face = sum(p.kind == "face" for p in polygons)
    v.require(n_face <= 1, f'a face has at most one polygon of kind "face", found {n_face}', "polygons")
    names = [p.name for p in polygons if p.name]
    v.require(len(names) == len(set(names)), "polygon names must be unique", "polygons")
    parser = ComponentParser(CONTROL_POINTS, HOLE_FEATURES, Path(source).parent if source is not None else None,
                             drivers)
    components = parser.parse_list(doc.get("components", []), v, "components")
    v.require(bool(polygons) or bool(components), "a face needs at least one polygon or component", "polygons")
    return Face(
        name=str(doc.get("name") or Path(source or "face").stem), viewbox=viewbox,  # type: ignore[arg-type]
        background=v.color(doc.get("background", "#ffffff"), "background"),
        points=points, ranges=ranges, polygons=polygons,
        head_pivot=tuple(v.numbers(head.get("pivot", [0, 0]), 2, "head.pivot")),  # type: ignore[arg-type]
        feature_depth=v.number(head.get("feature_depth", 0.0), "head.feature_depth"),
        head_tilt=v.number(head.get("tilt", 0.0), "head.tilt", 0.0, 90.0), params=params, physics=physics,
        eye_radius=v.number(eyes.get("radius", 0.0), "eyes.radius", 0.0),
        components=components,
        description=str(doc.get("description", "")),
        meta={} if source is None else {"source": str(source)},
    )


def _motor_range(v: ShapeValidator, value: Any, where: str) -> tuple[float, float]:
    v.require(value is not None, "missing motor range [min, max]", where)
    lo, hi = v.numbers(value, 2, where)
    v.require(lo != hi, f"min and max are both {lo}", where)
    return (lo, hi)


def _polygon(v: ShapeValidator, p: Any, where: str, drivers: tuple[str, ...] = MOTOR_CODES) -> PolygonSpec:
    v.require(isinstance(p, dict), "must be an object", where)
    kind = v.choice(p.get("kind"), KINDS, f"{where}.kind")
    attached = kind in ("hole", "feature", "pupil", "point")
    allowed = {"kind", "name", "color", "vertices", "depth", "stroke", "width"}
    allowed |= {"attach"} if attached else set()
    allowed |= {"vertices_max"} if kind == "point" else set()
    v.fields(p, allowed, where, f"a {kind} polygon")
    spec: dict[str, Any] = {"kind": kind, "name": str(p.get("name", "")),
                            "color": v.color(p.get("color"), f"{where}.color"),
                            "vertices": v.vertices(p.get("vertices"), f"{where}.vertices")}
    if "depth" in p:
        spec["depth"] = v.number(p["depth"], f"{where}.depth")
    if "stroke" in p:
        spec["stroke"] = v.color(p["stroke"], f"{where}.stroke")
        spec["width"] = v.number(p.get("width"), f"{where}.width", 0.0, 1e4)
    else:
        v.require("width" not in p, "a width needs a stroke colour", f"{where}.width")
    attach = p.get("attach")
    if kind in ("hole", "feature"):
        options = HOLE_FEATURES if kind == "hole" else tuple(FEATURES)
        spec["attach"] = v.choice(attach, options, f"{where}.attach")
    elif kind == "pupil":
        v.require(attach in PUPIL_EYES, f'unknown control point "{attach}" for a pupil (PR or PL)', f"{where}.attach")
        spec["attach"] = attach
    elif kind == "point":
        if isinstance(attach, str) and attach in CONTROL_POINTS and attach not in MOTOR_CODES:
            moving = [m.code for m in MOTORS if m.point == attach]
            v.require(False, f'control point "{attach}" ' + (f"moves in 2-D: attach to one of its motors {moving}"
                      if moving else "never moves: use a free polygon"), f"{where}.attach")
        v.require(attach in drivers, f'unknown control point "{attach}" (a point polygon attaches to a '
                  f'motor or a parameter of the face: {" ".join(drivers)})', f"{where}.attach")
        spec["attach"] = attach
        spec["vertices_max"] = v.vertices(p.get("vertices_max"), f"{where}.vertices_max")
        v.require(len(spec["vertices_max"]) == len(spec["vertices"]),
                  f"vertices_max has {len(spec['vertices_max'])} points, vertices {len(spec['vertices'])}",
                  f"{where}.vertices_max")
        v.not_degenerate(spec["vertices_max"], f"{where}.vertices_max")
    v.not_degenerate(spec["vertices"], f"{where}.vertices")
    return PolygonSpec(**spec)
