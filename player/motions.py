"""Standard motions (ToonFace expected "libraries of standard motions"), built on the repertoire.

A motion is a timed list of steps, each a set of :class:`~player.animator.Move` started at an
offset from when the motion is played; the Animator slices each step as it would any command.
``play NAME SECONDS`` stretches a motion to that length.

Poses (``smile``, ``frown``, ``surprise``, ``neutral``, and any expression in the repertoire)
move every motor but the head and the pupils to the expression (the face's neutral for the
motors it leaves alone), so the face shows that expression whatever it showed before; gestures
(``blink``, ``wink``, ``nod``, ``shake``, ``talk``) move only their own motors and come back.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from player.animator import Move, moves_to
from toon import MOTOR_CODES, Expression, motor_index

#: Motions that are a pose from the repertoire under another name.
POSE_ALIASES = {"smile": "happiness", "frown": "anger"}
GESTURES = ("blink", "wink", "nod", "shake", "talk")
#: Default length of each motion, seconds.
DEFAULT_SECONDS = {"blink": 0.2, "wink": 0.4, "nod": 1.0, "shake": 1.2, "talk": 1.5}
POSE_SECONDS = 0.5
_FACE_MOTORS = tuple(c for c in MOTOR_CODES if c not in ("HH", "HV", "PLH", "PLV", "PRH", "PRV"))


@dataclass(frozen=True)
class Motion:
    """A named, timed list of steps: ``(offset seconds, moves)``."""

    name: str
    steps: tuple[tuple[float, tuple[Move, ...]], ...]


def motion_names(expressions: dict[str, Expression]) -> list[str]:
    """Every name ``play`` accepts: the standard motions, then the repertoire's other expressions."""
    names = ["smile", "frown", "neutral", "surprise", *GESTURES]
    return names + [n for n in expressions if n not in names and n not in ("blink", "wink")]


def standard_motion(name: str, seconds: float | None, current: np.ndarray, neutral: np.ndarray,
                    expressions: dict[str, Expression], extras: Mapping[str, float] | None = None) -> Motion:
    """The motion ``name`` lasting ``seconds`` (its default when None), from the ``current``
    values ``(21,)`` on a face whose rest pose is ``neutral`` ``(21,)`` and whose parameters
    beyond the 21 rest at ``extras`` (code: value; an expression moves them too).

    Raises
    ------
    KeyError
        For a name that is neither a standard motion nor an expression.
    """
    d = DEFAULT_SECONDS.get(name, POSE_SECONDS) if seconds is None else seconds
    v = lambda code: float(current[motor_index(code)])  # noqa: E731 - a short local lookup
    if name == "blink":
        lids = ("ERU", "ELU", "ERL", "ELL")
        shut = {"ERU": 0.0, "ELU": 0.0, "ERL": 0.5, "ELL": 0.5}
        return Motion(name, ((0.0, tuple(Move(c, shut[c], d / 2) for c in lids)),
                             (d / 2, tuple(Move(c, v(c), d / 2) for c in lids))))
    if name == "wink":
        return Motion(name, ((0.0, (Move("ELU", 0.0, d / 2), Move("ELL", 0.5, d / 2))),
                             (d / 2, (Move("ELU", v("ELU"), d / 2), Move("ELL", v("ELL"), d / 2)))))
    if name in ("nod", "shake"):
        code = "HV" if name == "nod" else "HH"
        rest = float(neutral[motor_index(code)])
        swings = (rest - 0.15, rest + 0.12, rest - 0.08, rest)
        return Motion(name, tuple((d * k / 4, (Move(code, s, d / 4),)) for k, s in enumerate(swings)))
    if name == "talk":
        syllables = max(1, int(round(d * 4)))  # about four a second
        step = d / syllables
        steps = []
        for k in range(syllables):
            steps.append((k * step, (Move("MB", 0.55 if k % 2 == 0 else 0.35, step / 2),)))
            steps.append((k * step + step / 2, (Move("MB", float(neutral[motor_index("MB")]), step / 2),)))
        return Motion(name, tuple(steps))
    expression = expressions[POSE_ALIASES.get(name, name)]
    beyond = tuple(Move(code, value, d) for code, value in expression.extra_pose(extras or {}).items())
    return Motion(name, ((0.0, moves_to(expression.pose(neutral), d, _FACE_MOTORS) + beyond),))
