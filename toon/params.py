"""Parameters a face declares beyond the 21 motors (CharToon's animation parameters).

A face file's ``params`` object names each parameter by its code (capitals, digits and ``_``,
like ``UL``) and gives::

    "UL": {"description": "upper lip raised (sneer)", "neutral": 0,
           "points": {"MT": {"at0": [0, 0], "at1": [0, 18]}}}

- ``neutral``: the value at which the face shows its rest drawing (a track without the
  parameter holds it there); for a standard extra (:data:`toon.motors.STANDARD_EXTRAS`) it is
  the standard one and may be left out.
- ``points``: control points the parameter displaces, linearly from ``at0`` (value 0) to ``at1``
  (value 1), on top of where the motors put them; at the neutral value the displacement is
  zero, so the rest drawing is the face's own. Every line, arc and component bound to a moved
  point follows it, as it follows a motor.

Beyond its points a parameter drives, exactly as a motor does, components' ``visible``,
``translate`` and ``scale`` (``{"motor": "UL", ...}``) and ``point`` polygons attached to it
(``"attach": "PERK"``, two states at 0 and 1). ``HT`` is declared by ``head.tilt`` instead.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from toon.motors import EXTRA_CODE, MOTOR_CODES, STANDARD_EXTRAS
from toon.validate import ShapeValidator


@dataclass(frozen=True)
class PointMove:
    """A control point displaced by ``at0 + value * (at1 - at0)``."""

    point: str
    at0: tuple[float, float]
    at1: tuple[float, float]


@dataclass(frozen=True)
class ParamSpec:
    """One declared parameter: its code, what it means, its rest value and the points it moves."""

    code: str
    description: str = ""
    neutral: float = 0.0
    points: tuple[PointMove, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The parameter as written in a face file (its code is the key)."""
        d: dict[str, Any] = {"description": self.description, "neutral": self.neutral}
        if self.points:
            d["points"] = {m.point: {"at0": list(m.at0), "at1": list(m.at1)} for m in self.points}
        return d


def drawable(codes: tuple[str, ...] | list[str], declared: tuple[str, ...]) -> tuple[list[str], list[str], list[str]]:
    """Parameters ``codes`` (a track's or a stream's) against those a face ``declared``: those it
    draws, the standard ones it lacks (left out, said) and any other it lacks (an error, or a
    stream refused)."""
    kept = [c for c in codes if c in declared]
    standard = [c for c in codes if c not in declared and c in STANDARD_EXTRAS]
    return kept, standard, [c for c in codes if c not in declared and c not in STANDARD_EXTRAS]


class DrawnExtras:
    """The parameters beyond the 21 a live source sends (a stream, a performer), kept to those a
    face declares: a standard one the face lacks is drawn without (every preset sends all of
    them; few faces draw all), any other is refused and said once through ``say`` (it means
    something only to a face that has it)."""

    def __init__(self, declared: tuple[str, ...], face_name: str, say: Callable[[str], None]) -> None:
        self.declared, self.face_name, self.say = declared, face_name, say
        self._said: set[str] = set()

    def drawn(self, extra: Mapping[str, float] | None) -> dict[str, float]:
        """``extra`` without the codes the face lacks."""
        if not extra:
            return {}
        kept, _standard, other = drawable(list(extra), self.declared)
        if odd := [c for c in other if c not in self._said]:
            self.say(f"refused parameter{'s' if len(odd) > 1 else ''} {', '.join(odd)}: not standard and not "
                     f"declared by face {self.face_name} (declared: {', '.join(self.declared) or 'none'})")
        self._said.update(other)
        return {code: float(extra[code]) for code in kept}


def parse_params(raw: Any, v: ShapeValidator, control_points: tuple[str, ...]) -> tuple[ParamSpec, ...]:
    """Validate a face file's ``params`` object; errors name the field (``params.UL.points.MT``)."""
    if raw is None:
        return ()
    v.require(isinstance(raw, dict), 'must map codes to parameters, like {"UL": {"neutral": 0}}', "params")
    return tuple(_param(code, body, v, control_points) for code, body in raw.items())


def _param(code: Any, body: Any, v: ShapeValidator, control_points: tuple[str, ...]) -> ParamSpec:
    where = f"params.{code}"
    v.require(isinstance(code, str) and re.fullmatch(EXTRA_CODE, code) is not None,
              "a parameter code is 1-16 capitals, digits or _, starting with a capital", where)
    v.require(code not in MOTOR_CODES, f"{code} is one of the 21 motors; give the new parameter another code", where)
    v.require(code != "HT", "the head's tilt HT is declared by head.tilt (degrees each way)", where)
    v.require(isinstance(body, dict), "must be an object", where)
    v.fields(body, {"description", "neutral", "points"}, where, "a parameter")
    standard = STANDARD_EXTRAS.get(code)
    neutral = v.number(body.get("neutral", standard.neutral if standard else 0.0), f"{where}.neutral", 0.0, 1.0)
    v.require(standard is None or neutral == standard.neutral,
              f"{code} is a standard parameter ({standard.description if standard else ''}) whose neutral is "
              f"{standard.neutral if standard else ''}; leave neutral out or give a new code", f"{where}.neutral")
    points = body.get("points", {})
    v.require(isinstance(points, dict), 'must map control points to {"at0": [dx, dy], "at1": [dx, dy]}',
              f"{where}.points")
    moves = []
    for name, move in points.items():
        at = f"{where}.points.{name}"
        v.require(name in control_points, f'unknown control point "{name}" (known: {" ".join(control_points)})', at)
        v.fields(move, {"at0", "at1"}, at, "a point move")
        at0 = tuple(v.numbers(move.get("at0", [0.0, 0.0]), 2, f"{at}.at0"))
        at1 = tuple(v.numbers(move.get("at1", [0.0, 0.0]), 2, f"{at}.at1"))
        rest = [a0 + neutral * (a1 - a0) for a0, a1 in zip(at0, at1, strict=True)]
        v.require(max(abs(r) for r in rest) < 1e-9,
                  f"at the neutral {neutral:g} the point moves by [{rest[0]:g}, {rest[1]:g}]; a parameter at rest "
                  "leaves its points at rest (make at0 + neutral * (at1 - at0) zero)", at)
        moves.append(PointMove(name, at0, at1))  # type: ignore[arg-type]
    description = body.get("description", standard.description if standard else "")
    v.require(isinstance(description, str), "must be text", f"{where}.description")
    return ParamSpec(code, description, neutral, tuple(moves))
