"""CharToon's components (Face Editor, section 3.2 of the CharToon seed), as face-file entries.

A face's ``components`` list holds, besides ToonFace's polygons:

- ``polyline``, ``polygon`` and ``ellipse``: contour-animated components, defined by points on
  their contour (an ellipse by four: left, top, right, bottom); polygons and ellipses may be
  filled or empty; every kind may have a stroke of a given width.
- ``skeleton``: a skeleton (polyline, or polygon with ``skeleton_closed``) that holds the control
  points, and a body (polyline or polygon) of fixed and frozen points that follows it:
  ``coupling = "point"`` keeps each fixed body point's vector from its nearest skeleton point;
  ``coupling = "edge"`` keeps, for its nearest skeleton edge, the ratio at which it projects on
  the edge and its distance from it.
- ``image``: a PNG picture (CharToon's scanned backgrounds and hand-painted parts) stretched over
  the parallelogram of its three ``points`` (top-left, top-right, bottom-left corner), from
  ``src``: a ``.png`` file beside the face, or a ``data:image/png;base64,...`` URI in the face
  file itself (:mod:`toon.images`); no fill or stroke.
- ``composite``: a group of components, inline (``components``) or re-used from a library file
  (``use`` and ``library``), placed with a ``transform`` (``scale`` ``[sx, sy]``, negative to flip,
  then ``translate``) and with its control points, holes and clips renamed by ``controls``
  (``{"M": "BRM", "E": "eye_right"}``).

Points are written as: ``"BRC"``, a **master** control point (its position comes from the motors);
``{"slave": "BRC", "at": [x, y]}``, a **slave** that moves as its master does (or
``{"slave": {"ML": 0.25, "MB": 0.75}, "at": [x, y]}``, as a blend of several move: each master's
motion times its weight, the weights summing to 1, so a point between two control points bends
smoothly with both); ``[x, y]``, a
**frozen** point that never moves; ``{"fixed": [x, y]}``, a **fixed** point that moves only when a
skeleton drives it (a fixed skeleton point is a joint that stays put).

Further fields: ``layer`` (-10..-1 background, drawn before the face and never animated; 1..10
foreground, drawn after it; default 1), ``smooth`` (``true`` or inclusive point ranges
``[[i, j], ...]``: spline interpolation instead of straight lines), ``hidden`` (indices of
invisible segments, segment ``i`` from point ``i`` to ``i + 1``), ``clip`` (draw only inside an
eye's or the mouth's holes), ``hole`` (the component's fill opens that feature's hole, like a
ToonFace hole polygon, for the pupils and clipped components drawn after it), ``depth``
(head-turn parallax), and the animatable parameters
``visible`` (``{"motor": "MB", "range": [0.3, 1]}``), ``translate``
(``{"motor": "HH", "at0": [dx, dy], "at1": [dx, dy]}``), ``scale``
(``{"motor": "ERU", "at0": [sx, sy], "at1": [sx, sy], "origin": [x, y]}``) and ``rotate``
(``{"motor": "FRINGE", "at0": [-8], "at1": [8], "origin": [x, y]}``: degrees counter-clockwise
about the origin; scaled first, then turned, then moved), each linear in its motor's (or
parameter's) value like A1.5-A1.6.

Parsing and checking live in :mod:`toon.component_parser`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from toon.validate import Color, format_color

if TYPE_CHECKING:
    from toon.images import Picture


@dataclass(frozen=True)
class PointRef:
    """One defining point: ``kind`` is master, slave, fixed or frozen.

    ``master`` names the control point of a master or slave; ``at`` is the rest position of a
    slave, fixed or frozen point (a master's comes from the face). A slave of several masters has
    ``blend``, each ``(control point, weight)`` (weights summing to 1), and ``master`` is its
    heaviest.
    """

    kind: str
    master: str = ""
    at: tuple[float, float] = (0.0, 0.0)
    blend: tuple[tuple[str, float], ...] = ()

    @property
    def animated(self) -> bool:
        """Whether a motor can move this point directly."""
        return self.kind in ("master", "slave")

    def to_json(self) -> Any:
        """The point as written in a face file."""
        if self.kind == "master":
            return self.master
        if self.kind == "slave":
            return {"slave": dict(self.blend) if self.blend else self.master, "at": list(self.at)}
        return {"fixed": list(self.at)} if self.kind == "fixed" else list(self.at)


@dataclass(frozen=True)
class MotorParam:
    """A parameter linear in one motor's value: ``at0 + value * (at1 - at0)``."""

    motor: str
    at0: tuple[float, ...]
    at1: tuple[float, ...]
    origin: tuple[float, float] = (0.0, 0.0)  # scale only


@dataclass(frozen=True)
class Visibility:
    """Shown while ``motor``'s value lies in ``[low, high]``."""

    motor: str
    low: float
    high: float


@dataclass(frozen=True)
class Component:
    """A component as written in a face file; composites keep their children (resolved)."""

    kind: str
    name: str = ""
    layer: int = 1
    points: tuple[PointRef, ...] = ()  # contour, or the skeleton of a skeleton component
    body: tuple[PointRef, ...] = ()
    coupling: str = ""
    closed: bool = False  # of the outline, or of a skeleton's body
    skeleton_closed: bool = False
    fill: Color | None = None
    stroke: Color | None = None
    width: float = 0.0
    smooth: tuple[tuple[int, int], ...] = ()
    hidden: tuple[int, ...] = ()
    clip: str = ""
    hole: str = ""
    depth: float | None = None
    visible: Visibility | None = None
    translate: MotorParam | None = None
    scale: MotorParam | None = None
    rotate: MotorParam | None = None
    children: tuple[Component, ...] = ()
    use: str = ""
    library: str = ""
    controls: tuple[tuple[str, str], ...] = ()
    transform: tuple[float, float, float, float] = (1.0, 1.0, 0.0, 0.0)  # sx, sy, tx, ty
    src: str = ""  # an image's picture, as written: a PNG beside the face, or a PNG data URI
    picture: Picture | None = field(default=None, compare=False, repr=False)  # an image's, read

    @property
    def animated(self) -> bool:
        """Whether anything about this component changes with the motors."""
        if self.kind == "composite":
            return any(c.animated for c in self.children)
        return (any(p.animated for p in self.points) or self.visible is not None
                or self.translate is not None or self.scale is not None or self.rotate is not None)

    def to_dict(self) -> dict[str, Any]:
        """The component as written in a face file."""
        d: dict[str, Any] = {"kind": self.kind}
        if self.name:
            d["name"] = self.name
        if self.kind == "composite":
            if self.use:
                d["use"], d["library"] = self.use, self.library
            else:
                d["components"] = [c.to_dict() for c in self.children]
            if self.controls:
                d["controls"] = dict(self.controls)
            if self.transform != (1.0, 1.0, 0.0, 0.0):
                d["transform"] = {"scale": list(self.transform[:2]), "translate": list(self.transform[2:])}
            return d
        if self.layer != 1:
            d["layer"] = self.layer
        if self.kind == "skeleton":
            d["coupling"] = self.coupling
            d["skeleton"] = [p.to_json() for p in self.points]
            d["body"] = [p.to_json() for p in self.body]
            d["skeleton_closed"] = self.skeleton_closed
        else:
            d["points"] = [p.to_json() for p in self.points]
        if self.kind == "image":
            d["src"] = self.src
        if self.kind in ("polyline", "skeleton"):
            d["closed"] = self.closed
        for key in ("fill", "stroke"):
            if getattr(self, key) is not None:
                d[key] = format_color(getattr(self, key))
        if self.width:
            d["width"] = self.width
        if self.smooth:
            d["smooth"] = [list(r) for r in self.smooth]
        if self.hidden:
            d["hidden"] = list(self.hidden)
        if self.clip:
            d["clip"] = self.clip
        if self.hole:
            d["hole"] = self.hole
        if self.depth is not None:
            d["depth"] = self.depth
        if self.visible:
            d["visible"] = {"motor": self.visible.motor, "range": [self.visible.low, self.visible.high]}
        if self.translate:
            d["translate"] = {"motor": self.translate.motor, "at0": list(self.translate.at0),
                              "at1": list(self.translate.at1)}
        for key in ("scale", "rotate"):
            param = getattr(self, key)
            if param:
                d[key] = {"motor": param.motor, "at0": list(param.at0), "at1": list(param.at1),
                          "origin": list(param.origin)}
        return d


def flatten(components: tuple[Component, ...],
            transform: tuple[float, float, float, float] = (1.0, 1.0, 0.0, 0.0)) -> list[Component]:
    """Basic components with every enclosing composite's transform applied, in drawing order."""
    out: list[Component] = []
    for c in components:
        if c.kind == "composite":
            sx, sy, tx, ty = c.transform
            osx, osy, otx, oty = transform
            # outer(inner(p)) = outer_s * (s * p + t) + outer_t
            out.extend(flatten(c.children, (osx * sx, osy * sy, osx * tx + otx, osy * ty + oty)))
        else:
            out.append(_transformed(c, transform) if transform != (1.0, 1.0, 0.0, 0.0) else c)
    return out


def _transformed(c: Component, transform: tuple[float, float, float, float]) -> Component:
    sx, sy, tx, ty = transform

    def place(p: tuple[float, float]) -> tuple[float, float]:
        return (p[0] * sx + tx, p[1] * sy + ty)

    def point(ref: PointRef) -> PointRef:
        return ref if ref.kind == "master" else replace(ref, at=place(ref.at))

    changes: dict[str, Any] = {"points": tuple(point(p) for p in c.points),
                               "body": tuple(point(p) for p in c.body),
                               "width": c.width * (abs(sx * sy) ** 0.5)}
    if c.translate:
        t = c.translate
        changes["translate"] = replace(t, at0=(t.at0[0] * sx, t.at0[1] * sy), at1=(t.at1[0] * sx, t.at1[1] * sy))
    if c.scale:
        changes["scale"] = replace(c.scale, origin=place(c.scale.origin))
    if c.rotate:  # a mirrored composite turns the other way
        way = 1.0 if sx * sy > 0 else -1.0
        changes["rotate"] = replace(c.rotate, origin=place(c.rotate.origin), at0=(way * c.rotate.at0[0],),
                                    at1=(way * c.rotate.at1[0],))
    return replace(c, **changes)
