"""A whole track as a Lottie animation (Bodymovin JSON, schema 5.x): for Lottie players on the
web and on phones, and After Effects plug-ins.

Written here (the popular Python Lottie library is AGPL). Each drawn item is a shape layer, in
the renderer's order (Lottie draws its first layer on top, so the list is reversed): its outline
a path keyframed over the track, its fill (even-odd) and its stroke (miter joins, butt ends;
a stroke with hidden edges as open paths of its visible runs). What the renderer does with its
mask groups, Lottie does with layer masks: the face and what is drawn outside the holes
subtract every hole, a pupil or a clipped component adds its group's holes. Outlines are keyed
as in :mod:`toon.svg_anim` (the fewest frames whose straight-line interpolation stays within the
tolerance; an outline whose vertex count changes holds from key to key), and an item that comes
and goes fades its layer's opacity in steps. Coordinates are the renderer's pixels at ``size``
(the viewbox fitted centred, aspect kept), so a player shows what ``render`` draws. An image
component is an image layer of its picture (an embedded asset), its transform's position,
rotation, skew and scale keyed where its corners need it (:func:`toon.svg_anim.affine_parts`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from common import atomic_path
from toon.curves import visible_runs
from toon.geometry import DrawItem, Geometry
from toon.images import pixel_affine
from toon.raster import fit_viewbox
from toon.svg_anim import affine_parts, linear_keys

LOTTIE_VERSION = "5.7.4"
_STATIC_TRANSFORM = {"o": {"a": 0, "k": 100}, "r": {"a": 0, "k": 0}, "p": {"a": 0, "k": [0, 0, 0]},
                     "a": {"a": 0, "k": [0, 0, 0]}, "s": {"a": 0, "k": [100, 100, 100]}}
_LINEAR = {"i": {"x": [1], "y": [1]}, "o": {"x": [0], "y": [0]}}


def _shape(points: np.ndarray, closed: bool) -> dict[str, Any]:
    zeros = [[0, 0]] * len(points)
    return {"c": closed, "v": np.round(points, 1).tolist(), "i": zeros, "o": zeros}


def _keyed(frames: list[np.ndarray | None], closed: bool, tolerance: float) -> dict[str, Any]:
    """A path's ``ks``: still, keyframed linearly, or held from key to key (its size changes)."""
    shown = next(f for f in frames if f is not None)
    filled = [shown if f is None else f for f in frames]
    if len({f.shape for f in filled}) == 1:
        stack = np.stack(filled)
        if np.abs(stack - stack[0]).max() <= tolerance:
            return {"a": 0, "k": _shape(stack[0], closed)}
        keys = linear_keys(stack, tolerance)
        return {"a": 1, "k": [{"t": k, "s": [_shape(stack[k], closed)], **_LINEAR} for k in keys]}
    keys = [k for k in range(len(filled)) if k == 0 or filled[k].shape != filled[k - 1].shape
            or np.abs(filled[k] - filled[k - 1]).max() > tolerance]
    return {"a": 1, "k": [{"t": k, "s": [_shape(filled[k], closed)], "h": 1} for k in keys]}


def _colour(color: tuple[float, float, float, float]) -> dict[str, Any]:
    return {"a": 0, "k": [round(c, 4) for c in color[:3]] + [1]}


def _opacity(present: list[bool], full: float = 100) -> dict[str, Any]:
    if all(present):
        return {"a": 0, "k": full}
    keys = [k for k in range(len(present)) if k == 0 or present[k] != present[k - 1]]
    return {"a": 1, "k": [{"t": k, "s": [full if present[k] else 0], "h": 1} for k in keys]}


def track_lottie(frames: Sequence[Geometry], rate: float, size: tuple[int, int] = (512, 512),
                 tolerance: float = 1.0, name: str = "toonface") -> dict[str, Any]:
    """The Lottie document (a dict, JSON-ready) of ``frames`` at ``rate`` frames a second.

    Parameters
    ----------
    frames : sequence of Geometry
        Each frame's geometry (:meth:`toon.FaceRig.geometry`), at least one.
    rate : float
    size : (width, height)
        The animation's size in pixels.
    tolerance : float
        How far (pixels) an interpolated outline may stray from a frame.
    name : str
    """
    first = frames[0]
    scale, ox, oy = fit_viewbox(first.viewbox, size)
    x0, y0 = ox - first.viewbox[0] * scale, oy + first.viewbox[3] * scale

    def place(vertices: np.ndarray) -> np.ndarray:
        return np.column_stack([x0 + vertices[:, 0] * scale, y0 - vertices[:, 1] * scale])

    items: dict[int, DrawItem] = {}
    for geometry in frames:
        for item in geometry.items:
            items.setdefault(item.key, item)
    order = sorted(items)
    outlines: dict[int, list[np.ndarray | None]] = {key: [] for key in order}
    for geometry in frames:
        here = {item.key: item for item in geometry.items}
        for key in order:
            drawn = here.get(key)
            outlines[key].append(None if drawn is None else place(drawn.vertices))
    present = {key: [f is not None for f in outlines[key]] for key in order}
    holes = {key: items[key].mask_write for key in order if items[key].mask_write}
    hole_paths = {key: _keyed(outlines[key], True, tolerance) for key in holes}
    layers = []
    assets: dict[str, dict[str, Any]] = {}  # a picture's data -> its asset
    for index, key in enumerate(order):
        item = items[key]
        shapes = _item_shapes(item, outlines[key], present[key], tolerance, scale)
        if not shapes and item.picture is None:
            continue
        masks = []
        if item.mask_test == 0:
            masks = [{"inv": False, "mode": "s", "pt": hole_paths[h], "o": {"a": 0, "k": 100}, "x": {"a": 0, "k": 0},
                      "nm": items[h].name or f"hole {h}"} for h in holes]
        elif item.mask_test is not None:
            group = [h for h, g in holes.items() if g == item.mask_test]
            if not group:
                continue  # clipped to a group with no holes: nothing shows
            masks = [{"inv": False, "mode": "a", "pt": hole_paths[h], "o": {"a": 0, "k": 100}, "x": {"a": 0, "k": 0},
                      "nm": items[h].name or f"hole {h}"} for h in group]
        layer = {"ddd": 0, "ind": index + 1, "ty": 4, "nm": item.name or f"{item.kind} {key}", "sr": 1,
                 "ks": {**_STATIC_TRANSFORM, "o": _opacity(present[key])}, "ao": 0, "shapes": shapes,
                 "ip": 0, "op": len(frames), "st": 0, "bm": 0}
        if item.picture is not None:
            picture = item.picture
            asset = assets.setdefault(picture.href, {"id": f"picture_{len(assets)}", "w": picture.size[0],
                                                     "h": picture.size[1], "u": "", "p": picture.href, "e": 1})
            del layer["shapes"]
            layer.update(ty=2, refId=asset["id"], ks={**_placed(outlines[key], picture.size, tolerance),
                                                       "o": _opacity(present[key], 100 * item.opacity)})
        if masks:
            layer.update(hasMask=True, masksProperties=masks)
        layers.append(layer)
    if first.background[3] > 0:  # drawn first, so last in Lottie's list
        layers.insert(0, _background(first.background, size, len(order) + 1, len(frames)))
    return {"v": LOTTIE_VERSION, "fr": rate, "ip": 0, "op": len(frames), "w": size[0], "h": size[1], "nm": name,
            "ddd": 0, "assets": list(assets.values()), "layers": list(reversed(layers))}


def _placed(corners: list[np.ndarray | None], size: tuple[int, int], tolerance: float) -> dict[str, Any]:
    """An image layer's transform onto its corners (pixels) at every frame: Lottie applies the
    scale, then the skew (along x: its ``sk`` is SVG's skewX negated), the rotation (clockwise on
    screen, as SVG's) and the position, as :func:`toon.svg_anim.affine_parts` takes a map apart."""
    shown = next(c for c in corners if c is not None)
    quads = np.stack([shown if c is None else c for c in corners])
    keys = linear_keys(quads, tolerance) if len(quads) > 1 else [0]
    moved, turned, skewed, scaled = affine_parts(np.array([pixel_affine(quads[k], size) for k in keys]))
    values: dict[str, list] = {"p": [[float(x), float(y), 0.0] for x, y in moved], "r": [float(r) for r in turned],
              "sk": [-float(s) for s in skewed], "s": [[100 * float(x), 100 * float(y), 100.0] for x, y in scaled]}

    def keyed(series: list) -> dict[str, Any]:
        if all(v == series[0] for v in series):
            return {"a": 0, "k": series[0]}
        return {"a": 1, "k": [{"t": k, "s": v if isinstance(v, list) else [v], **_LINEAR}
                              for k, v in zip(keys, series, strict=True)]}
    return {"a": {"a": 0, "k": [0, 0, 0]}, **{name: keyed(series) for name, series in values.items()},
            "sa": {"a": 0, "k": 0}}


def _background(color: tuple[float, float, float, float], size: tuple[int, int], index: int,
                frames: int) -> dict[str, Any]:
    """The background: a rectangle over the whole picture."""
    rect = {"ty": "rc", "d": 1, "s": {"a": 0, "k": list(size)}, "p": {"a": 0, "k": [size[0] / 2, size[1] / 2]},
            "r": {"a": 0, "k": 0}}
    fill = {"ty": "fl", "c": _colour(color), "o": {"a": 0, "k": color[3] * 100}, "r": 1}
    return {"ddd": 0, "ind": index, "ty": 4, "nm": "background", "sr": 1, "ks": _STATIC_TRANSFORM, "ao": 0, "ip": 0,
            "op": frames, "st": 0, "bm": 0,
            "shapes": [{"ty": "gr", "nm": "background", "it": [rect, fill, {"ty": "tr", **_STATIC_TRANSFORM}]}]}


def _item_shapes(item: DrawItem, outline: list[np.ndarray | None], present: list[bool], tolerance: float,
                 scale: float) -> list[dict[str, Any]]:
    """An item's shape groups: its stroke's (on top) and its fill's."""
    groups = []
    stroked = item.stroke is not None and item.width > 0
    whole = item.edge_visible is None or bool(np.asarray(item.edge_visible).all())
    stroke = {"ty": "st", "c": _colour(item.stroke), "o": {"a": 0, "k": item.stroke[3] * 100},
              "w": {"a": 0, "k": item.width * scale}, "lc": 1, "lj": 1, "ml": 4} if item.stroke is not None else None
    if stroked and stroke is not None:
        if whole:
            paths = [{"ty": "sh", "ks": _keyed(outline, item.closed, tolerance)}]
        else:  # the visible runs of the first frame it shows in, as open paths
            shown = next(f for f in outline if f is not None)
            count = len(shown)
            paths = []
            for start, stop in visible_runs(np.asarray(item.edge_visible), item.closed):
                span = (stop - start) % count if item.closed else stop - start
                rows = np.arange(start, start + span + 1) % count
                paths.append({"ty": "sh", "ks": _keyed([None if f is None else f[rows] for f in outline], False,
                                                       tolerance)})
        groups.append({"ty": "gr", "nm": "stroke", "it": [*paths, stroke, {"ty": "tr", **_STATIC_TRANSFORM}]})
    if item.fill is not None and item.closed:
        groups.append({"ty": "gr", "nm": "fill", "it": [
            {"ty": "sh", "ks": _keyed(outline, True, tolerance)},
            {"ty": "fl", "c": _colour(item.fill), "o": {"a": 0, "k": item.fill[3] * 100}, "r": 2},
            {"ty": "tr", **_STATIC_TRANSFORM}]})
    return groups


def save_lottie(frames: Sequence[Geometry], rate: float, path: str | os.PathLike, size: tuple[int, int] = (512, 512),
                tolerance: float = 1.0) -> Path:
    """Write :func:`track_lottie` to ``path`` as compact JSON, atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(track_lottie(frames, rate, size, tolerance, path.stem), separators=(",", ":")),
                       encoding="utf-8")
    return path
