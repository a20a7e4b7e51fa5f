"""What the studio accepts from a page: messages parsed within limits, numbers that are numbers,
and files only inside the folder the studio was started in.

A page is trusted no more than any program on the network: a message with NaN put a bare ``NaN``
into every later frame (which the pages' ``JSON.parse`` rejects), deep JSON or a 60 KB path
dropped the socket with a server traceback, and ``labels /etc/shadow`` answered with the file's
first line. Each rule here raises :class:`ValueError` with one line for the page.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from common.data import names_builtin
from common.limits import parse_json_message

#: The deepest nesting of a page's message (the deepest the pages send is 3).
MAX_DEPTH = 8
#: The largest number in a message, either sign (times, values, indices, factors).
MAX_NUMBER = 1e6
#: The longest string in a message (a path on Linux is at most 4096 bytes).
MAX_STRING = 4096


def parse_message(text: str) -> object:
    """A page's message, parsed: JSON no deeper than :data:`MAX_DEPTH`, with no NaN or infinity
    (``NaN``, ``Infinity``, ``1e400``), no number beyond :data:`MAX_NUMBER` and no string longer
    than :data:`MAX_STRING`.

    Raises
    ------
    ValueError
        Saying which rule the message breaks.
    """
    parsed = parse_json_message(text, MAX_DEPTH)
    _check(parsed)
    return parsed


def _check(value: object) -> None:
    if isinstance(value, dict):
        for key, item in value.items():
            _check(key)
            _check(item)
    elif isinstance(value, list):
        for item in value:
            _check(item)
    elif isinstance(value, str):
        if len(value) > MAX_STRING:
            raise ValueError(f"a string of {len(value)} characters: the studio takes at most {MAX_STRING}")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        number(value)


def number(value: object, what: str = "a number") -> float:
    """``value`` (a JSON number or a string holding one) as a float, refused where it is not
    finite or lies beyond :data:`MAX_NUMBER`."""
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{what}: expected a number, got {_shown(value)}") from None
    if not math.isfinite(out) or abs(out) > MAX_NUMBER:
        raise ValueError(f"{what}: expected a finite number within ±{MAX_NUMBER:g}, got {_shown(value)}")
    return out


def index(value: object, what: str = "an index") -> int:
    """``value`` as a whole number (an index or a count) within :data:`MAX_NUMBER`."""
    out = number(value, what)
    if out != int(out):
        raise ValueError(f"{what}: expected a whole number, got {out:g}")
    return int(out)


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


@dataclass(frozen=True)
class Folder:
    """The folder the studio reads and writes in (where it was started): a path from a page is
    taken relative to it, and refused where it leads outside it, by ``..``, an absolute path or a
    link.

    Attributes
    ----------
    root : Path
        The folder, resolved.
    """

    root: Path

    @classmethod
    def here(cls) -> Folder:
        """The current working folder."""
        return cls(Path.cwd().resolve())

    def inside(self, path: object, what: str = "a file") -> Path:
        """``path`` resolved inside :attr:`root`; a :class:`ValueError` naming the folder where it
        is not (the error names the path as the page gave it, never what the file holds)."""
        text = str(path)
        if not text or "\x00" in text:
            raise ValueError(f"{what}: expected a file name, got {_shown(path)}")
        resolved = (self.root / text).resolve()  # an absolute path stays one, and is then checked
        if resolved != self.root and self.root not in resolved.parents:
            raise ValueError(f"{what}: {_shown(text)} is outside {self.root}, the folder the studio was started in;"
                             " the studio reads and writes only there")
        return resolved

    def name_or_inside(self, name: object, what: str = "a file") -> str:
        """A built-in's bare name as given (``toon32``, ``mouths``: :func:`~common.data.names_builtin`,
        whatever the folder holds), else a path inside :attr:`root`."""
        text = str(name)
        if names_builtin(text):
            return text
        return str(self.inside(text, what))
