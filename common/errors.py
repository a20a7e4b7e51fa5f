"""The one exception family the CLI turns into a one-line message and a non-zero exit."""

from __future__ import annotations

import os


class ToonfaceError(Exception):
    """Base class of every error that is the user's to fix (bad file, bad option, bad value)."""


class InputError(ToonfaceError, ValueError):
    """A file or value that cannot be used, with where the problem is.

    Parameters
    ----------
    message : str
        What is wrong, quoting the offending value.
    source : str or os.PathLike, optional
        The file (or other named input) the problem is in.
    field : str, optional
        The path of the bad field inside it, such as ``polygons[3].attach`` or ``line 12``.

    Examples
    --------
    >>> str(InputError('unknown control point "Mx"', "face.json", "polygons[3].point"))
    'face.json: polygons[3].point: unknown control point "Mx"'
    """

    def __init__(self, message: str, source: str | os.PathLike | None = None,
                 field: str | None = None) -> None:
        self.message = message
        self.source = None if source is None else os.fspath(source)
        self.field = field
        super().__init__(self._render())

    def _render(self) -> str:
        parts = [p for p in (self.source, self.field) if p]
        return ": ".join([*parts, self.message])


def require_file(path: str | os.PathLike) -> None:
    """Raise :class:`InputError` unless ``path`` is a regular file, saying what it is instead
    ("no such file", "a folder, not a file", "a named pipe (FIFO), not a file"...): a FIFO was
    reported as missing."""
    import stat

    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise InputError("no such file", path) from None
    except OSError as exc:
        raise InputError(f"cannot read it ({exc.strerror})", path) from None
    if stat.S_ISREG(mode):
        return
    raise InputError(f"{file_kind(mode)}, not a file", path)


def file_kind(mode: int) -> str:
    """What a file that is not a regular one is, from its ``st_mode``: "a folder", "a named pipe
    (FIFO)", "a socket", "a character device", "a block device"."""
    import stat

    kinds = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISSOCK, "a socket"),
             (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"))
    return next((name for test, name in kinds if test(mode)), "not a regular file")


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C's KeyboardInterrupt, so that outputs are
    closed and kept the same way (the ``toonface`` command installs the handler)."""


class Interrupted(KeyboardInterrupt):
    """An offline output stopped part-way by Ctrl-C or SIGTERM, closed with the frames it has.

    Parameters
    ----------
    output : str
        What was kept.
    frames, total : int
        Frames written, and the frames the whole output would have had.
    signal_name : str
        ``SIGINT`` or ``SIGTERM``.
    """

    def __init__(self, output: str, frames: int, total: int, signal_name: str) -> None:
        super().__init__(f"{output}: stopped by {signal_name} after {frames} of {total} frames")
        self.output, self.frames, self.total, self.signal_name = output, frames, total, signal_name
