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

from common import InputError, builtin_names
from common.data import names_builtin
from common.limits import MAX_PICTURE_BYTES, MAX_SVG_BYTES, read_regular
from toon import Face, builtin_faces, load_face, save_face
from toon.face import KINDS, face_from_dict
from toonface.studio import component_edits as parts
from toonface.studio import face_params
from toonface.studio.face_items import (
    LISTS,
    component_part,
    finite,
    item,
    placed,
    points,
    states,
    transform,
    unique_name,
    vertex,
    vertices,
)
from toonface.studio.history import History

#: How many face edits can be undone.
UNDO_LEVELS = 100
#: The fields :meth:`FaceEditor.restyle` changes, by kind of item.
STYLE_FIELDS = {"polygon": {"color", "stroke", "width", "kind", "attach", "depth", "name"},
                "component": {"layer", "fill", "stroke", "width", "name", "closed", "coupling", "skeleton_closed",
                              "smooth", "hidden", "clip", "hole", "depth", "visible", "translate", "scale",
                              "controls", "transform"}}


class FaceEditor:
    """A face document with validated edits, undo and redo.

    Parameters
    ----------
    face : Face
        The template: a built-in face or a face file, loaded.
    """

    def __init__(self, face: Face) -> None:
        self.face: Face = face
        self.doc: dict = {}
        self._start(face)
        self.history: History[dict] = History(UNDO_LEVELS)
        self.clipboard: tuple[str, dict] | None = None  # (kind of item, a copy); kept across faces
        self.listed: dict = {}  # the library last listed: its name and its composites' names
        self.libraries = builtin_names("components", ".json")  # the built-in component libraries

    def _start(self, face: Face) -> None:
        """Edit ``face``: its library files named absolutely while it is edited (written relative
        to the face file again when it is saved)."""
        self.doc = face.to_dict()
        source = face.meta.get("source")
        parts.rebase_libraries(self.doc, Path(source).parent if source else None)
        self.face = face if self.doc == face.to_dict() else face_from_dict(self.doc, source="the edited face")

    # -- the rule every edit goes through ----------------------------------------------------------
    def _edit(self, change: Callable[[dict], object]) -> Face:
        doc = copy.deepcopy(self.doc)
        change(doc)
        face = face_from_dict(doc, source="the edited face")  # InputError: refused, nothing changed
        self.history.push(self.doc)
        self.doc, self.face = doc, face
        return face

    def undo(self) -> bool:
        return self._restore(self.history.undo(self.doc))

    def redo(self) -> bool:
        return self._restore(self.history.redo(self.doc))

    def _restore(self, doc: dict | None) -> bool:
        if doc is None:
            return False
        self.doc, self.face = doc, face_from_dict(doc, source="the edited face")
        return True

    # -- control points and motor ranges -----------------------------------------------------------
    def move_point(self, name: str, x: float, y: float) -> Face:
        """A control point's rest position; it must stay within its motors' ranges."""
        return self._edit(lambda doc: doc["points"].__setitem__(_known(doc["points"], name, "control point"),
                                                                [finite(x), finite(y)]))

    def set_range(self, code: str, end: str, value: float) -> Face:
        """One end (``min`` or ``max``) of a motor's range: a coordinate, or degrees for the
        pupils and the head, as the face model has them."""
        if end not in ("min", "max"):
            raise ValueError(f"a range end is min or max, got {end!r}")

        def change(doc: dict) -> None:
            limits = doc["motors"][_known(doc["motors"], code, "motor")]
            limits[0 if end == "min" else 1] = finite(value)
        return self._edit(change)

    # -- polygons' vertices -------------------------------------------------------------------------
    def move_vertex(self, polygon: int, index: int, x: float, y: float, state: str = "vertices") -> Face:
        """Vertex ``index`` of polygon ``polygon`` to ``(x, y)`` (``state``: ``vertices`` or, for a
        point-attached polygon, ``vertices_max``)."""
        def change(doc: dict) -> None:
            vertex(vertices(item(doc, "polygon", polygon), state), index)[:] = [finite(x), finite(y)]
        return self._edit(change)

    def add_vertex(self, polygon: int, after: int, x: float, y: float) -> Face:
        """A vertex after ``after`` (in both states of a point-attached polygon)."""
        def change(doc: dict) -> None:
            spec = item(doc, "polygon", polygon)
            for state in states(spec):
                vertex(spec[state], after)
                spec[state].insert(after + 1, [finite(x), finite(y)])
        return self._edit(change)

    def delete_vertex(self, polygon: int, index: int) -> Face:
        def change(doc: dict) -> None:
            spec = item(doc, "polygon", polygon)
            for state in states(spec):
                vertex(spec[state], index)
                del spec[state][index]
        return self._edit(change)

    def add_polygon(self, x: float, y: float, size: float = 20.0, color: str = "#808080") -> Face:
        """A new free polygon (a square of ``size`` centred on ``(x, y)``), drawn last; reshape it
        by its vertices, then give it a kind and an attachment."""
        half = finite(size) / 2
        square = [[finite(x) + dx * half, finite(y) + dy * half] for dx, dy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        def change(doc: dict) -> None:
            names = {p.get("name") for p in doc["polygons"]}
            name = next(f"shape {k}" for k in range(1, 10_000) if f"shape {k}" not in names)
            doc["polygons"].append({"kind": "free", "name": name, "color": color, "vertices": square})
        return self._edit(change)

    def move_component_point(self, component: int, index: int, x: float, y: float, part: str = "points") -> Face:
        """Point ``index`` of a component's ``part`` (``points``; a skeleton's ``skeleton`` or
        ``body``) to ``(x, y)``; a master point moves with its control point, not here."""
        def change(doc: dict) -> None:
            refs = component_part(item(doc, "component", component), part)
            refs[index] = placed(vertex(refs, index), np.array([finite(x), finite(y)]))
        return self._edit(change)

    # -- CharToon's components, made from nothing, point by point (:mod:`.component_edits`) ----------
    def new_component(self, kind: str, x: float, y: float, size: float = 40.0) -> Face:
        """A polyline, polygon, ellipse or skeleton centred on ``(x, y)``, drawn last."""
        return self._edit(lambda doc: parts.new_component(doc, kind, x, y, size))

    def add_component_point(self, component: int, part: str, after: int, x: float, y: float) -> Face:
        return self._edit(lambda doc: parts.add_point(doc, component, part, after, x, y))

    def delete_component_point(self, component: int, part: str, index: int) -> Face:
        return self._edit(lambda doc: parts.delete_point(doc, component, part, index))

    def import_artwork(self, path: Path, notes: list[str] | None = None) -> list[int]:
        """An SVG drawing's shapes (:func:`component_edits.import_svg`, what was approximated in
        ``notes``) or a PNG picture (:func:`component_edits.import_picture`) as components drawn
        last; their indices. An :class:`InputError` naming the file where it is neither."""
        path = Path(path)
        try:
            picture = path.suffix.lower() == ".png"
            data = read_regular(path, *((MAX_PICTURE_BYTES, "picture") if picture else (MAX_SVG_BYTES, "drawing")))
            made: list[int] = []
            if picture:
                self._edit(lambda doc: made.append(parts.import_picture(doc, data, path.name)))
            else:
                text = data.decode("utf-8")
                self._edit(lambda doc: made.extend(parts.import_svg(doc, text, notes)))
        except OSError as exc:
            raise InputError(f"cannot read it: {exc.strerror or exc}", path) from None
        except ValueError as exc:  # (a UnicodeDecodeError too)
            raise InputError(str(exc).removeprefix(f"{path.name}: "), path) from None
        return made

    def attach(self, component: int, feature: str) -> Face:
        """A component's points made slaves of ``feature``'s two control points nearest each
        (:func:`component_edits.attach`: mouth, a brow, an eye, or one control point)."""
        return self._edit(lambda doc: parts.attach(doc, component, feature))

    def set_point_kind(self, component: int, part: str, index: int, kind: str, master: str | None = None) -> Face:
        """A component's point made master, slave, fixed or frozen (of ``master``, or the nearest control point)."""
        return self._edit(lambda doc: parts.set_point_kind(doc, component, part, index, kind, master))

    def group(self, indices: list[int], name: str = "") -> Face:
        """Components made one composite, to move, flip, copy and save to a library as one."""
        return self._edit(lambda doc: parts.group(doc, indices, name))

    def ungroup(self, index: int) -> Face:
        """A composite replaced by its components, placed (a library's entry copied into the face)."""
        children = parts.placed_children(self.face.components[_component(self.doc, index)])

        def change(doc: dict) -> None:
            doc["components"][index:index + 1] = children
        return self._edit(change)

    def save_to_library(self, index: int, library: str | os.PathLike, name: str, description: str = "") -> Path:
        """Component ``index`` (a composite's components, placed) written to a component library
        as composite ``name``; not an edit of the face."""
        component = self.face.components[_component(self.doc, index)]
        children = (parts.placed_children(component) if component.kind == "composite"
                    else [component.to_dict()])
        return parts.save_to_library(library, name, children, description)

    def insert_from_library(self, library: str, use: str, controls: dict[str, str] | None = None,
                            dx: float = 0.0, dy: float = 0.0) -> Face:
        """A library's composite re-used in this face, drawn last (a file's path kept absolute)."""
        named = library if names_builtin(library) else str(Path(library).resolve())
        return self._edit(lambda doc: parts.insert_from_library(doc, named, use, controls, dx, dy))

    def list_library(self, library: str) -> None:
        """Read which composites a library offers (shown with the face; not an edit)."""
        self.listed = {"library": library, "names": parts.library_names(library)}

    # -- polygons and components as units (``kind``: ``polygon`` or ``component``) ------------------
    def move(self, kind: str, index: int, dx: float, dy: float) -> Face:
        shift = np.array([finite(dx), finite(dy)])
        return self._edit(lambda doc: transform(item(doc, kind, index), kind, lambda xy: xy + shift))

    def scale(self, kind: str, index: int, factor: float) -> Face:
        """Scale about the item's centre (the mean of its placed points)."""
        if not factor > 0:
            raise ValueError(f"a scale factor must be > 0, got {factor}")
        return self._about_centre(kind, index, np.array([factor, factor]))

    def flip(self, kind: str, index: int, axis: str = "x") -> Face:
        """Mirror about the item's centre: ``x`` left to right, ``y`` top to bottom."""
        if axis not in ("x", "y"):
            raise ValueError(f"flip about x or y, got {axis!r}")
        mirror = np.array([-1.0, 1.0]) if axis == "x" else np.array([1.0, -1.0])
        return self._about_centre(kind, index, mirror)

    def _about_centre(self, kind: str, index: int, factors: np.ndarray) -> Face:
        """Scale or mirror an item about the mean of its placed points; a composite by its
        ``transform``, about the mean of its components' placed points."""
        if kind == "component" and item(self.doc, kind, index)["kind"] == "composite":
            centre = parts.placed_points(self.face.components[index]).mean(axis=0)

            def change(doc: dict) -> None:
                placing = item(doc, kind, index).setdefault("transform", {})
                scale = np.asarray(placing.get("scale", [1.0, 1.0]), dtype=float)
                shift = np.asarray(placing.get("translate", [0.0, 0.0]), dtype=float)
                # about the centre after the transform: c + (s p + t - c) f = (f s) p + c + (t - c) f
                placing["scale"] = (scale * factors).tolist()
                placing["translate"] = (centre + (shift - centre) * factors).tolist()
            return self._edit(change)

        def about(doc: dict) -> None:
            spec = item(doc, kind, index)
            centre = points(spec, kind).mean(axis=0)
            transform(spec, kind, lambda xy: centre + (xy - centre) * factors)
        return self._edit(about)

    def duplicate(self, kind: str, index: int, dx: float = 0.0, dy: float = 0.0) -> Face:
        """A copy of the item, moved by ``(dx, dy)``, just after it (its name made unique)."""
        shift = np.array([finite(dx), finite(dy)])

        def change(doc: dict) -> None:
            twin = copy.deepcopy(item(doc, kind, index))
            if twin.get("name"):
                twin["name"] = unique_name(doc, kind, twin["name"])
            transform(twin, kind, lambda xy: xy + shift)
            doc[LISTS[kind]].insert(index + 1, twin)
        return self._edit(change)

    def delete(self, kind: str, index: int) -> Face:
        def change(doc: dict) -> None:
            item(doc, kind, index)
            del doc[LISTS[kind]][index]
        return self._edit(change)

    def restyle(self, kind: str, index: int, /, **fields: object) -> Face:
        """Change an item's fields (None removes an optional one): a polygon's ``color``, ``stroke``,
        ``width``, ``kind``, ``attach``, ``depth`` or ``name``; a component's ``layer`` (-10..-1
        behind, 1..10 in front), ``fill``, ``stroke``, ``width`` or ``name``. The validator says
        what a polygon's kind needs."""
        unknown = set(fields) - STYLE_FIELDS[kind]
        if unknown:
            raise ValueError(f"unknown {kind} field(s) {', '.join(sorted(unknown))}")
        if kind == "polygon" and "kind" in fields and fields["kind"] not in KINDS:
            raise ValueError(f"a kind is one of {', '.join(KINDS)}, got {fields['kind']!r}")

        def change(doc: dict) -> None:
            spec = item(doc, kind, index)
            for key, value in fields.items():
                if value is None:
                    spec.pop(key, None)
                else:
                    spec[key] = value
            if kind == "polygon":
                if spec["kind"] == "point" and "vertices_max" not in spec:  # a new point polygon: both states alike
                    spec["vertices_max"] = copy.deepcopy(spec["vertices"])
                if spec["kind"] != "point":
                    spec.pop("vertices_max", None)
                if spec["kind"] not in ("hole", "feature", "pupil", "point"):
                    spec.pop("attach", None)
        return self._edit(change)

    def copy_item(self, kind: str, index: int) -> None:
        """Copy a polygon or a component to paste into this face or another one opened later (not an edit)."""
        self.clipboard = (kind, copy.deepcopy(item(self.doc, kind, index)))

    def paste_item(self) -> Face:
        """The copied polygon or component, added to this face (drawn last; a name it already has
        made unique). A component that names a control point works on any face: every face has them."""
        if self.clipboard is None:
            raise ValueError("nothing to paste: copy a polygon or a component first")
        kind, spec = self.clipboard

        def change(doc: dict) -> None:
            twin = copy.deepcopy(spec)
            if twin.get("name"):
                twin["name"] = unique_name(doc, kind, twin["name"])
            doc.setdefault(LISTS[kind], []).append(twin)
        return self._edit(change)

    def set_background(self, color: str) -> Face:
        return self._edit(lambda doc: doc.__setitem__("background", color))

    def rename(self, name: str, description: str | None = None) -> Face:
        def change(doc: dict) -> None:
            doc["name"] = name
            if description is not None:
                doc["description"] = description
        return self._edit(change)

    def set_param(self, code: str, neutral: float | None = None, description: str | None = None,
                  point: str | None = None, dx: float = 0.0, dy: float = 0.0) -> Face:
        """Declare parameter ``code`` beyond the 21 or change it (:func:`face_params.set_param`)."""
        return self._edit(lambda doc: face_params.set_param(doc, code, neutral, description, point, dx, dy))

    def delete_param(self, code: str) -> Face:
        """Remove parameter ``code`` (a component or polygon it drives makes that an error, named)."""
        return self._edit(lambda doc: face_params.delete_param(doc, code))

    def set_driver(self, name: str, param: str, inputs: str, frequency: float, damping: float,
                   swing: float = 1.0, gain: float = 1.0) -> Face:
        """Add physics driver ``name`` or change it (:func:`face_params.set_driver`)."""
        return self._edit(lambda doc: face_params.set_driver(doc, name, param, inputs, frequency, damping,
                                                             bool(swing), gain))

    def delete_driver(self, name: str) -> Face:
        """Remove physics driver ``name``."""
        return self._edit(lambda doc: face_params.delete_driver(doc, name))

    # -- files ---------------------------------------------------------------------------------------
    def open(self, name_or_path: str) -> Face:
        """Start from a built-in face (a template) or a face file; undo starts afresh."""
        self._start(load_face(name_or_path))
        self.history.clear()
        return self.face

    def save(self, path: str | os.PathLike) -> Path:
        """Write the face as a new face file (``.json``); what is saved loads back equal, but for
        the library files its composites re-use, which it names relative to itself."""
        target = Path(path)
        if target.suffix.lower() != ".json":
            raise InputError("a face is saved as .json", target)
        if self.face.name in builtin_faces() and target.stem != self.face.name:  # a template's copy is a new face,
            self.rename(target.stem)  # named as its file (issue 69: a cat saved as mine.json said "cat")
        if not any(parts.file_libraries(self.doc.get("components", []))):
            return save_face(self.face, target)
        doc = copy.deepcopy(self.doc)
        parts.rebase_libraries(doc, None, target.parent)
        return save_face(face_from_dict(doc, source=target), target)

    def describe(self) -> dict:
        """What the page's face panel shows: the document, and how many edits undo and redo hold."""
        return {"doc": self.doc, "outlines": parts.outlines(self.face),
                "libraries": self.libraries, "listed": self.listed, **self.history.counts()}


def _component(doc: dict, index: int) -> int:
    item(doc, "component", index)
    return index


def _known(table: dict, key: str, what: str) -> str:
    if key not in table:
        raise KeyError(f"no {what} {key!r}")
    return key



