"""The studio's face editor (ToonFace's Editor, CharToon's Face Editor): a face edited as its
``toonface.face/1`` document.

Every edit changes a copy of the document, which :func:`toon.face.face_from_dict` then
validates: a face that would be invalid is refused with the validator's message (which names
the field, such as ``polygons[3].vertices`` or ``motors.MLV``) and the face stays as it was.
Edits are made at the rest pose, in face units (y up), and can be undone and redone.
"""

from __future__ import annotations

import copy
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from common import InputError
from toon import Face, load_face, save_face
from toon.face import KINDS, face_from_dict

#: How many face edits can be undone.
UNDO_LEVELS = 100


class FaceEditor:
    """A face document with validated edits, undo and redo.

    Parameters
    ----------
    face : Face
        The template: a built-in face or a face file, loaded.
    """

    def __init__(self, face: Face) -> None:
        self.face = face
        self.doc = face.to_dict()
        self._undo: list[dict] = []
        self._redo: list[dict] = []
        self.clipboard: tuple[str, dict] | None = None  # ("polygons" or "components", a copy); kept across faces

    # -- the rule every edit goes through ----------------------------------------------------------
    def _edit(self, change: Callable[[dict], None]) -> Face:
        doc = copy.deepcopy(self.doc)
        change(doc)
        face = face_from_dict(doc, source="the edited face")  # InputError: refused, nothing changed
        self._undo = [*self._undo[-(UNDO_LEVELS - 1):], self.doc]
        self._redo.clear()
        self.doc, self.face = doc, face
        return face

    def undo(self) -> bool:
        if not self._undo:
            return False
        self._redo.append(self.doc)
        self._adopt(self._undo.pop())
        return True

    def redo(self) -> bool:
        if not self._redo:
            return False
        self._undo.append(self.doc)
        self._adopt(self._redo.pop())
        return True

    def _adopt(self, doc: dict) -> None:
        self.doc, self.face = doc, face_from_dict(doc, source="the edited face")

    # -- control points and motor ranges -----------------------------------------------------------
    def move_point(self, name: str, x: float, y: float) -> Face:
        """A control point's rest position; it must stay within its motors' ranges."""
        return self._edit(lambda doc: doc["points"].__setitem__(_known(doc["points"], name, "control point"),
                                                                [_finite(x), _finite(y)]))

    def set_range(self, code: str, end: str, value: float) -> Face:
        """One end (``min`` or ``max``) of a motor's range: a coordinate, or degrees for the
        pupils and the head, as the face model has them."""
        if end not in ("min", "max"):
            raise ValueError(f"a range end is min or max, got {end!r}")

        def change(doc: dict) -> None:
            limits = doc["motors"][_known(doc["motors"], code, "motor")]
            limits[0 if end == "min" else 1] = _finite(value)
        return self._edit(change)

    # -- polygons -----------------------------------------------------------------------------------
    def move_vertex(self, polygon: int, index: int, x: float, y: float, state: str = "vertices") -> Face:
        """Vertex ``index`` of polygon ``polygon`` to ``(x, y)`` (``state``: ``vertices`` or, for a
        point-attached polygon, ``vertices_max``)."""
        def change(doc: dict) -> None:
            vertices = _vertices(doc, polygon, state)
            _index(vertices, index)[:] = [_finite(x), _finite(y)]
        return self._edit(change)

    def add_vertex(self, polygon: int, after: int, x: float, y: float) -> Face:
        """A vertex after ``after`` (in both states of a point-attached polygon)."""
        def change(doc: dict) -> None:
            for state in _states(doc, polygon):
                vertices = _vertices(doc, polygon, state)
                _index(vertices, after)
                vertices.insert(after + 1, [_finite(x), _finite(y)])
        return self._edit(change)

    def delete_vertex(self, polygon: int, index: int) -> Face:
        def change(doc: dict) -> None:
            for state in _states(doc, polygon):
                vertices = _vertices(doc, polygon, state)
                _index(vertices, index)
                del vertices[index]
        return self._edit(change)

    def add_polygon(self, x: float, y: float, size: float = 20.0, color: str = "#808080") -> Face:
        """A new free polygon (a square of ``size`` centred on ``(x, y)``), drawn last; reshape it
        by its vertices, then give it a kind and an attachment."""
        half = _finite(size) / 2

        def change(doc: dict) -> None:
            names = {p.get("name") for p in doc["polygons"]}
            name = next(f"shape {k}" for k in range(1, 10_000) if f"shape {k}" not in names)
            square = [[x - half, y - half], [x + half, y - half], [x + half, y + half], [x - half, y + half]]
            doc["polygons"].append({"kind": "free", "name": name, "color": color,
                                    "vertices": [[_finite(a), _finite(b)] for a, b in square]})
        return self._edit(change)

    def delete_polygon(self, polygon: int) -> Face:
        def change(doc: dict) -> None:
            _polygon(doc, polygon)
            del doc["polygons"][polygon]
        return self._edit(change)

    def duplicate_polygon(self, polygon: int, dx: float = 0.0, dy: float = 0.0) -> Face:
        """A copy of the polygon, moved by ``(dx, dy)``, after it (its name, if any, made unique)."""
        def change(doc: dict) -> None:
            twin = copy.deepcopy(_polygon(doc, polygon))
            if twin.get("name"):
                names = {p.get("name") for p in doc["polygons"]}
                twin["name"] = next(f"{twin['name']} {k}" for k in range(2, 1000) if f"{twin['name']} {k}" not in names)
            doc["polygons"].insert(polygon + 1, twin)
            _transform(doc, polygon + 1, lambda xy: xy + [dx, dy])
        return self._edit(change)

    def move_polygon(self, polygon: int, dx: float, dy: float) -> Face:
        return self._edit(lambda doc: _transform(doc, polygon, lambda xy: xy + [_finite(dx), _finite(dy)]))

    def scale_polygon(self, polygon: int, factor: float) -> Face:
        """Scale about the polygon's centre (the mean of its vertices)."""
        if not factor > 0:
            raise ValueError(f"a scale factor must be > 0, got {factor}")

        def change(doc: dict) -> None:
            centre = np.mean(np.asarray(_vertices(doc, polygon, "vertices"), dtype=float), axis=0)
            _transform(doc, polygon, lambda xy: centre + (xy - centre) * factor)
        return self._edit(change)

    def flip_polygon(self, polygon: int, axis: str = "x") -> Face:
        """Mirror the polygon about its centre: ``x`` left to right, ``y`` top to bottom."""
        if axis not in ("x", "y"):
            raise ValueError(f"flip about x or y, got {axis!r}")

        def change(doc: dict) -> None:
            centre = np.mean(np.asarray(_vertices(doc, polygon, "vertices"), dtype=float), axis=0)
            mirror = np.array([-1.0, 1.0]) if axis == "x" else np.array([1.0, -1.0])
            _transform(doc, polygon, lambda xy: centre + (xy - centre) * mirror)
        return self._edit(change)

    def set_style(self, polygon: int, **fields: object) -> Face:
        """Change a polygon's ``color``, ``stroke``, ``width``, ``kind``, ``attach``, ``depth`` or
        ``name`` (None removes an optional one); the validator says what a kind needs."""
        unknown = set(fields) - {"color", "stroke", "width", "kind", "attach", "depth", "name"}
        if unknown:
            raise ValueError(f"unknown polygon field(s) {', '.join(sorted(unknown))}")
        if "kind" in fields and fields["kind"] not in KINDS:
            raise ValueError(f"a kind is one of {', '.join(KINDS)}, got {fields['kind']!r}")

        def change(doc: dict) -> None:
            spec = _polygon(doc, polygon)
            for key, value in fields.items():
                if value is None:
                    spec.pop(key, None)
                else:
                    spec[key] = value
            if spec["kind"] == "point" and "vertices_max" not in spec:  # a new point polygon: both states alike
                spec["vertices_max"] = copy.deepcopy(spec["vertices"])
            if spec["kind"] != "point":
                spec.pop("vertices_max", None)
            if spec["kind"] not in ("hole", "feature", "pupil", "point"):
                spec.pop("attach", None)
        return self._edit(change)

    # -- CharToon components (top level: a composite moves as a unit by its transform) ---------------
    def move_component_point(self, component: int, index: int, x: float, y: float, part: str = "points") -> Face:
        """Point ``index`` of a component's ``part`` (``points``; a skeleton's ``skeleton`` or
        ``body``) to ``(x, y)``; a master point moves with its control point, not here."""
        def change(doc: dict) -> None:
            refs = _component_part(doc, component, part)
            if not 0 <= index < len(refs):
                raise IndexError(f"no point {index} (the component has {len(refs)})")
            refs[index] = _placed(refs[index], np.array([_finite(x), _finite(y)]))
        return self._edit(change)

    def move_component(self, component: int, dx: float, dy: float) -> Face:
        def change(doc: dict) -> None:
            spec = _component(doc, component)
            if spec["kind"] == "composite":
                transform = spec.setdefault("transform", {"scale": [1.0, 1.0], "translate": [0.0, 0.0]})
                tx, ty = transform["translate"]
                transform["translate"] = [tx + _finite(dx), ty + _finite(dy)]
            else:
                _transform_component(spec, lambda xy: xy + [dx, dy])
        return self._edit(change)

    def scale_component(self, component: int, factor: float) -> Face:
        """Scale a component about the centre of its own points."""
        if not factor > 0:
            raise ValueError(f"a scale factor must be > 0, got {factor}")
        return self._edit(lambda doc: _about_centre(doc, component, np.array([factor, factor])))

    def flip_component(self, component: int, axis: str = "x") -> Face:
        if axis not in ("x", "y"):
            raise ValueError(f"flip about x or y, got {axis!r}")
        mirror = np.array([-1.0, 1.0]) if axis == "x" else np.array([1.0, -1.0])
        return self._edit(lambda doc: _about_centre(doc, component, mirror))

    def set_component(self, component: int, **fields: object) -> Face:
        """A component's ``layer`` (-10..-1 behind, 1..10 in front), ``fill``, ``stroke``,
        ``width`` or ``name`` (None removes an optional one)."""
        unknown = set(fields) - {"layer", "fill", "stroke", "width", "name"}
        if unknown:
            raise ValueError(f"unknown component field(s) {', '.join(sorted(unknown))}")

        def change(doc: dict) -> None:
            spec = _component(doc, component)
            for key, value in fields.items():
                if value is None:
                    spec.pop(key, None)
                else:
                    spec[key] = value
        return self._edit(change)

    def duplicate_component(self, component: int, dx: float = 0.0, dy: float = 0.0) -> Face:
        def change(doc: dict) -> None:
            twin = copy.deepcopy(_component(doc, component))
            if twin.get("name"):
                twin["name"] = f"{twin['name']} copy"
            doc["components"].insert(component + 1, twin)
        face = self._edit(change)
        return self.move_component(component + 1, dx, dy) if dx or dy else face

    def delete_component(self, component: int) -> Face:
        def change(doc: dict) -> None:
            _component(doc, component)
            del doc["components"][component]
        return self._edit(change)

    def copy_item(self, kind: str, index: int) -> None:
        """Copy a polygon or a component (``kind``: ``polygon`` or ``component``) to paste into this
        face or another one opened later (not an edit)."""
        spec = _polygon(self.doc, index) if kind == "polygon" else _component(self.doc, index)
        self.clipboard = (f"{kind}s", copy.deepcopy(spec))

    def paste_item(self) -> Face:
        """The copied polygon or component, added to this face (drawn last; a name it already has
        made unique). A component that names a control point works on any face: every face has them."""
        if self.clipboard is None:
            raise ValueError("nothing to paste: copy a polygon or a component first")
        key, spec = self.clipboard

        def change(doc: dict) -> None:
            twin = copy.deepcopy(spec)
            names = {item.get("name") for item in doc.get(key, [])}
            if twin.get("name") in names:
                base = twin["name"]
                twin["name"] = next(f"{base} {k}" for k in range(2, 10_000) if f"{base} {k}" not in names)
            doc.setdefault(key, []).append(twin)
        return self._edit(change)

    def set_background(self, color: str) -> Face:
        return self._edit(lambda doc: doc.__setitem__("background", color))

    def rename(self, name: str, description: str | None = None) -> Face:
        def change(doc: dict) -> None:
            doc["name"] = name
            if description is not None:
                doc["description"] = description
        return self._edit(change)

    # -- files ---------------------------------------------------------------------------------------
    def open(self, name_or_path: str) -> Face:
        """Start from a built-in face (a template) or a face file; undo starts afresh."""
        face = load_face(name_or_path)
        self.face, self.doc = face, face.to_dict()
        self._undo.clear()
        self._redo.clear()
        return face

    def save(self, path: str | os.PathLike) -> Path:
        """Write the face as a new face file (``.json``); what is saved loads back equal."""
        target = Path(path)
        if target.suffix.lower() != ".json":
            raise InputError("a face is saved as .json", target)
        return save_face(self.face, target)

    def describe(self) -> dict:
        """What the page's face panel shows: the document, and how many edits undo and redo hold."""
        return {"doc": self.doc, "undo": len(self._undo), "redo": len(self._redo)}


def _known(table: dict, key: str, what: str) -> str:
    if key not in table:
        raise KeyError(f"no {what} {key!r}")
    return key


def _finite(x: float) -> float:
    value = float(x)
    if not np.isfinite(value):
        raise ValueError(f"expected a finite number, got {x}")
    return value


def _polygon(doc: dict, polygon: int) -> dict:
    polygons = doc["polygons"]
    if not 0 <= polygon < len(polygons):
        raise IndexError(f"the face has no polygon {polygon} (it has {len(polygons)})")
    return polygons[polygon]


def _states(doc: dict, polygon: int) -> list[str]:
    return ["vertices", "vertices_max"] if "vertices_max" in _polygon(doc, polygon) else ["vertices"]


def _vertices(doc: dict, polygon: int, state: str) -> list:
    spec = _polygon(doc, polygon)
    if state not in _states(doc, polygon):
        raise ValueError(f"polygon {polygon} has no {state}")
    return spec[state]


def _index(vertices: list, index: int) -> list:
    if not 0 <= index < len(vertices):
        raise IndexError(f"no vertex {index} (the polygon has {len(vertices)})")
    return vertices[index]


def _component(doc: dict, component: int) -> dict:
    components = doc.get("components", [])
    if not 0 <= component < len(components):
        raise IndexError(f"the face has no component {component} (it has {len(components)})")
    return components[component]


def _component_part(doc: dict, component: int, part: str) -> list:
    spec = _component(doc, component)
    if spec["kind"] == "composite":
        raise ValueError("a composite's points are its parts': move it as a unit")
    if part not in ("points", "skeleton", "body") or part not in spec:
        raise ValueError(f"a {spec['kind']} has no {part}")
    return spec[part]


def _xy(ref: object) -> np.ndarray | None:
    """Where a written point is (None for a master: its control point's)."""
    if isinstance(ref, str):
        return None
    if isinstance(ref, dict):
        return np.asarray(ref.get("at", ref.get("fixed")), dtype=float)
    return np.asarray(ref, dtype=float)


def _placed(ref: object, xy: np.ndarray) -> object:
    """The written point ``ref`` at ``xy``, its kind kept."""
    at = [float(xy[0]), float(xy[1])]
    if isinstance(ref, str):
        raise ValueError(f"a master point moves with its control point {ref}: drag that instead")
    if isinstance(ref, dict):
        return {**ref, "at": at} if "slave" in ref else {"fixed": at}
    return at


def _transform_component(spec: dict, how: Callable[[np.ndarray], np.ndarray]) -> None:
    """Every non-master point of a basic component through ``how`` ((2,) -> (2,))."""
    for part in ("points", "skeleton", "body"):
        if part in spec:
            spec[part] = [ref if (xy := _xy(ref)) is None else _placed(ref, how(xy)) for ref in spec[part]]


def _about_centre(doc: dict, component: int, factors: np.ndarray) -> None:
    """Scale or mirror a basic component about the mean of its non-master points."""
    spec = _component(doc, component)
    if spec["kind"] == "composite":
        raise ValueError("a composite is scaled by its transform in the file, not here")
    placed = [xy for part in ("points", "skeleton", "body") for xy in map(_xy, spec.get(part, [])) if xy is not None]
    if not placed:
        raise ValueError("the component's points all follow control points: nothing to scale")
    centre = np.mean(placed, axis=0)
    _transform_component(spec, lambda xy: centre + (xy - centre) * factors)


def _transform(doc: dict, polygon: int, how: Callable[[np.ndarray], np.ndarray]) -> None:
    """Every vertex of a polygon, in each of its states, through ``how`` ((N, 2) -> (N, 2))."""
    for state in _states(doc, polygon):
        spec = _polygon(doc, polygon)
        spec[state] = [[float(x), float(y)] for x, y in how(np.asarray(spec[state], dtype=float))]
