"""The expression repertoire (CharToon 4.1): named motor poses that every built-in face shares.

``data/expressions.toml`` (``format = "toonface.expressions/1"``) holds, for each expression, a
``description`` and ``motors``: values in ``[0, 1]`` for the motors the expression moves, and
for the standard parameters beyond the 21 it moves (``UL``, ``PERK``...; a face without one
shows the expression without it). The others stay at the face's neutral, so one repertoire
drives every face whose motors follow the same conventions (CharToon: "expressions from the
expression repertoire can be re-used").
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from common import read_document, resolve_builtin
from toon.motors import ALL_CODES, MOTOR_INDEX, extra_rest
from toon.validate import ShapeValidator

FORMAT = "toonface.expressions/1"
#: Expressions every repertoire must define: neutral, CharToon's six basic ones, blink and wink.
REQUIRED: tuple[str, ...] = ("neutral", "happiness", "surprise", "fear", "sadness", "anger", "disgust", "blink",
                             "wink")


@dataclass(frozen=True)
class Expression:
    """A named pose: motor code to value for the motors it moves."""

    name: str
    motors: MappingProxyType
    description: str = ""
    extra: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))  # the standard extras it moves

    def pose(self, neutral: np.ndarray) -> np.ndarray:
        """Motor values ``(21,)``: ``neutral`` with this expression's motors set."""
        out = np.array(neutral, dtype=np.float64, copy=True)
        for code, value in self.motors.items():
            out[MOTOR_INDEX[code]] = value
        return out

    def extra_pose(self, declared: Mapping[str, float]) -> dict[str, float]:
        """The parameters beyond the 21 of a face that ``declared`` them (code: rest): this
        expression's where it moves them, the rest elsewhere; HT (the head's) only where set."""
        return {code: float(self.extra.get(code, extra_rest(code, declared))) for code in declared
                if code != "HT" or code in self.extra}


def load_expressions(name_or_path: str | os.PathLike = "expressions") -> dict[str, Expression]:
    """The repertoire from a TOML file (the built-in one by default), in file order.

    Raises
    ------
    common.InputError
        Naming the file and the bad field (an unknown motor, a value outside [0, 1], a missing
        required expression).
    """
    path = resolve_builtin(name_or_path, ".", ".toml", "expression repertoire")
    doc = read_document(path)
    v = ShapeValidator(path)
    v.require(doc.get("format") == FORMAT, f'unsupported format {doc.get("format")!r} (expected "{FORMAT}")',
              "format")
    table = doc.get("expressions")
    if not isinstance(table, dict):
        v.fail("missing table [expressions.NAME]", "expressions")
    out = {}
    for name, entry in table.items():
        where = f"expressions.{name}"
        v.fields(entry, {"description", "motors"}, where, "an expression")
        motors = entry.get("motors", {})
        v.require(isinstance(motors, dict), "must be a table of motor = value", f"{where}.motors")
        values = {}
        for code, value in motors.items():
            v.choice(code, ALL_CODES, f"{where}.motors.{code}")
            values[code] = v.number(value, f"{where}.motors.{code}", 0.0, 1.0)
        out[name] = Expression(name, MappingProxyType({c: x for c, x in values.items() if c in MOTOR_INDEX}),
                               str(entry.get("description", "")),
                               MappingProxyType({c: x for c, x in values.items() if c not in MOTOR_INDEX}))
    missing = [n for n in REQUIRED if n not in out]
    v.require(not missing, f"missing expression(s): {', '.join(missing)}", "expressions")
    return out
