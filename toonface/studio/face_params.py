"""The face editor's parameters beyond the 21 and physics drivers, as edits of a face document
(:class:`toonface.studio.faces.FaceEditor` validates the result, undoes and redoes)."""

from __future__ import annotations

import numpy as np

from toon.motors import STANDARD_EXTRAS
from toonface.studio.face_items import finite


def set_param(doc: dict, code: str, neutral: float | None = None, description: str | None = None,
              point: str | None = None, dx: float = 0.0, dy: float = 0.0) -> None:
    """Declare parameter ``code`` (or change it): where it rests, what it means, and with
    ``point``, that control point moved by ``(dx, dy)`` face units (y up) at the parameter's 1
    from where it rests (at its 0 for one that rests at 1); a move of (0, 0) lets the point go.
    A standard one (UL...) rests where the standard says."""
    body = doc.setdefault("params", {}).setdefault(code, {})
    if neutral is not None:
        body["neutral"] = finite(neutral)
    if description is not None:
        body["description"] = description
    if point is not None:
        rest = body.get("neutral", STANDARD_EXTRAS[code].neutral if code in STANDARD_EXTRAS else 0.0)
        moves = body.setdefault("points", {})
        step = np.array([finite(dx), finite(dy)]) / (1.0 - rest if rest < 1 else -1.0)
        if step.any():
            moves[point] = {"at0": list(-rest * step), "at1": list((1 - rest) * step)}
        else:
            moves.pop(point, None)


def delete_param(doc: dict, code: str) -> None:
    """Remove parameter ``code``."""
    if code not in doc.get("params", {}):
        raise KeyError(f"no parameter {code!r}")
    del doc["params"][code]


def set_driver(doc: dict, name: str, param: str, inputs: str, frequency: float, damping: float,
               swing: bool = True, gain: float = 1.0) -> None:
    """Add driver ``name`` (or change it): a spring of ``frequency`` Hz and ``damping`` moving
    parameter ``param`` by its swing (``swing``) or its follow, times ``gain``, from ``inputs``
    written ``"HH:1.2 MB':0.04 HH'':0.001"`` (a code, ``'`` for its velocity, ``''`` for its
    acceleration, and a gain; see :mod:`toon.physics`)."""
    parsed = []
    for word in inputs.split():
        code, _, gain_text = word.partition(":")
        primes = len(code) - len(code.rstrip("'"))
        kind = {1: {"of": "velocity"}, 2: {"of": "acceleration"}}.get(primes, {})
        parsed.append({"code": code.rstrip("'").upper(), "gain": finite(float(gain_text or 1.0)), **kind})
    body = {"name": name, "inputs": parsed, "frequency": finite(frequency), "damping": finite(damping),
            "output": {"param": param, "gain": finite(gain), "swing": bool(swing)}}
    drivers = doc.setdefault("physics", [])
    at = next((k for k, d in enumerate(drivers) if d.get("name") == name), None)
    if at is None:
        drivers.append(body)
    else:
        drivers[at] = body


def delete_driver(doc: dict, name: str) -> None:
    """Remove driver ``name``."""
    drivers = doc.get("physics", [])
    kept = [d for d in drivers if d.get("name") != name]
    if len(kept) == len(drivers):
        raise KeyError(f"no driver {name!r}")
    doc["physics"] = kept
