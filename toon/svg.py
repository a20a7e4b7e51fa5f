"""SVG export of one frame, from :class:`toon.Geometry` alone (no GL), for inspection and print.

The SVG draws exactly what the renderer draws, in the same order: the face polygon through a
mask that removes every hole, pupils and clipped components through a clip path made of their
group's holes, fills with the even-odd rule, strokes with miter joins (SVG's default limit of 4)
and butt ends, and invisible segments left out of the stroke paths. An image component's picture
is defined once, on a line of its own (a PNG data URI), and placed by a ``<use>`` whose matrix
takes it onto its corners: a frame that moves it changes only that line.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from common import atomic_path
from toon.curves import visible_runs
from toon.geometry import DrawItem, Geometry
from toon.images import pixel_affine
from toon.validate import Color


def _fmt(x: float, decimals: int = 3) -> str:
    text = f"{x:.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _coords(points: np.ndarray, decimals: int = 3) -> str:
    # y up in face units, down in SVG
    return " ".join(f"{_fmt(x, decimals)},{_fmt(-y, decimals)}" for x, y in points)


def _paint(color: Color | None) -> str:
    if color is None:
        return "none"
    return "#" + "".join(f"{round(c * 255):02x}" for c in color[:3])


def _opacity(attr: str, color: Color | None) -> str:
    return f' {attr}="{_fmt(color[3])}"' if color is not None and color[3] < 1.0 else ""


def _stroke_paths(item: DrawItem, decimals: int = 3) -> list[str]:
    pts = item.vertices
    n = len(pts)
    edges = n if item.closed else n - 1
    visible = item.edge_visible if item.edge_visible is not None else np.ones(edges, dtype=bool)
    paths = []
    for first, last in visible_runs(visible, item.closed):
        if item.closed and visible.all():
            paths.append(f"M{_coords(pts, decimals)}Z")
            continue
        idx = np.arange(first, first + ((last - first) % n if item.closed else last - first) + 1) % n
        paths.append(f"M{_coords(pts[idx], decimals)}")
    return paths


def geometry_svg(geometry: Geometry, size: tuple[int, int] = (512, 512), decimals: int = 3) -> str:
    """The frame as an SVG document (a string): the opening tag, the definitions (where there are
    any), the background and each drawn item on lines of their own, so that two frames differ
    only in the lines of what moved (the room's browser viewers are sent just those).

    Parameters
    ----------
    geometry : Geometry
        One frame, as from :meth:`toon.FaceRig.geometry`.
    size : (width, height)
        The drawing's size in pixels; the viewbox is fitted centred, aspect kept, as on screen.
    decimals : int
        Coordinates' decimals (face units: a face is some 500 across, so 1 is a fifth of a pixel
        of a 512-pixel drawing).
    """
    xmin, ymin, xmax, ymax = geometry.viewbox
    w, h = xmax - xmin, ymax - ymin
    view = f"{_fmt(xmin)} {_fmt(-ymax)} {_fmt(w)} {_fmt(h)}"
    holes: dict[int, list[str]] = {}
    for item in geometry.items:
        if item.mask_write:
            holes.setdefault(item.mask_write, []).append(f'<polygon points="{_coords(item.vertices, decimals)}"/>')
    big = f'x="{_fmt(xmin - 10 * w)}" y="{_fmt(-ymax - 10 * h)}" width="{_fmt(21 * w)}" height="{_fmt(21 * h)}"'
    pictures: dict[str, int] = {}  # a picture's data -> its number: the same picture twice is defined once
    shown = []
    for item in geometry.items:
        if item.picture is not None and item.picture.href not in pictures:
            pictures[item.picture.href] = len(pictures)
            pw, ph = item.picture.size
            shown.append(f'<image id="picture-{pictures[item.picture.href]}" width="{pw}" height="{ph}" '
                         f'preserveAspectRatio="none" href="{item.picture.href}"/>')
    defs = []
    if holes:
        black = "".join(p.replace("<polygon ", '<polygon fill="black" fill-rule="evenodd" ') for ps in holes.values()
                        for p in ps)
        defs.append(f'<mask id="no-holes" maskUnits="userSpaceOnUse" {big}><rect {big} fill="white"/>{black}</mask>')
        for group, polys in holes.items():
            defs.append(f'<clipPath id="group-{group}">'
                        + "".join(p.replace("<polygon ", '<polygon clip-rule="evenodd" ') for p in polys)
                        + "</clipPath>")
    body = [f'<rect {big} fill="{_paint(geometry.background)}"{_opacity("fill-opacity", geometry.background)}/>']
    for item in geometry.items:
        name = f" data-name={quoteattr(item.name)}" if item.name else ""
        if item.mask_test == 0:
            wrap = ' mask="url(#no-holes)"' if holes else ""
        elif item.mask_test is not None:
            if item.mask_test not in holes:  # clipped to a group with no holes: nothing shows
                continue
            wrap = f' clip-path="url(#group-{item.mask_test})"'
        else:
            wrap = ""
        parts = []
        if item.fill is not None and item.closed:
            parts.append(f'<polygon points="{_coords(item.vertices, decimals)}" fill="{_paint(item.fill)}"'
                         f'{_opacity("fill-opacity", item.fill)} fill-rule="evenodd"/>')
        if item.stroke is not None and item.width > 0:
            for d in _stroke_paths(item, decimals):
                parts.append(f'<path d="{d}" fill="none" stroke="{_paint(item.stroke)}"'
                             f'{_opacity("stroke-opacity", item.stroke)} stroke-width="{_fmt(item.width)}" '
                             'stroke-linejoin="miter" stroke-miterlimit="4" stroke-linecap="butt"/>')
        if item.picture is not None and len(item.vertices) == 4:
            parts.append(_placed(item, pictures[item.picture.href], decimals))
        if parts:
            body.append(f'<g class="{item.kind}"{name}{wrap}>' + "".join(parts) + "</g>")
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{size[0]}" height="{size[1]}" viewBox="{view}" '
            'preserveAspectRatio="xMidYMid meet">\n'
            + (f"<defs>{''.join(shown)}</defs>\n" if shown else "")
            + (f"<defs>{''.join(defs)}</defs>\n" if defs else "")
            + "\n".join(body) + "\n</svg>\n")


def _placed(item: DrawItem, number: int, decimals: int) -> str:
    """A ``<use>`` of picture ``number`` taken onto the item's corners (SVG's y runs down)."""
    assert item.picture is not None
    a, c, e, b, d, f = pixel_affine(item.vertices * [1.0, -1.0], item.picture.size).ravel()
    matrix = " ".join(_fmt(x, decimals + 3) for x in (a, b, c, d, e, f))
    fade = f' opacity="{_fmt(item.opacity)}"' if item.opacity < 1.0 else ""
    return f'<use href="#picture-{number}" transform="matrix({matrix})"{fade}/>'


def save_svg(geometry: Geometry, path: str | os.PathLike, size: tuple[int, int] = (512, 512)) -> Path:
    """Write one frame as an SVG file, atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(geometry_svg(geometry, size), encoding="utf-8")
    return path
