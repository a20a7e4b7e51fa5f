"""A face compiled into a data-only web rig: what a page needs to draw the face itself from motor
values, evaluated by the one drawing module every page shares (``toonface/studio/static/rig.js``).

:class:`~toon.rig.FaceRig` binds a face once (vertices to lines and arcs, components to their
outline operators and skeletons) and then computes each frame in a few array operations; the web
rig is those bindings written out as plain numbers, so the page runs the same formulas on the same
constants and draws the frame as :func:`toon.svg.geometry_svg` would (the same lines, in the same
order). Nothing of the face is re-derived in JavaScript: a new kind of component or a change to a
binding rule changes the numbers here, and the golden test (``tests/toon/test_web_rig.py``) holds
the page's pictures to the Python renderer's.

The physics (:mod:`toon.physics`) travels as its linear system: the matrix ``A`` of the augmented
state, the drivers' target and output rows and the kicks, integrated in the page with the same
matrix exponential (for the interval between frames) as :class:`toon.physics.Physics`.

The format (``"format": "toonface-web-rig"``, ``"version": 1``) is JSON; arrays of points are
lists of ``[x, y]``; sparse matrices are CSR (``shape``, ``indptr``, ``indices``, ``data``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy import sparse

from toon.geometry import DrawItem
from toon.motors import N_MOTORS
from toon.physics import physics_for
from toon.plan import Skeleton
from toon.rig import FaceRig
from toon.skeleton import EdgeCoupling
from toon.validate import Color

FORMAT, VERSION = "toonface-web-rig", 1


def _list(array: np.ndarray | None) -> Any:
    return None if array is None else np.asarray(array).tolist()


def _csr(matrix: np.ndarray | sparse.csr_array | None) -> dict[str, Any] | None:
    if matrix is None:
        return None
    csr = sparse.csr_array(matrix)
    csr.sort_indices()
    return {"shape": list(csr.shape), "indptr": csr.indptr.tolist(), "indices": csr.indices.tolist(),
            "data": csr.data.tolist()}


def _paint(color: Color | None) -> list[float] | None:
    return None if color is None else [float(c) for c in color]


def _item(item: DrawItem) -> dict[str, Any]:
    out: dict[str, Any] = {"fill": _paint(item.fill), "stroke": _paint(item.stroke), "width": float(item.width),
                           "closed": bool(item.closed), "kind": item.kind, "maskWrite": int(item.mask_write),
                           "maskTest": item.mask_test, "name": item.name,
                           "edgeVisible": None if item.edge_visible is None else [bool(v) for v in item.edge_visible]}
    if item.picture is not None:
        out["picture"] = {"href": item.picture.href, "size": list(item.picture.size)}
        out["opacity"] = float(item.opacity)
    return out


def _skeleton(skeleton: Skeleton, taken: slice, given: slice) -> dict[str, Any]:
    c = skeleton.coupling
    out: dict[str, Any] = {"taken": [taken.start, taken.stop], "given": [given.start, given.stop],
                           "bodyRest": _list(skeleton.body_rest), "skeletonRest": _list(skeleton.skeleton_rest),
                           "moves": [bool(m) for m in c.moves]}
    if isinstance(c, EdgeCoupling):
        out.update(kind="edge", start=_list(c.start), end=_list(c.end), t=_list(c.t), d=_list(c.d))
    else:
        out.update(kind="point", nearest=_list(c.nearest))
    return out


def _change(change: Any, columns: dict[str, int]) -> dict[str, Any] | None:
    if change is None:
        return None
    return {"column": columns[change.motor], "at0": list(change.at0), "at1": list(change.at1),
            "origin": list(change.origin)}


def _physics(rig: FaceRig) -> dict[str, Any] | None:
    face = rig.face
    rests = np.concatenate([face.neutral(), rig._extra_neutral])
    physics = physics_for(face.physics, rig.codes, rests)
    if physics is None:
        return None
    return {"a": _list(physics._a), "target": _list(physics._target), "output": _list(physics._output),
            "kick": _list(physics._kick), "used": _list(physics._used), "rests": _list(rests),
            "frequencies": [d.frequency for d in physics.drivers],
            "outputs": [[rig.codes.index(d.param), d.gain] for d in physics.drivers]}


def web_rig(rig: FaceRig) -> dict[str, Any]:
    """``rig``'s face as a web rig (see the module docstring): a JSON-ready dict.

    Parameters
    ----------
    rig : FaceRig
        The face, bound.

    Returns
    -------
    dict
        Its ``codes`` (a frame's columns: the 21 motors, then HT and the face's parameters),
        ``neutral`` (the frame at rest), the control points and what moves them, the vertex plan,
        each item's paint, the head's turn and tilt, the switched items, and the physics.
    """
    face, plan = rig.face, rig._plan
    lines, arcs = plan.lines, plan.arcs
    columns = rig._columns
    low, span = rig._gaze_range
    return {
        "format": FORMAT, "version": VERSION, "name": face.name, "codes": list(rig.codes),
        "neutral": [*face.neutral().tolist(), *rig._extra_neutral.tolist()], "motors": N_MOTORS,
        "viewbox": list(face.viewbox), "background": _paint(face.background),
        "rest": _list(rig._rest),
        "driven": [[col, row, axis, lo, hi] for col, row, axis, lo, hi in rig._driven],
        "moves": [[col, row, *at0.tolist(), *span_.tolist()] for col, row, at0, span_ in rig._moves],
        "eyeRadius": float(face.eye_radius), "pupilRows": list(rig._pupil_rows),
        "gazeColumns": _list(rig._gaze_columns), "gazeLow": _list(low), "gazeSpan": _list(span),
        "lids": [[up, lo_row, column, lo, hi, rest] for up, lo_row, column, (lo, hi), rest in rig._lids],
        "head": {"yaw": list(rig._head[0]), "pitch": list(rig._head[1]), "pivot": _list(rig._pivot),
                 "tilt": float(face.head_tilt), "tiltColumn": columns.get("HT", -1),
                 "yawColumn": columns["HH"], "pitchColumn": columns["HV"]},
        "plan": {
            "size": plan.size, "slices": [[s.start, s.stop] for s in plan.slices],
            "staticAt": _list(plan.static_at), "staticXy": _list(plan.static_xy),
            "lines": None if lines is None else {k: _list(getattr(lines, k)) for k in ("start", "end", "vrl", "d")},
            "lineAt": _list(plan.line_at),
            "arcs": None if arcs is None else {k: _list(getattr(arcs, k)) for k in (
                "a", "b", "m", "other", "upper", "vrl", "d", "gap")},
            "arcAt": _list(plan.arc_at),
            "pupilAt": _list(plan.pupil_at), "pupilRow": _list(plan.pupil_row), "pupilEye": _list(plan.pupil_eye),
            "pupilOffset": _list(plan.pupil_offset),
            "pointAt": _list(plan.point_at), "pointMotor": _list(plan.point_motor),
            "pointMin": _list(plan.point_min), "pointMax": _list(plan.point_max),
            "definingRow": _list(plan.defining_row), "definingOffset": _list(plan.defining_offset),
            "definingBlend": _csr(plan.defining_blend),
            "directFrom": _list(plan.direct_from), "directTo": _list(plan.direct_to),
            "skeletons": [_skeleton(s, taken, given) for s, taken, given in plan.skeletons],
            "operator": _csr(plan.operator), "componentAt": _list(plan.component_at),
            "movingAt": _list(plan.moving_at), "movingDepth": _list(plan.moving_depth),
        },
        "animated": [{"at": [where.start, where.stop], "scale": _change(spec.scale, columns),
                      "rotate": _change(spec.rotate, columns), "translate": _change(spec.translate, columns)}
                     for where, spec in rig._animated],
        "switched": [[key, columns[shown.motor], shown.low, shown.high] for key, shown in rig._switched],
        "items": [_item(t) for t in rig.templates],
        "physics": _physics(rig),
    }

