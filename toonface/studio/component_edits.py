"""The face editor's CharToon component tools, as changes to a face document.

CharToon's Face Editor (section 3.2 of the CharToon seed) builds a face from components drawn from
nothing: polylines, polygons, ellipses and skeletons, whose points are masters (control points),
slaves that move as their master does, fixed points a skeleton drives, and frozen ones; spline and
invisible ranges of an outline; groups kept as composites and re-used from a library. Each function
here changes a ``toonface.face/1`` document in place; :class:`~toonface.studio.faces.FaceEditor`
validates the result and refuses it, with the validator's message, when the face would be invalid.
The file format is :mod:`toon.components`'.
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from common import InputError, atomic_path, read_document, resolve_builtin
from common.data import names_builtin
from toon import Face
from toon.component_parser import LIBRARY_FORMAT
from toon.components import Component, flatten
from toon.face import FEATURES
from toonface.studio.face_items import component_part, finite, item, rest_of, unique_name, vertex

#: What "new component" makes.
NEW_KINDS = ("polyline", "polygon", "ellipse", "skeleton")
#: How a component's point moves (:class:`toon.components.PointRef`).
POINT_KINDS = ("master", "slave", "fixed", "frozen")


def new_component(doc: dict, kind: str, x: float, y: float, size: float = 40.0) -> int:
    """Add a component of ``kind`` centred on ``(x, y)``, ``size`` across, drawn last in layer 1;
    returns its index. Its points are frozen (a skeleton's: a fixed joint and a slave of the
    nearest control point, driving a body of fixed points), to reshape and re-kind point by point."""
    if kind not in NEW_KINDS:
        raise ValueError(f"a new component is one of {', '.join(NEW_KINDS)}, got {kind!r}")
    cx, cy, h = finite(x), finite(y), finite(size) / 2
    if not h > 0:
        raise ValueError(f"a component's size must be > 0, got {size}")
    spec: dict[str, Any] = {"kind": kind, "name": unique_name(doc, "component", kind)}
    if kind == "polyline":
        spec.update(points=[[cx - h, cy], [cx, cy + h / 2], [cx + h, cy]], stroke="#202020", width=max(h / 8, 1.0))
    elif kind == "polygon":
        spec.update(points=[[cx - h, cy - h], [cx + h, cy - h], [cx + h, cy + h], [cx - h, cy + h]], fill="#808080")
    elif kind == "ellipse":
        spec.update(points=[[cx - h, cy], [cx, cy + h / 2], [cx + h, cy], [cx, cy - h / 2]], fill="#808080")
    else:
        tip = nearest_point(doc, cx + h, cy)
        w = h / 4
        spec.update(coupling="edge", skeleton=[{"fixed": [cx - h, cy]}, {"slave": tip, "at": [cx + h, cy]}],
                    body=[{"fixed": xy} for xy in ([cx - h, cy - w], [cx + h, cy - w], [cx + h, cy + w],
                                                   [cx - h, cy + w])],
                    fill="#808080")
    doc.setdefault("components", []).append(spec)
    return len(doc["components"]) - 1


def nearest_point(doc: dict, x: float, y: float, among: Iterable[str] | None = None) -> str:
    """The control point resting nearest ``(x, y)`` (of ``among``, where given)."""
    return min(doc["points"] if among is None else among,
               key=lambda name: float(np.hypot(doc["points"][name][0] - x, doc["points"][name][1] - y)))


def add_point(doc: dict, component: int, part: str, after: int, x: float, y: float) -> None:
    """A point at ``(x, y)`` after point ``after`` of the component's ``part``, moving as the point
    before it does (after a master, a slave of it). Smooth ranges and invisible segments keep
    their places: a range or a hidden segment the new point falls in grows by it."""
    spec = item(doc, "component", component)
    refs = component_part(spec, part)
    before = vertex(refs, after)
    xy = [finite(x), finite(y)]
    if isinstance(before, str):
        new: object = {"slave": before, "at": xy}
    elif isinstance(before, dict):
        follows = before.get("slave")
        new = {"slave": dict(follows) if isinstance(follows, dict) else follows, "at": xy} if follows else {"fixed": xy}
    else:
        new = xy
    ids: list[int | None] = list(range(len(refs)))
    ids.insert(after + 1, None)
    refs.insert(after + 1, new)
    if _is_outline(spec, part):
        spec["hidden"] = _hidden(spec, len(refs) - 1, ids)
        if spec.get("smooth") is not True:  # smooth all round stays so
            spec["smooth"] = [[a + (a > after), b + (b > after)] for a, b in _ranges(spec)]
        _tidy(spec)


def delete_point(doc: dict, component: int, part: str, index: int) -> None:
    """Remove point ``index``; a smooth range loses it, and the two segments it joined become one,
    invisible when both were."""
    spec = item(doc, "component", component)
    refs = component_part(spec, part)
    vertex(refs, index)
    ids: list[int | None] = [i for i in range(len(refs)) if i != index]
    old = len(refs)
    del refs[index]
    if _is_outline(spec, part):
        spec["hidden"] = _hidden(spec, old, ids)
        if spec.get("smooth") is not True:
            ranges = ([a - (a > index), b - (b >= index)] for a, b in _ranges(spec))
            spec["smooth"] = [[a, b] for a, b in ranges if a < b]
        _tidy(spec)


def set_point_kind(doc: dict, component: int, part: str, index: int, kind: str, master: str | None = None) -> None:
    """Make point ``index`` a master, slave, fixed or frozen point where it rests (a master moves
    to its control point). A master or a slave follows ``master``: by default the control point it
    follows already, or the nearest one."""
    if kind not in POINT_KINDS:
        raise ValueError(f"a point is one of {', '.join(POINT_KINDS)}, got {kind!r}")
    refs = component_part(item(doc, "component", component), part)
    ref = vertex(refs, index)
    xy = rest_of(doc, ref)
    if master is None:
        follows = ref if isinstance(ref, str) else ref.get("slave") if isinstance(ref, dict) else None
        if isinstance(follows, dict):  # a slave of several masters: its heaviest
            follows = max(follows, key=follows.get)
        master = follows or nearest_point(doc, float(xy[0]), float(xy[1]))
    elif master not in doc["points"]:
        raise KeyError(f"no control point {master!r}")
    at = [float(xy[0]), float(xy[1])]
    refs[index] = {"master": master, "slave": {"slave": master, "at": at}, "fixed": {"fixed": at},
                   "frozen": at}[kind]


def group(doc: dict, indices: list[int], name: str = "") -> int:
    """Components ``indices`` made one composite, in their drawing order, where the first of them
    was; returns its index."""
    chosen = sorted(set(indices))
    if not chosen:
        raise ValueError("choose the components to group")
    children = [copy.deepcopy(item(doc, "component", i)) for i in chosen]
    for i in reversed(chosen):
        del doc["components"][i]
    doc["components"].insert(chosen[0], {"kind": "composite",
                                         "name": unique_name(doc, "component", name or "group"),
                                         "components": children})
    return chosen[0]


def placed_children(component: Component) -> list[dict]:
    """A composite's basic components as written, placed by its transform (and its library's
    entry read, its control points renamed): what ungrouping it or saving it to a library keeps."""
    if component.kind != "composite":
        raise ValueError(f"a {component.kind} is not a composite")
    return [c.to_dict() for c in flatten((component,))]


def placed_points(component: Component) -> np.ndarray:
    """Where a component's points other than masters rest, placed by any composites' transforms,
    ``(N, 2)``."""
    found = [p.at for basic in flatten((component,)) for p in (*basic.points, *basic.body) if p.kind != "master"]
    if not found:
        raise ValueError("the component's points all follow control points: nothing to move")
    return np.array(found, dtype=float)


def save_to_library(library: str | os.PathLike, name: str, components: list[dict], description: str = "") -> Path:
    """Write ``components`` as composite ``name`` of a ``toonface.components/1`` library file,
    made if absent; an entry of that name is replaced. The file is checked before it is written."""
    path = Path(library)
    if path.suffix.lower() != ".json":
        raise InputError("a component library is saved as .json", path)
    if not name:
        raise ValueError("a library composite needs a name")
    doc: dict[str, Any] = read_document(path) if path.exists() else {"format": LIBRARY_FORMAT, "composites": {}}
    entries = doc.get("composites")
    if doc.get("format") != LIBRARY_FORMAT or not isinstance(entries, dict):
        raise InputError(f'not a component library (format "{LIBRARY_FORMAT}")', path)
    entries[name] = {"description": description, "components": copy.deepcopy(components)}
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return path


def library_names(library: str) -> list[str]:
    """The composites a library offers (a built-in library's name, or a file)."""
    doc = read_document(resolve_builtin(Path(library), "components", ".json", "component library"))
    if doc.get("format") != LIBRARY_FORMAT or not isinstance(doc.get("composites"), dict):
        raise InputError(f'not a component library (format "{LIBRARY_FORMAT}")', library)
    return list(doc["composites"])


def insert_from_library(doc: dict, library: str, use: str, controls: dict[str, str] | None = None,
                        dx: float = 0.0, dy: float = 0.0) -> int:
    """Add a composite re-used from ``library`` (its entry ``use``), drawn last, moved by
    ``(dx, dy)``, its control points and hole features renamed by ``controls``; returns its index."""
    spec: dict[str, Any] = {"kind": "composite", "name": unique_name(doc, "component", use), "use": use,
                            "library": library}
    if controls:
        spec["controls"] = dict(controls)
    if dx or dy:
        spec["transform"] = {"scale": [1.0, 1.0], "translate": [finite(dx), finite(dy)]}
    doc.setdefault("components", []).append(spec)
    return len(doc["components"]) - 1


def file_libraries(components: list[dict]) -> Iterator[dict]:
    """The composites, at any depth, that re-use a library file (not a built-in library)."""
    for spec in components:
        if spec.get("kind") != "composite":
            continue
        if spec.get("library") and not names_builtin(str(spec["library"])):
            yield spec
        yield from file_libraries(spec.get("components", []))


def rebase_libraries(doc: dict, base_dir: Path | None, target_dir: Path | None = None) -> None:
    """Library files named relative to ``base_dir`` (the face file's folder; None: the working
    folder) named absolutely, or with ``target_dir`` relative to it (where the face is saved)."""
    for spec in file_libraries(doc.get("components", [])):
        path = Path(spec["library"])
        if not path.is_absolute():
            path = (base_dir or Path.cwd()) / path
        path = path.resolve()
        spec["library"] = str(path) if target_dir is None else os.path.relpath(path, target_dir.resolve())


def outlines(face: Face) -> list[list[list[list[float]]]]:
    """Each component's drawn outlines at rest, for the editor's overlay: per component, per basic
    component in it, its points ``[[x, y], ...]`` (a skeleton's body, then its skeleton)."""
    out = []
    for component in face.components:
        lines = []
        for basic in flatten((component,)):
            for refs in ((basic.body, basic.points) if basic.kind == "skeleton" else (basic.points,)):
                lines.append([[float(v) for v in (face.points[p.master] if p.kind == "master" else p.at)]
                              for p in refs])
        out.append(lines)
    return out


# -- an outline's smooth ranges and invisible segments -----------------------------------------------
def _is_outline(spec: dict, part: str) -> bool:
    """Whether ``part`` is what the component draws (its ``smooth`` and ``hidden`` refer to it)."""
    return part == ("body" if spec["kind"] == "skeleton" else "points")


def _closed(spec: dict) -> bool:
    return spec["kind"] in ("polygon", "ellipse") or bool(spec.get("closed", spec["kind"] == "skeleton"))


def _ranges(spec: dict) -> list[tuple[int, int]]:
    return [(int(a), int(b)) for a, b in (spec.get("smooth") or [])]


def _hidden(spec: dict, n: int, ids: list[int | None]) -> list[int]:
    """The invisible segments of the outline whose points are now the old ones ``ids`` (None: the
    new point): a new segment is hidden when every old segment it spans or splits was."""
    hidden = set(int(h) for h in spec.get("hidden", []))
    closed = _closed(spec)
    out = []
    count = len(ids) if closed else len(ids) - 1
    for k in range(count):
        a, b = ids[k], ids[(k + 1) % len(ids)]
        if a is None:  # the new point splits the old segment that ran from the point before it
            spanned = [ids[k - 1]]
        elif b is None:
            spanned = [a]
        else:
            spanned = [(a + j) % n for j in range((b - a) % n if closed else b - a)]
        if spanned and all(s in hidden for s in spanned):
            out.append(k)
    return out


def _tidy(spec: dict) -> None:
    for key in ("hidden", "smooth"):
        if not spec.get(key):
            spec.pop(key, None)



def import_svg(doc: dict, text: str, notes: list[str] | None = None) -> list[int]:
    """An SVG drawing's shapes as components drawn last, fitted into the face's viewbox
    (:func:`toon.svg_import.svg_components`); returns their indices."""
    from toon.svg_import import svg_components

    xmin, ymin, xmax, ymax = (float(v) for v in doc["viewbox"])
    made = svg_components(text, (xmin, ymin, xmax, ymax), notes)
    components = doc.setdefault("components", [])
    for spec in made:
        spec["name"] = unique_name(doc, "component", spec["name"])
        components.append(spec)
    return list(range(len(components) - len(made), len(components)))


def import_picture(doc: dict, data: bytes, name: str) -> int:
    """A PNG picture (its bytes) as an image component drawn last, kept in the face file itself
    (a data URI: the face and its pictures travel as one file), its aspect kept, fitted into the
    middle half of the face's viewbox; frozen where it lands, ready to be moved, attached or put
    on a background layer. Returns its index. A ValueError where it is not a readable PNG."""
    from toon.images import decode_png

    picture = decode_png(data, name)
    xmin, ymin, xmax, ymax = (float(v) for v in doc["viewbox"])
    width, height = picture.size
    scale = 0.5 * min((xmax - xmin) / width, (ymax - ymin) / height)
    cx, cy, half_w, half_h = (xmin + xmax) / 2, (ymin + ymax) / 2, width * scale / 2, height * scale / 2
    left, right, top, bottom = (round(v, 3) for v in (cx - half_w, cx + half_w, cy + half_h, cy - half_h))
    components = doc.setdefault("components", [])
    components.append({"kind": "image", "name": unique_name(doc, "component", Path(name).stem or "picture"),
                       "src": picture.href, "points": [[left, top], [right, top], [left, bottom]]})
    return len(components) - 1


def attach(doc: dict, component: int, feature: str) -> None:
    """Every point of a component made a slave of ``feature`` (one of :data:`toon.face.FEATURES`,
    or a control point's name) where it rests: of the feature's two control points nearest it,
    each weighted by the other's distance (:func:`blend_of`), so a point between two of them bends
    with both and one on a control point moves as it does. The component then moves as that part
    of the face does, smoothly."""
    masters = FEATURES[feature][0] if feature in FEATURES else (feature,) if feature in doc["points"] else None
    if masters is None:
        named = ", ".join(sorted(FEATURES, key=lambda f: f != "mouth"))  # the mouth first, as the page lists them
        raise ValueError(f"attach to one of {named} or a control point, got {feature!r}")
    spec = item(doc, "component", component)
    if spec.get("kind") not in ("polyline", "polygon", "ellipse", "image"):
        raise ValueError(f"attach a polyline, polygon, ellipse or image (a {spec.get('kind')} moves by its own points)")
    refs = component_part(spec, "points")
    for i, ref in enumerate(refs):
        x, y = (float(v) for v in rest_of(doc, ref))
        refs[i] = {"slave": blend_of(doc, x, y, masters), "at": [x, y]}


def blend_of(doc: dict, x: float, y: float, among: Iterable[str]) -> str | dict[str, float]:
    """What a point resting at ``(x, y)`` follows, of the control points ``among``: the nearest
    alone where it is the only one or the point lies on it, else the two nearest, each weighted by
    the other's distance (the nearer the heavier; weights to 3 decimals, summing to 1)."""
    ranked = sorted(among, key=lambda name: float(np.hypot(doc["points"][name][0] - x, doc["points"][name][1] - y)))
    if len(ranked) == 1:
        return ranked[0]
    near, far = ((n, float(np.hypot(doc["points"][n][0] - x, doc["points"][n][1] - y))) for n in ranked[:2])
    weight = round(far[1] / (near[1] + far[1]), 3) if near[1] + far[1] > 0 else 1.0
    return near[0] if weight >= 1.0 else {near[0]: weight, far[0]: round(1.0 - weight, 3)}
