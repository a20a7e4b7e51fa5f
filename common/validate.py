"""The one validator of project files: every check fails as ``FILE: field.path: what is wrong``.

Marker sets, mappings, profiles, performances, faces, component libraries, expressions and
batch jobs are all checked with :class:`Validator`, so that a bad field reads the same in every
kind of file::

    face.json: polygons[3].attach: expected one of eyes, mouth, got 'nose'
    job.toml: render.size: unknown field (known: fps, part_seconds, samples, size)
    m.toml: motor.ERU.max_speed: expected a number of at least 0, got -1

Each check takes the value (``None`` where the field is absent) and the dotted path of the field
(:func:`at` builds it), and returns the value as the caller wants it.
"""

from __future__ import annotations

import math
import os
from collections.abc import Collection
from typing import Any, NoReturn

from common.errors import InputError


def at(where: str, key: str | int) -> str:
    """The path of ``key`` inside the field ``where``.

    >>> at("motor.ERU", "gain"), at("", "name"), at("cue", 3)
    ('motor.ERU.gain', 'name', 'cue[3]')
    """
    if isinstance(key, int):
        return f"{where}[{key}]"
    return f"{where}.{key}" if where else key


def is_number(x: Any) -> bool:
    """A finite int or float that is not a bool."""
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _span(low: float, high: float) -> str:
    if low > -math.inf and high < math.inf:
        return f" from {low:g} to {high:g}"
    if low > -math.inf:
        return f" of at least {low:g}"
    return f" of at most {high:g}" if high < math.inf else ""


class Validator:
    """Checks the fields of one document, raising :class:`InputError` naming the file and field.

    Parameters
    ----------
    source : path or None
        The document's file, named in every error.
    """

    def __init__(self, source: str | os.PathLike | None) -> None:
        self.source = source

    def fail(self, message: str, where: str) -> NoReturn:
        """Raise ``InputError(message)`` at ``where``."""
        raise InputError(message, self.source, where or None)

    def require(self, ok: bool, message: str, where: str) -> None:
        """Raise ``InputError(message)`` at ``where`` unless ``ok``."""
        if not ok:
            self.fail(message, where)

    def present(self, value: Any, where: str) -> Any:
        """A field that must be there."""
        self.require(value is not None, "missing", where)
        return value

    def fields(self, value: Any, allowed: Collection[str], where: str, what: str = "a table") -> dict:
        """A table with no fields outside ``allowed``; an unknown one is named by its own path."""
        self.require(isinstance(value, dict), f"expected {what}, got {value!r}", where)
        unknown = sorted(set(value) - set(allowed))
        if unknown:
            self.fail(f"unknown field (known: {', '.join(sorted(allowed))})", at(where, unknown[0]))
        return value

    def number(self, value: Any, where: str, low: float = -math.inf, high: float = math.inf) -> float:
        """A finite number in ``[low, high]``."""
        self.require(is_number(value) and low <= value <= high, f"expected a number{_span(low, high)}, got {value!r}",
                     where)
        return float(value)

    def integer(self, value: Any, where: str, low: float = -math.inf, high: float = math.inf) -> int:
        """An integer in ``[low, high]``."""
        ok = isinstance(value, int) and not isinstance(value, bool) and low <= value <= high
        self.require(ok, f"expected an integer{_span(low, high)}, got {value!r}", where)
        return int(value)

    def numbers(self, value: Any, n: int, where: str) -> list[float]:
        """A list of exactly ``n`` finite numbers."""
        ok = isinstance(value, list) and len(value) == n and all(is_number(x) for x in value)
        self.require(ok, f"expected a list of {n} number{'s' if n > 1 else ''}, got {value!r}", where)
        return [float(x) for x in value]

    def boolean(self, value: Any, where: str) -> bool:
        """``true`` or ``false``."""
        self.require(isinstance(value, bool), f"expected true or false, got {value!r}", where)
        return bool(value)

    def text(self, value: Any, where: str, empty: bool = True) -> str:
        """A string (non-empty unless ``empty``)."""
        ok = isinstance(value, str) and (empty or bool(value))
        self.require(ok, f"expected a{'' if empty else ' non-empty'} string, got {value!r}", where)
        return str(value)

    def strings(self, value: Any, where: str, empty: bool = True) -> list[str]:
        """A list of non-empty strings (at least one unless ``empty``)."""
        ok = isinstance(value, list) and (empty or bool(value)) and all(isinstance(v, str) and v for v in value)
        self.require(ok, f"expected a{'' if empty else ' non-empty'} list of names, got {value!r}", where)
        return list(value)

    def choice(self, value: Any, options: Collection[str], where: str) -> str:
        """One of ``options``; the error lists them."""
        self.require(isinstance(value, str) and value in options,
                     f"expected one of {', '.join(options)}, got {value!r}", where)
        return str(value)
