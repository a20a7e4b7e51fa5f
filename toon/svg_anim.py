"""A whole track as one animated SVG that a browser plays with no script (SMIL ``<animate>``).

The document is :func:`toon.svg.geometry_svg`'s drawing (the same items, masks and clip paths)
with each outline's ``points`` or ``d`` and each item's ``visibility`` animated over the track.
It stays small because only what moves is keyed, and only where it must be: an outline's
frames are reduced to the fewest keyframes whose straight-line interpolation stays within
``tolerance`` (face units) of every frame, the other frames left to the browser's interpolation;
an outline whose vertex count or stroke runs change, or that comes and goes, steps from key to
key (``calcMode="discrete"``), keyed only where it changes. An image component's picture is
defined once and placed by four nested transforms (translate, rotate, skewX, scale: any affine
map, SMIL having no animated matrix), keyed where its corners need it as an outline is.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from common import atomic_path
from toon.geometry import DrawItem, Geometry
from toon.images import pixel_affine
from toon.svg import _coords, _fmt, _opacity, _paint, _stroke_paths

#: Coordinates are written to this many decimals (face units: a face is some 500 across).
DECIMALS = 1


@dataclass
class _Timeline:
    """One animated attribute of one element: per frame, its value as an array (for
    interpolation) and as text, or None where the element is absent."""

    arrays: list[np.ndarray | None] = field(default_factory=list)
    texts: list[str | None] = field(default_factory=list)


def _num(x: float) -> str:
    return _fmt(x, DECIMALS)


def _time(x: float) -> str:
    """A time or a key time, to the microsecond (coordinates' rounding would move keys by frames)."""
    text = f"{x:.6f}".rstrip("0").rstrip(".")
    return text or "0"


def _points(points: np.ndarray) -> str:
    return _coords(points, DECIMALS)


def _paths_rounded(item: DrawItem) -> list[str]:
    return _stroke_paths(item.with_vertices(np.round(item.vertices, DECIMALS)))


def linear_keys(frames: np.ndarray, tolerance: float) -> list[int]:
    """The fewest frames (indices, first and last included) of ``frames`` ``(F, ...)`` whose
    straight-line interpolation is within ``tolerance`` of every frame (greedy, each segment as
    long as it can be)."""
    count = len(frames)
    keys = [0]
    start = 0
    while start < count - 1:
        end = start + 1
        while end + 1 < count:
            span = np.linspace(0.0, 1.0, end + 2 - start)[:, None, None]
            guess = frames[start][None] + (frames[end + 1] - frames[start])[None] * span
            if np.abs(guess - frames[start:end + 2]).max() > tolerance:
                break
            end += 1
        keys.append(end)
        start = end
    return keys


def _animate(attribute: str, line: _Timeline, dur: float, tolerance: float) -> str:
    """The ``<animate>`` of one attribute, or ``""`` where it never changes."""
    frames = len(line.texts)
    present = [t is not None for t in line.texts]
    shapes = {a.shape for a in line.arrays if a is not None}
    if all(present) and len(shapes) == 1:
        stack = np.stack([a for a in line.arrays if a is not None])
        if np.abs(stack - stack[0]).max() <= tolerance:
            return ""
        keys, mode = linear_keys(stack, tolerance), "linear"
    else:  # steps: keyed where the text changes
        keys = [k for k in range(frames) if k == 0 or line.texts[k] != line.texts[k - 1]]
        mode = "discrete"
        if len(keys) == 1:
            return ""
    last = max(frames - 1, 1)
    shown = line.texts[_first(present)] or ""  # an absent element keeps a shape (its visibility hides it)
    values = ";".join(line.texts[k] or shown for k in keys)
    times = ";".join(_time(k / last) if k < last else "1" for k in keys)
    return (f'<animate attributeName="{attribute}" dur="{_time(dur)}s" repeatCount="indefinite" calcMode="{mode}" '
            f'keyTimes="{times}" values="{values}"/>')


def _visibility(present: list[bool], dur: float) -> str:
    if all(present):
        return ""
    keys = [k for k in range(len(present)) if k == 0 or present[k] != present[k - 1]]
    last = max(len(present) - 1, 1)
    values = ";".join("visible" if present[k] else "hidden" for k in keys)
    times = ";".join(_time(k / last) for k in keys)
    return (f'<animate attributeName="visibility" dur="{_time(dur)}s" repeatCount="indefinite" calcMode="discrete" '
            f'keyTimes="{times}" values="{values}"/>')


def track_svg(frames: Sequence[Geometry], rate: float, size: tuple[int, int] = (512, 512),
              tolerance: float | None = None) -> str:
    """An animated SVG document of ``frames`` (geometries at ``rate`` frames a second), looping.

    Parameters
    ----------
    frames : sequence of Geometry
        Each frame's geometry (:meth:`toon.FaceRig.geometry`), at least one.
    rate : float
        Frames per second.
    size : (width, height)
        The drawing's size in pixels; the viewbox is fitted centred, aspect kept.
    tolerance : float, optional
        How far (face units) an interpolated outline may stray from a frame; by default a
        five-hundredth of the viewbox's larger side (a pixel drawn 500 pixels wide).
    """
    first = frames[0]
    xmin, ymin, xmax, ymax = first.viewbox
    w, h = xmax - xmin, ymax - ymin
    tolerance = max(w, h) / 500 if tolerance is None else tolerance
    dur = max(len(frames) - 1, 1) / rate
    items: dict[int, DrawItem] = {}
    for geometry in frames:
        for item in geometry.items:
            items.setdefault(item.key, item)
    order = sorted(items)
    fills = {key: _Timeline() for key in order}
    strokes = {key: _Timeline() for key in order}
    present: dict[int, list[bool]] = {key: [] for key in order}
    for geometry in frames:
        here = {item.key: item for item in geometry.items}
        for key in order:
            drawn = here.get(key)
            present[key].append(drawn is not None)
            fills[key].arrays.append(None if drawn is None else np.round(drawn.vertices, DECIMALS))
            fills[key].texts.append(None if drawn is None else _points(drawn.vertices))
            paths = None if drawn is None or drawn.stroke is None else _paths_rounded(drawn)
            strokes[key].texts.append(None if paths is None else " ".join(paths))
            whole = drawn is not None and paths is not None and (drawn.edge_visible is None
                                                                 or bool(drawn.edge_visible.all()))
            strokes[key].arrays.append(np.round(drawn.vertices, DECIMALS) if whole and drawn is not None else None)
    big = f'x="{_num(xmin - 10 * w)}" y="{_num(-ymax - 10 * h)}" width="{_num(21 * w)}" height="{_num(21 * h)}"'
    holes = [key for key in order if items[key].mask_write]
    defs = [f'<polygon id="h{k}" points="{fills[k].texts[_first(present[k])]}">'  # each hole once, used thrice
            f'{_animate("points", fills[k], dur, tolerance)}{_visibility(present[k], dur)}</polygon>' for k in holes]
    if holes:
        black = "".join(f'<use href="#h{k}" fill="black" fill-rule="evenodd"/>' for k in holes)
        defs.append(f'<mask id="no-holes" maskUnits="userSpaceOnUse" {big}><rect {big} fill="white"/>{black}</mask>')
        for group in sorted({items[k].mask_write for k in holes}):
            uses = "".join(f'<use href="#h{k}" clip-rule="evenodd"/>' for k in holes if items[k].mask_write == group)
            defs.append(f'<clipPath id="group-{group}">{uses}</clipPath>')
    body = [f'<rect {big} fill="{_paint(first.background)}"{_opacity("fill-opacity", first.background)}/>']
    groups_with_holes = {items[k].mask_write for k in holes}
    pictures: dict[str, int] = {}  # a picture's data -> its number
    for key in order:
        picture = items[key].picture
        if picture is not None and picture.href not in pictures:
            pictures[picture.href] = len(pictures)
            defs.append(f'<image id="picture-{pictures[picture.href]}" width="{picture.size[0]}" '
                        f'height="{picture.size[1]}" preserveAspectRatio="none" href="{picture.href}"/>')
    for key in order:
        item = items[key]
        if item.mask_test == 0:
            wrap = ' mask="url(#no-holes)"' if holes else ""
        elif item.mask_test is not None:
            if item.mask_test not in groups_with_holes:
                continue
            wrap = f' clip-path="url(#group-{item.mask_test})"'
        else:
            wrap = ""
        shown = _first(present[key])
        stroked = item.stroke is not None and item.width > 0
        stroke = (f' stroke="{_paint(item.stroke)}"{_opacity("stroke-opacity", item.stroke)} '
                  f'stroke-width="{_num(item.width)}" stroke-linejoin="miter" stroke-miterlimit="4" '
                  'stroke-linecap="butt"') if stroked else ""
        # a closed outline stroked whole at every frame: its polygon carries both fill and stroke
        whole = stroked and item.closed and all(t is None or a is not None for t, a in
                                                zip(strokes[key].texts, strokes[key].arrays, strict=True))
        parts = []
        if item.picture is not None:
            parts.append(_placed(fills[key], pictures[item.picture.href], item.picture.size, dur, tolerance,
                                 item.opacity))
        if item.fill is not None and item.closed:
            paint = f' fill="{_paint(item.fill)}"{_opacity("fill-opacity", item.fill)} fill-rule="evenodd"'
            paint += stroke if whole else ""
            if item.mask_write:
                parts.append(f'<use href="#h{key}"{paint}/>')
            else:
                parts.append(f'<polygon points="{fills[key].texts[shown]}"{paint}>'
                             f'{_animate("points", fills[key], dur, tolerance)}</polygon>')
        elif whole:
            parts.append(f'<polygon points="{fills[key].texts[shown]}" fill="none"{stroke}>'
                         f'{_animate("points", fills[key], dur, tolerance)}</polygon>')
        if stroked and not whole:
            parts.append(f'<path d="{strokes[key].texts[shown] or "M0,0"}" fill="none"{stroke}>'
                         f'{_animate("d", strokes[key], dur, tolerance)}</path>')
        if parts:
            name = f" data-name={quoteattr(item.name)}" if item.name else ""
            body.append(f'<g class="{item.kind}"{name}{wrap}>{_visibility(present[key], dur)}' + "".join(parts)
                        + "</g>")
    view = f"{_num(xmin)} {_num(-ymax)} {_num(w)} {_num(h)}"
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]}" height="{size[1]}" viewBox="{view}" '
            'preserveAspectRatio="xMidYMid meet">\n'
            + (f"<defs>{''.join(defs)}</defs>\n" if defs else "")
            + "\n".join(body) + "\n</svg>\n")


def _placed(corners: _Timeline, number: int, size: tuple[int, int], dur: float, tolerance: float,
            opacity: float) -> str:
    """Picture ``number`` placed on its corners at every frame: ``translate rotate skewX scale``
    (:func:`affine_parts`), each animated where it changes, keyed where the corners need it."""
    shown = next(a for a in corners.arrays if a is not None)
    quads = np.stack([shown if a is None else a for a in corners.arrays])
    keys = linear_keys(quads, tolerance) if len(quads) > 1 else [0]
    parts = affine_parts(np.array([pixel_affine(quads[k] * [1.0, -1.0], size) for k in keys]))
    last = max(len(quads) - 1, 1)
    times = ";".join(_time(k / last) if k < last else "1" for k in keys)
    nested = ""
    for kind, values in zip(("translate", "rotate", "skewX", "scale"), parts, strict=True):
        texts = [" ".join(_fmt(v, 4) for v in np.atleast_1d(row)) for row in values]
        animate = "" if len(set(texts)) == 1 else (
            f'<animateTransform attributeName="transform" type="{kind}" dur="{_time(dur)}s" repeatCount="indefinite" '
            f'calcMode="linear" keyTimes="{times}" values="{";".join(texts)}"/>')
        nested += f'<g transform="{kind}({texts[0]})">{animate}'
    fade = f' opacity="{_fmt(opacity)}"' if opacity < 1.0 else ""
    return nested + f'<use href="#picture-{number}"{fade}/>' + "</g>" * 4


def affine_parts(matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Affine maps ``(K, 2, 3)`` (``[[a, c, e], [b, d, f]]``) as SVG's ``translate(e f)
    rotate(θ) skewX(φ) scale(sx sy)``: translations ``(K, 2)``, rotations and skews in degrees
    ``(K,)`` (the rotation unwrapped, so that it turns the short way between keys) and scales
    ``(K, 2)`` (``sy`` negative for a mirrored picture)."""
    a, c, e = matrices[:, 0].T
    b, d, f = matrices[:, 1].T
    sx = np.hypot(a, b)
    theta = np.unwrap(np.arctan2(b, a))
    safe = np.where(sx > 1e-12, sx, 1.0)
    sy = (a * d - b * c) / safe
    shear = (a * c + b * d) / safe
    phi = np.degrees(np.arctan2(shear, np.where(np.abs(sy) > 1e-12, sy, 1e-12)))
    phi = np.where(phi > 90, phi - 180, np.where(phi < -90, phi + 180, phi))  # tan repeats every 180
    return np.column_stack([e, f]), np.degrees(theta), phi, np.column_stack([sx, sy])


def _first(present: list[bool]) -> int:
    return next((k for k, here in enumerate(present) if here), 0)


def save_track_svg(frames: Sequence[Geometry], rate: float, path: str | os.PathLike,
                   size: tuple[int, int] = (512, 512), tolerance: float | None = None) -> Path:
    """Write :func:`track_svg` to ``path``, atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(track_svg(frames, rate, size, tolerance), encoding="utf-8")
    return path
