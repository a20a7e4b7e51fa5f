"""A first look at a file named ``.npz`` before numpy opens it."""

from __future__ import annotations

import os
import zipfile
import zlib
from pathlib import Path
from typing import BinaryIO

from common.errors import InputError

_ZIP = b"PK\x03\x04"  # every .npz is a zip archive; an empty one starts PK\x05\x06
_EMPTY_ZIP = b"PK\x05\x06"


#: What numpy, zipfile and zlib raise on a damaged .npz (a reader turns each into one line).
NPZ_ERRORS: tuple[type[BaseException], ...] = (OSError, ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile,
                                              zlib.error, NotImplementedError, RuntimeError)


def check_npz(fh: BinaryIO, path: str | os.PathLike, what: str) -> None:
    """Refuse a file that is no zip archive, saying what it looks like (numpy would answer a text
    file with advice about pickles). ``fh`` is the file open for reading, left at its start (the
    caller reads it next: one open per file).

    Raises
    ------
    InputError
        Naming the file: empty, a text file, a single ``.npy`` array, or some other content.
    """
    head = fh.read(64)
    fh.seek(0)
    if head.startswith((_ZIP, _EMPTY_ZIP)):
        return
    if not head:
        raise InputError(f"empty file (0 bytes), not a {what}", path)
    if head.startswith(b"\x93NUMPY"):
        raise InputError(f"a single .npy array, not a {what} (.npz archive)", path)
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"not a {what}: a .npz is a zip archive and this file is not one", path) from None
    first = text.splitlines()[0][:40] if text.strip() else ""
    raise InputError(f"not a {what}: a text file (it starts {first!r}), not a .npz zip archive", Path(path))
