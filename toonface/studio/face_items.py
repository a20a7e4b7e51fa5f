"""A face document's polygons and components as items the face editor handles alike: found by
kind and index, their placed points read and moved as one array, named uniquely.

A polygon's points are its vertices, in each of its states (``vertices``, and ``vertices_max``
for a point-attached one). A component's are its written points (``points``, or a skeleton's
``skeleton`` and ``body``) other than masters, which sit where their control point is.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

#: The document's list of each kind of item.
LISTS = {"polygon": "polygons", "component": "components"}
#: Where a component writes its points.
PARTS = ("points", "skeleton", "body")


def finite(x: float) -> float:
    value = float(x)
    if not np.isfinite(value):
        raise ValueError(f"expected a finite number, got {x}")
    return value


def item(doc: dict, kind: str, index: int) -> dict:
    """Item ``index`` of ``kind`` (``polygon`` or ``component``)."""
    if kind not in LISTS:
        raise ValueError(f"an item is a polygon or a component, got {kind!r}")
    items = doc.get(LISTS[kind], [])
    if not 0 <= index < len(items):
        raise IndexError(f"the face has no {kind} {index} (it has {len(items)})")
    return items[index]


def unique_name(doc: dict, kind: str, name: str) -> str:
    """``name``, or ``name 2``, ``name 3``... where the face has an item of ``kind`` so named."""
    names = {spec.get("name") for spec in doc.get(LISTS[kind], [])}
    return name if name not in names else next(f"{name} {k}" for k in range(2, 10_000) if f"{name} {k}" not in names)


def states(spec: dict) -> list[str]:
    """A polygon's vertex lists."""
    return ["vertices", "vertices_max"] if "vertices_max" in spec else ["vertices"]


def vertices(spec: dict, state: str) -> list:
    if state not in states(spec):
        raise ValueError(f"the polygon has no {state}")
    return spec[state]


def vertex(points: list, index: int) -> list:
    if not 0 <= index < len(points):
        raise IndexError(f"no point {index} (it has {len(points)})")
    return points[index]


def component_part(spec: dict, part: str) -> list:
    if spec["kind"] == "composite":
        raise ValueError("a composite's points are its parts': move it as a unit")
    if part not in PARTS or part not in spec:
        raise ValueError(f"a {spec['kind']} has no {part}")
    return spec[part]


def placed(ref: object, xy: np.ndarray) -> object:
    """A component's written point ``ref`` moved to ``xy``, its kind kept (a master cannot move)."""
    at = [float(xy[0]), float(xy[1])]
    if isinstance(ref, str):
        raise ValueError(f"a master point moves with its control point {ref}: drag that instead")
    if isinstance(ref, dict):
        return {**ref, "at": at} if "slave" in ref else {"fixed": at}
    return at


def _xy(ref: object) -> np.ndarray | None:
    """Where a component's written point is (None for a master)."""
    if isinstance(ref, str):
        return None
    if isinstance(ref, dict):
        return np.asarray(ref.get("at", ref.get("fixed")), dtype=float)
    return np.asarray(ref, dtype=float)


def rest_of(doc: dict, ref: object) -> np.ndarray:
    """Where a component's written point rests ``(2,)``: a master at its control point."""
    xy = _xy(ref)
    return np.asarray(doc["points"][ref], dtype=float) if xy is None else xy


def points(spec: dict, kind: str) -> np.ndarray:
    """The item's placed points ``(N, 2)``: a polygon's vertices at rest, a component's points
    that are not masters (a composite has none of its own)."""
    if kind == "polygon":
        return np.asarray(spec["vertices"], dtype=float)
    if spec["kind"] == "composite":
        raise ValueError("a composite has no points of its own: it is placed by its transform")
    found = [xy for part in PARTS for xy in map(_xy, spec.get(part, [])) if xy is not None]
    if not found:
        raise ValueError("the component's points all follow control points: nothing to move")
    return np.array(found)


def transform(spec: dict, kind: str, how: Callable[[np.ndarray], np.ndarray]) -> None:
    """Every placed point of the item through ``how`` (``(N, 2) -> (N, 2)``); a composite moves
    by its ``transform``'s translation (``how`` of the origin)."""
    if kind == "polygon":
        for state in states(spec):
            spec[state] = [[float(x), float(y)] for x, y in how(np.asarray(spec[state], dtype=float))]
    elif spec["kind"] == "composite":
        shift = how(np.zeros((1, 2)))[0]
        transform_ = spec.setdefault("transform", {"scale": [1.0, 1.0], "translate": [0.0, 0.0]})
        transform_["translate"] = [transform_["translate"][0] + float(shift[0]),
                                   transform_["translate"][1] + float(shift[1])]
    else:
        for part in PARTS:
            if part in spec:
                spec[part] = [ref if (xy := _xy(ref)) is None else placed(ref, how(xy[None])[0]) for ref in spec[part]]
