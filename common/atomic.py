"""Atomic writes: outputs appear whole under their final name, or not at all."""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from common.errors import InputError


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike, mode: int | None = None) -> Iterator[Path]:
    """Yield a temporary path beside ``target``; rename it onto ``target`` if the block succeeds.

    The temporary file keeps ``target``'s suffix (so writers that choose a format by suffix
    still work). On an exception the temporary file is removed and ``target`` is untouched.
    ``mode``: the output's permissions (``0o600`` for a secret; it is never readable by others on
    the way); by default the usual ones under the umask.
    """
    target = Path(target)
    check_folder(target)
    _remove_leftovers(target, rf"\.{re.escape(target.stem)}\.[a-z0-9_]{{8}}\.partial{re.escape(target.suffix)}")
    fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=f".partial{target.suffix}",
                               dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        os.chmod(tmp_path, 0o666 & ~_umask() if mode is None else mode)  # mkstemp makes it owner-only
        os.replace(tmp_path, target)
    finally:
        tmp_path.unlink(missing_ok=True)


def _remove_leftovers(target: Path, pattern: str) -> None:
    """Remove the hidden temporaries an earlier run writing ``target`` left when it was killed
    (SIGKILL leaves no time to clean up): the next run to the same output clears them."""
    match = re.compile(pattern).fullmatch
    for path in target.parent.iterdir():
        if match(path.name):
            with contextlib.suppress(OSError):
                shutil.rmtree(path) if path.is_dir() else path.unlink()


def check_folder(target: Path) -> None:
    """Refuse an output whose folder does not exist, as ``cp`` does (a typo must not make folders)."""
    folder = target.parent
    if not folder.is_dir():
        raise InputError(f"cannot write: no such folder {folder}", target)


def _umask() -> int:
    """The process's umask, read without changing it (os.umask can only set it, for every thread)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    return 0o022


@contextlib.contextmanager
def atomic_dir(target: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary directory beside ``target``; it replaces ``target`` if the block succeeds.

    An existing ``target`` directory is replaced whole, so a re-run never mixes old and new files.
    """
    target = Path(target)
    check_folder(target)
    _remove_leftovers(target, rf"\.{re.escape(target.name)}\.([a-z0-9_]{{8}}\.partial|old)")
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".partial", dir=target.parent))
    try:
        yield tmp
        os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp makes it owner-only
        if target.exists():
            old = target.with_name(f".{target.name}.old")
            shutil.rmtree(old, ignore_errors=True)
            os.replace(target, old)
            os.replace(tmp, target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
