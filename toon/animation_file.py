"""Knot-point animation files (TOML, ``toonface.animation/1``; :mod:`toon.animation` describes
the format): writing an animation so that it reads like its curves, and reading one with errors
that name the file and field. :mod:`toon.animation` re-exports all three functions."""

from __future__ import annotations

import os
import re
from itertools import pairwise
from pathlib import Path

from common import InputError, atomic_path, read_versioned
from toon.animation import EASE, FORMAT, MAX_DURATION, Animation, Knots, eased
from toon.motors import EXTRA_CODE, MOTOR_CODES, MOTOR_INDEX


def save_animation(anim: Animation, path: str | os.PathLike) -> Path:
    """Write :func:`animation_text` to ``path`` (atomically)."""
    text = animation_text(anim, path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def animation_text(anim: Animation, path: str | os.PathLike | None = None) -> str:
    """The animation as TOML, each motor's knots as inline ``[time, value]`` pairs: a short curve
    on one line, a long one a few knots to a line, so the file reads like the curves (an error
    naming ``path`` where it cannot be written)."""
    if not 0 <= anim.duration <= MAX_DURATION:  # anim scale --time 1e300 wrote a file the reader refused
        raise InputError(f"the animation would last {anim.duration:g} s; an animation lasts 0..{MAX_DURATION:g} s",
                         path)
    lines = [f'format = "{FORMAT}"', f"duration = {float(anim.duration)!r}", "", "[knots]"]
    for code in (*MOTOR_CODES, *anim.extra_codes):
        if code not in anim.knots:
            continue
        ease = f', "{EASE}"'
        pairs = [f"[{float(k[0])!r}, {float(k[1])!r}{ease if eased(k) else ''}]" for k in anim.knots[code]]
        one_line = f"{code} = [{', '.join(pairs)}]"
        if len(one_line) <= 100:
            lines.append(one_line)
        else:
            lines.append(f"{code} = [")
            lines += ["    " + ", ".join(pairs[i:i + 5]) + "," for i in range(0, len(pairs), 5)]
            lines.append("]")
    return "\n".join(lines) + "\n"


def load_animation(path: str | os.PathLike) -> Animation:
    """Read an animation file; errors name the file and field."""
    path = Path(path)
    doc = read_versioned(path, FORMAT, "animation")
    duration = doc.get("duration")
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) or not 0 <= duration <= MAX_DURATION:
        raise InputError(f"expected seconds (0..{MAX_DURATION:g}), got {duration!r}", path, "duration")
    table = doc.get("knots", {})
    if not isinstance(table, dict):
        raise InputError("expected a table CODE = [[time, value], ...]", path, "knots")
    knots: dict[str, Knots] = {}
    for code, points in table.items():
        where = f"knots.{code}"
        if code not in MOTOR_INDEX and not re.fullmatch(EXTRA_CODE, code):
            raise InputError(f"unknown motor {code!r} (a motor such as MB, or a face's parameter such as HT)",
                             path, where)
        if not (isinstance(points, list) and all(
                isinstance(p, list) and len(p) in (2, 3) and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                                 for x in p[:2]) and p[2:] in ([], [EASE])
                for p in points)):
            raise InputError(f'expected [[time, value], ...] (a knot that eases: [time, value, "{EASE}"])', path, where)
        if any(not 0 <= p[1] <= 1 for p in points):
            raise InputError("values must be 0..1", path, where)
        if any(b[0] < a[0] for a, b in pairwise(points)) or any(
                a[0] == b[0] == c[0] for a, b, c in zip(points, points[1:], points[2:], strict=False)):
            raise InputError("knot times must increase (two knots at one time make a step; three cannot)", path,
                             where)
        knots[code] = tuple((float(p[0]), float(p[1]), True) if p[2:] else (float(p[0]), float(p[1])) for p in points)
    return Animation(knots, float(duration))
