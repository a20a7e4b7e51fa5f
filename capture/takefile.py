"""Take files. This version reads and writes the project's own ``.npz``; other formats plug in
by suffix in :data:`_READERS` / :data:`_WRITERS`."""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from common import InputError, atomic_path
from capture.take import Take

NPZ_FORMAT = "toonface.take/1"


def _write_npz(take: Take, path: Path) -> None:
    with open(path, "wb") as fh:
        np.savez_compressed(fh, format=NPZ_FORMAT, positions=take.positions, labels=np.array(take.labels),
                            rate=np.float64(take.rate), times=take.times, dims=np.int64(take.dims),
                            meta=json.dumps(take.meta))


def _read_npz(path: Path) -> Take:
    try:
        with np.load(path, allow_pickle=False) as z:
            if "format" not in z.files or str(z["format"]) != NPZ_FORMAT:
                raise InputError(f'not a toonface take (missing format "{NPZ_FORMAT}")', path)
            return Take(z["positions"], tuple(str(x) for x in z["labels"]), float(z["rate"]),
                        times=z["times"], dims=int(z["dims"]), meta=json.loads(str(z["meta"])))
    except InputError as exc:
        raise InputError(exc.message, path) from None
    except (OSError, ValueError, KeyError) as exc:
        raise InputError(f"cannot read take ({exc})", path) from None


_READERS: dict[str, Callable[[Path], Take]] = {".npz": _read_npz}
_WRITERS: dict[str, Callable[[Take, Path], None]] = {".npz": _write_npz}


def load_take(path: str | os.PathLike) -> Take:
    """Read a take file, choosing the reader by suffix."""
    path = Path(path)
    reader = _READERS.get(path.suffix.lower())
    if reader is None:
        raise InputError(f"unknown take format {path.suffix!r} (readable: {', '.join(_READERS)})", path)
    if not path.is_file():
        raise InputError("no such file", path)
    return reader(path)


def save_take(take: Take, path: str | os.PathLike) -> Path:
    """Write a take file atomically, choosing the writer by suffix."""
    path = Path(path)
    writer = _WRITERS.get(path.suffix.lower())
    if writer is None:
        raise InputError(f"unknown take format {path.suffix!r} (writable: {', '.join(_WRITERS)})", path)
    with atomic_path(path) as tmp:
        writer(take, tmp)
    return path
