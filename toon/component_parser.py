"""Reading CharToon components from a face file or a component library, with field-path errors.

The format is described in :mod:`toon.components`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path
from typing import Any

from common import InputError, read_document, resolve_builtin
from toon.components import Component, MotorParam, PointRef, Visibility
from toon.motors import MOTOR_CODES
from toon.validate import ShapeValidator

LIBRARY_FORMAT = "toonface.components/1"
COMPONENT_KINDS: tuple[str, ...] = ("polyline", "polygon", "ellipse", "skeleton", "image", "composite")
COUPLINGS: tuple[str, ...] = ("point", "edge")
MAX_NESTING = 16


@dataclass
class ComponentParser:
    """Parses and checks components against a face's control points and clip groups.

    Parameters
    ----------
    control_points : tuple of str
        The names a master or slave may refer to.
    clip_groups : tuple of str
        Hole features a component may be clipped to.
    base_dir : Path or None
        Where a face's relative ``library`` paths are looked up.
    drivers : tuple of str
        What may drive ``visible``, ``translate`` and ``scale``: the 21 motors and the face's
        parameters.
    """

    control_points: tuple[str, ...]
    clip_groups: tuple[str, ...]
    base_dir: Path | None = None
    drivers: tuple[str, ...] = MOTOR_CODES
    _libraries: dict[Path, dict] = field(default_factory=dict)

    def parse_list(self, raw: Any, v: ShapeValidator, where: str, depth: int = 0,
                   rename: dict[str, str] | None = None) -> tuple[Component, ...]:
        """Parse a list of components; ``rename`` maps a composite's names onto the face's."""
        v.require(isinstance(raw, list), "must be a list of components", where)
        v.require(depth <= MAX_NESTING, f"composites nested deeper than {MAX_NESTING} (do they use each other?)",
                  where)
        return tuple(self.parse(c, v, f"{where}[{i}]", depth, rename or {}) for i, c in enumerate(raw))

    def parse(self, c: Any, v: ShapeValidator, where: str, depth: int, rename: dict[str, str]) -> Component:
        """Parse one component (recursing into composites)."""
        v.require(isinstance(c, dict), "must be an object", where)
        kind = v.choice(c.get("kind"), COMPONENT_KINDS, f"{where}.kind")
        if kind == "composite":
            return self._composite(c, v, where, depth, rename)
        shape = {"skeleton": {"coupling", "skeleton", "body", "skeleton_closed", "closed"},
                 "polyline": {"points", "closed"}}.get(kind, {"points"})
        common = {"kind", "name", "layer", "fill", "stroke", "width", "smooth", "hidden", "clip", "hole", "depth",
                  "visible", "translate", "scale", "rotate"}
        if kind == "image":
            common = {"kind", "name", "layer", "clip", "depth", "visible", "translate", "scale", "rotate"}
            shape = {"points", "src"}
        v.fields(c, common | shape, where, f"a {kind} component")
        spec: dict[str, Any] = {"kind": kind, "name": str(c.get("name", ""))}
        spec["layer"] = v.integer(c.get("layer", 1), f"{where}.layer", -10, 10)
        v.require(spec["layer"] != 0, "layer 0 is the ToonFace face itself: use -10..-1 or 1..10", f"{where}.layer")
        if kind == "skeleton":
            spec["coupling"] = v.choice(c.get("coupling"), COUPLINGS, f"{where}.coupling")
            spec["points"] = self._points(c.get("skeleton"), v, f"{where}.skeleton", 2, rename,
                                          ("master", "slave", "fixed"))
            v.require(any(p.animated for p in spec["points"]), "a skeleton needs at least one control point",
                      f"{where}.skeleton")
            spec["body"] = self._points(c.get("body"), v, f"{where}.body", 2, rename, ("fixed", "frozen"))
            spec["skeleton_closed"] = v.boolean(c.get("skeleton_closed", False), f"{where}.skeleton_closed")
            spec["closed"] = v.boolean(c.get("closed", True), f"{where}.closed")
            outline = spec["body"]
        else:
            minimum = {"ellipse": 4, "polygon": 3}.get(kind, 2)
            spec["points"] = self._points(c.get("points"), v, f"{where}.points", minimum, rename,
                                          ("master", "slave", "fixed", "frozen"))
            v.require(kind != "ellipse" or len(spec["points"]) == 4,
                      "an ellipse has exactly 4 contour points: left, top, right, bottom", f"{where}.points")
            v.require(kind != "image" or len(spec["points"]) == 3,
                      "an image has exactly 3 points: its top-left, top-right and bottom-left corners",
                      f"{where}.points")
            spec["closed"] = kind != "polyline" or v.boolean(c.get("closed", False), f"{where}.closed")
            outline = spec["points"]
        spec["fill"] = v.optional_color(c.get("fill"), f"{where}.fill")
        spec["stroke"] = v.optional_color(c.get("stroke"), f"{where}.stroke")
        spec["width"] = v.number(c.get("width", 0.0), f"{where}.width", 0.0, 1e4)
        if kind == "image":
            spec["closed"] = True
            spec["src"], spec["picture"] = self._picture(c.get("src"), v, f"{where}.src")
        else:
            v.require(spec["fill"] is not None or (spec["stroke"] is not None and spec["width"] > 0),
                      "draws nothing: give it a fill, or a stroke with a width", where)
        v.require(spec["fill"] is None or spec["closed"], "an open outline cannot be filled", f"{where}.fill")
        spec["smooth"] = self._smooth(c.get("smooth", False), len(outline), spec["closed"], v, f"{where}.smooth")
        segments = len(outline) if spec["closed"] else len(outline) - 1
        hidden = c.get("hidden", [])
        v.require(isinstance(hidden, list), "must be a list of segment indices", f"{where}.hidden")
        spec["hidden"] = tuple(sorted({v.integer(h, f"{where}.hidden[{i}]", 0, segments - 1)
                                       for i, h in enumerate(hidden)}))
        for key in ("clip", "hole"):
            if key in c:
                name = rename.get(c[key], c[key]) if isinstance(c[key], str) else c[key]
                spec[key] = v.choice(name, self.clip_groups, f"{where}.{key}")
        v.require(not spec.get("hole") or spec["fill"] is not None, "a hole needs a fill", f"{where}.hole")
        if "depth" in c:
            spec["depth"] = v.number(c["depth"], f"{where}.depth")
        if "visible" in c:
            raw = c["visible"]
            v.fields(raw, {"motor", "range"}, f"{where}.visible", "visible")
            low, high = v.numbers(raw.get("range"), 2, f"{where}.visible.range")
            spec["visible"] = Visibility(v.choice(raw.get("motor"), self.drivers, f"{where}.visible.motor"),
                                         low, high)
        for key, extra in (("translate", set()), ("scale", {"origin"}), ("rotate", {"origin"})):
            if key in c:
                spec[key] = self._param(c[key], v, f"{where}.{key}", extra, 1 if key == "rotate" else 2)
        component = Component(**spec)
        if component.layer < 0:
            v.require(not component.animated, "background layers (-10..-1) hold only components that never move: "
                      "no control points, visibility, translation or scale", f"{where}.layer")
        return component

    def _composite(self, c: dict, v: ShapeValidator, where: str, depth: int, rename: dict[str, str]) -> Component:
        v.fields(c, {"kind", "name", "components", "use", "library", "controls", "transform"}, where,
                 "a composite component")
        controls = c.get("controls", {})
        v.require(isinstance(controls, dict) and all(isinstance(x, str) for x in controls.values()),
                  'must map names to control points or hole features, like {"M": "BRM"}', f"{where}.controls")
        inner = {name: rename.get(target, target) for name, target in controls.items()}
        transform = c.get("transform", {})
        v.fields(transform, {"scale", "translate"}, f"{where}.transform", "a transform")
        sx, sy = v.numbers(transform.get("scale", [1.0, 1.0]), 2, f"{where}.transform.scale")
        v.require(sx != 0 and sy != 0, "a scale of 0 flattens the composite", f"{where}.transform.scale")
        tx, ty = v.numbers(transform.get("translate", [0.0, 0.0]), 2, f"{where}.transform.translate")
        scope = {**rename, **inner}
        if "use" in c:
            v.require("components" not in c, "give either components or use, not both", where)
            use, library = c["use"], c.get("library")
            if not (isinstance(use, str) and use):
                v.fail("must name a composite in the library", f"{where}.use")
            if not (isinstance(library, str) and library):
                v.fail("must name a component library", f"{where}.library")
            raw, lib_path = self._library_entry(library, use, v, where)
            children = self.parse_list(raw, ShapeValidator(lib_path), f'composites.{use}.components', depth + 1, scope)
            return Component("composite", name=str(c.get("name", "")), children=children, use=use, library=library,
                             controls=tuple(controls.items()), transform=(sx, sy, tx, ty))
        children = self.parse_list(c.get("components"), v, f"{where}.components", depth + 1, scope)
        return Component("composite", name=str(c.get("name", "")), children=children,
                         controls=tuple(controls.items()), transform=(sx, sy, tx, ty))

    def _library_entry(self, library: str, use: str, v: ShapeValidator, where: str) -> tuple[Any, Path]:
        candidate = Path(library)
        if self.base_dir is not None and (candidate.suffix or os.sep in library) and not candidate.is_absolute():
            candidate = self.base_dir / candidate
        try:
            path = resolve_builtin(candidate, "components", ".json", "component library")
        except InputError as exc:
            raise InputError(str(exc), v.source, f"{where}.library") from None
        if path not in self._libraries:
            doc = read_document(path)
            lv = ShapeValidator(path)
            lv.require(doc.get("format") == LIBRARY_FORMAT,
                       f'unsupported format {doc.get("format")!r} (expected "{LIBRARY_FORMAT}")', "format")
            lv.require(isinstance(doc.get("composites"), dict), "missing object", "composites")
            self._libraries[path] = doc["composites"]
        entries = self._libraries[path]
        v.require(use in entries, f'library {path.name} has no composite "{use}" (it has: {", ".join(entries)})',
                  f"{where}.use")
        entry = entries[use]
        ShapeValidator(path).fields(entry, {"description", "components"}, f"composites.{use}", "a library composite")
        return entry.get("components"), path

    def _points(self, raw: Any, v: ShapeValidator, where: str, minimum: int, rename: dict[str, str],
                allowed: tuple[str, ...]) -> tuple[PointRef, ...]:
        v.require(isinstance(raw, list) and len(raw) >= minimum, f"expected a list of at least {minimum} points",
                  where)
        return tuple(self._point(p, v, f"{where}[{i}]", rename, allowed) for i, p in enumerate(raw))

    def _point(self, p: Any, v: ShapeValidator, where: str, rename: dict[str, str],
               allowed: tuple[str, ...]) -> PointRef:
        if isinstance(p, str):
            ref = PointRef("master", self._master(p, v, where, rename))
        elif isinstance(p, list):
            ref = PointRef("frozen", at=v.point(p, where))
        elif isinstance(p, dict) and "slave" in p:
            v.fields(p, {"slave", "at"}, where, "a slave point")
            at = v.point(p.get("at"), f"{where}.at")
            if isinstance(p["slave"], dict):  # a blend of masters
                blend = self._blend(p["slave"], v, f"{where}.slave", rename)
                ref = PointRef("slave", max(blend, key=lambda b: b[1])[0], at, blend)
            else:
                ref = PointRef("slave", self._master(p["slave"], v, f"{where}.slave", rename), at)
        elif isinstance(p, dict) and "fixed" in p:
            v.fields(p, {"fixed"}, where, "a fixed point")
            ref = PointRef("fixed", at=v.point(p["fixed"], f"{where}.fixed"))
        else:
            v.require(False, 'expected "CP" (master), [x, y] (frozen), {"fixed": [x, y]} or '
                             '{"slave": "CP", "at": [x, y]}', where)
        v.require(ref.kind in allowed, f"a {ref.kind} point is not allowed here (allowed: {', '.join(allowed)})",
                  where)
        return ref

    def _picture(self, raw: Any, v: ShapeValidator, where: str) -> tuple[str, Any]:
        from toon.images import load_picture

        v.require(isinstance(raw, str) and raw != "", "expected a .png file beside the face or a PNG data URI", where)
        try:
            return raw, load_picture(raw, self.base_dir)
        except ValueError as exc:
            v.fail(str(exc), where)

    def _blend(self, raw: dict, v: ShapeValidator, where: str, rename: dict[str, str]) -> tuple[tuple[str, float], ...]:
        v.require(len(raw) >= 1, 'expected {"CP": weight, ...}: at least one control point', where)
        blend = []
        for name, weight in raw.items():
            v.require(isinstance(weight, (int, float)) and not isinstance(weight, bool) and 0 < weight <= 1,
                      f"expected a weight in (0, 1], got {weight!r}", f"{where}.{name}")
            blend.append((self._master(name, v, f"{where}.{name}", rename), float(weight)))
        total = sum(w for _, w in blend)
        v.require(abs(total - 1.0) <= 1e-6, f"the weights must sum to 1, got {total:g}", where)
        merged: dict[str, float] = {}
        for name, weight in blend:  # two names renamed onto one control point add up
            merged[name] = merged.get(name, 0.0) + weight
        return tuple(merged.items())

    def _master(self, name: Any, v: ShapeValidator, where: str, rename: dict[str, str]) -> str:
        target = rename.get(name, name) if isinstance(name, str) else name
        v.require(target in self.control_points, f'unknown control point "{target}" (known: '
                  f'{" ".join(self.control_points)})', where)
        return str(target)

    def _smooth(self, raw: Any, n: int, closed: bool, v: ShapeValidator, where: str) -> tuple[tuple[int, int], ...]:
        if raw is False:
            return ()
        if raw is True:
            return ((0, n - 1),)
        v.require(isinstance(raw, list), "expected true, false or a list of [first, last] point ranges", where)
        ranges = []
        for i, r in enumerate(raw):
            v.require(isinstance(r, list) and len(r) == 2, "expected [first, last]", f"{where}[{i}]")
            a = v.integer(r[0], f"{where}[{i}][0]", 0, n - 2)
            b = v.integer(r[1], f"{where}[{i}][1]", a + 1, n - 1)
            ranges.append((a, b))
        ranges.sort()
        for (a0, b0), (a1, _) in pairwise(ranges):
            v.require(a1 >= b0, f"ranges [{a0}, {b0}] and [{a1}, ...] overlap", where)
        v.require(not closed or (0, n - 1) not in ranges or len(ranges) == 1,
                  "smoothing all the way round leaves no other range", where)
        return tuple(ranges)

    def _param(self, raw: Any, v: ShapeValidator, where: str, extra: set[str], size: int = 2) -> MotorParam:
        v.fields(raw, {"motor", "at0", "at1"} | extra, where, where.rsplit(".", 1)[-1])
        motor = v.choice(raw.get("motor"), self.drivers, f"{where}.motor")
        at0 = tuple(v.numbers(raw.get("at0"), size, f"{where}.at0"))
        at1 = tuple(v.numbers(raw.get("at1"), size, f"{where}.at1"))
        origin = tuple(v.numbers(raw.get("origin", [0.0, 0.0]), 2, f"{where}.origin"))
        return MotorParam(motor, at0, at1, origin)  # type: ignore[arg-type]
