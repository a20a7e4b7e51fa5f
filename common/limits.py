"""The limits on what toonface reads from others: one place, named (``docs/reference/limits.md``).

A file or a message from a stranger may ask for anything: a picture that never ends, a cue at
``1e308`` seconds, a drawing whose ``<use>`` elements repeat each other ten times a level. Every
reader checks what its input asks for against these limits *before* it allocates it, and refuses
with one line (an :class:`~common.errors.InputError`, or a ValueError a server turns into one
line for its page) naming the limit. Each limit lies far beyond any real input the project has
met; where one is too tight for real work, it is raised here, once, for every reader.

Files are read as regular files only (:func:`open_regular`): a named pipe would hang the reader,
a device (``/dev/zero``, through a link) would never end.
"""

from __future__ import annotations

import json
import math
import os
import re
import stat
from typing import Any, BinaryIO

from common.errors import InputError, file_kind

MiB = 1024 * 1024

# --- files ---------------------------------------------------------------------------------------
#: The largest TOML or JSON document (a face, a mapping, a job...): every toonface one is far smaller.
MAX_DOCUMENT_BYTES = 64 * MiB
#: The deepest nesting of arrays and tables in a document; a parser recursing deeper ran out of stack.
MAX_NESTING = 64
#: The largest text take or motor track (TRC, CSV): an hour of 120 Hz toon32 as CSV is 0.5 GB.
MAX_TAKE_BYTES = 2048 * MiB
#: The largest small text file: mouth cues, sound labels, a key, a text given with ``--text``.
MAX_TEXT_BYTES = 16 * MiB

# --- pictures ------------------------------------------------------------------------------------
#: The largest side of a picture in a face, pixels.
MAX_PICTURE_SIDE = 4096
#: The most pixels of a picture in a face (a 4096x4096 RGBA picture is 64 MB in memory).
MAX_PICTURE_PIXELS = MAX_PICTURE_SIDE * MAX_PICTURE_SIDE
#: The largest picture file (PNG).
MAX_PICTURE_BYTES = 64 * MiB

# --- SVG drawings --------------------------------------------------------------------------------
#: The largest SVG file imported.
MAX_SVG_BYTES = 16 * MiB
#: The most elements of a drawing once every ``<use>`` is expanded (a face's artwork has hundreds).
MAX_SVG_ELEMENTS = 20_000
#: The deepest nesting of a drawing's elements, ``<use>`` expanded.
MAX_SVG_DEPTH = 64
#: The most points of a drawing: its coordinate pairs, ``<use>`` expanded, and the points it
#: becomes (a curve becomes up to 32).
MAX_SVG_POINTS = 100_000

# --- sound ---------------------------------------------------------------------------------------
#: Sample rates a sound may have, Hz (telephone-grade to studio-grade).
SOUND_RATES = (4_000, 192_000)
#: The longest sound decoded, seconds, after decoding (an hour of 16 kHz float samples is 230 MB).
MAX_SOUND_SECONDS = 3 * 3600.0

# --- mouth cues ----------------------------------------------------------------------------------
#: The latest a mouth cue may end, seconds (a day), and never later than the sound it names.
MAX_CUE_SECONDS = 24 * 3600.0

# --- messages from pages and clients -------------------------------------------------------------
#: The deepest nesting of a JSON message a server reads.
MAX_MESSAGE_DEPTH = 16
#: The most digits a number in a JSON message may have (a time in ms has 13).
MAX_NUMBER_DIGITS = 32
#: Seconds a connection may take to send a whole request's headers (and may then idle between
#: requests) before a server closes it.
HEADER_TIMEOUT_SECONDS = 10.0


def open_regular(path: str | os.PathLike, limit: int, what: str = "file") -> BinaryIO:
    """``path`` opened for reading in binary, where it is a regular file of at most ``limit``
    bytes; an :class:`InputError` naming it otherwise ("a named pipe (FIFO), not a file", "a
    character device, not a file", "... bytes: larger than ...").

    The file is opened without blocking (a FIFO opened for reading would wait for a writer) and
    checked on the opened descriptor, so a link swapped for a device meanwhile is refused too.
    """
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InputError("no such file", path) from None
    except IsADirectoryError:
        raise InputError("a folder, not a file", path) from None
    except OSError as exc:
        raise InputError(f"cannot read it ({exc.strerror or exc})", path) from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise InputError(f"{file_kind(info.st_mode)}, not a file", path)
        if info.st_size > limit:
            raise InputError(f"{info.st_size} bytes: larger than the {limit} bytes a {what} may have", path)
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        handle = os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    return handle


def read_regular(path: str | os.PathLike, limit: int, what: str = "file") -> bytes:
    """The bytes of ``path``, a regular file of at most ``limit`` bytes (:func:`open_regular`);
    a file that grows past ``limit`` while it is read is refused too."""
    with open_regular(path, limit, what) as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise InputError(f"larger than the {limit} bytes a {what} may have", path)
    return data


def read_regular_text(path: str | os.PathLike, limit: int = MAX_TEXT_BYTES, what: str = "text file") -> str:
    """:func:`read_regular` decoded as UTF-8; an :class:`InputError` where it is not."""
    try:
        return read_regular(path, limit, what).decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"not a {what} (UTF-8 text)", path) from None


def nesting_depth(text: str) -> int:
    """The deepest nesting of ``[``/``{`` in a TOML or JSON text, outside quoted strings (an upper
    bound where TOML's comments hold brackets, which is all a limit needs).

    >>> nesting_depth('{"a": [1, {"b": "[[["}]}')
    3
    """
    import numpy as np  # loaded when a file is read, not when the command starts

    data = np.frombuffer(_STRINGS.sub("", text).encode("utf-8"), dtype=np.uint8)
    steps = ((data == ord("[")) | (data == ord("{"))).astype(np.int64) - ((data == ord("]")) | (data == ord("}")))
    return int(np.cumsum(steps).max(initial=0))


_STRINGS = re.compile(r'"(?:\\.|[^"\\\n])*"|\'[^\'\n]*\'')


def parse_json_message(text: str | bytes, max_depth: int = MAX_MESSAGE_DEPTH,
                       max_digits: int = MAX_NUMBER_DIGITS) -> Any:
    """A JSON message from a page or a client, parsed within limits: nested at most ``max_depth``
    deep, no number written with more than ``max_digits`` digits, no ``NaN`` or ``Infinity`` and
    no number that overflows to one (``1e400``).

    Raises
    ------
    ValueError
        One line saying which rule the message breaks.

    Examples
    --------
    >>> parse_json_message('{"t": 12.5, "scores": {"jawOpen": 0.25}}')
    {'t': 12.5, 'scores': {'jawOpen': 0.25}}
    >>> parse_json_message('{"t": 1e400}')
    Traceback (most recent call last):
    ValueError: a number that is not finite: 1e400
    """
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError:
            raise ValueError("not JSON (not UTF-8 text)") from None
    depth = nesting_depth(text)
    if depth > max_depth:
        raise ValueError(f"a message nested {depth} deep: at most {max_depth}")

    def whole(word: str) -> int:
        if len(word.lstrip("-")) > max_digits:
            raise ValueError(f"a number of {len(word.lstrip('-'))} digits: at most {max_digits}")
        return int(word)

    def real(word: str) -> float:
        if sum(c.isdigit() for c in word.lower().partition("e")[0]) > max_digits:
            raise ValueError(f"a number of more than {max_digits} digits")
        value = float(word)
        if not math.isfinite(value):
            raise ValueError(f"a number that is not finite: {word[:40]}")
        return value

    def constant(word: str) -> float:
        raise ValueError(f"{word} is not a number taken here")

    try:
        return json.loads(text, parse_int=whole, parse_float=real, parse_constant=constant)
    except json.JSONDecodeError as exc:
        raise ValueError(f"not JSON ({exc.msg} at character {exc.pos})") from None
    except RecursionError:
        raise ValueError("a message nested too deep") from None


def check_sound(rate: float, seconds: float, source: str | os.PathLike) -> None:
    """Refuse a sound whose ``rate`` (Hz) lies outside :data:`SOUND_RATES` or whose length
    ``seconds`` passes :data:`MAX_SOUND_SECONDS` (an :class:`InputError` naming ``source``)."""
    low, high = SOUND_RATES
    if not low <= rate <= high:
        raise InputError(f"a sound at {rate:g} Hz: the rates read are {low} to {high} Hz", source)
    if seconds > MAX_SOUND_SECONDS:
        raise InputError(f"a sound of {seconds:.0f} s: at most {MAX_SOUND_SECONDS:.0f} s are read", source)


def check_cue_end(end: float, source: str | os.PathLike, where: str | None = None,
                  sound_seconds: float | None = None) -> None:
    """Refuse a mouth cue ending after :data:`MAX_CUE_SECONDS`, or more than a frame (0.05 s)
    after the sound it came with where its length ``sound_seconds`` is known."""
    if end > MAX_CUE_SECONDS:
        raise InputError(f"a cue ending at {end:g} s: cues end within a day ({MAX_CUE_SECONDS:.0f} s)", source, where)
    if sound_seconds is not None and end > sound_seconds + 0.05:
        raise InputError(f"a cue ending at {end:g} s, after the sound's {sound_seconds:g} s", source, where)
