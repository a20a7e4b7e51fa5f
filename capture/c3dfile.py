"""C3D takes, read and written through the ``c3d`` library (py-c3d).

What the reader makes of a C3D file:

* integer and floating-point storage; Intel, DEC and SGI/MIPS (big-endian) processor types; the
  header's section pointers (the library follows them); a non-integer ``POINT:RATE``.
* integer samples multiplied by ``POINT:SCALE``; coordinates converted from ``POINT:UNITS``
  (mm, cm, m, in) to millimetres.
* a negative residual word marks a gap, which becomes NaN.
* analog channels are skipped (their count is kept in ``meta``).
* labels are trimmed; an empty label becomes ``M001`` and so on, and a repeated one gets ``#2``.
  Both changes are listed in ``meta["renamed"]``.

The library's warnings about vendor quirks (a ``DATA_START`` of 0, missing optional parameters,
a data section that ends early) are kept in ``meta["warnings"]`` rather than printed.
"""

from __future__ import annotations

import logging
import warnings
from pathlib import Path
from typing import Any

import c3d
import numpy as np

from capture.take import UNIT_MM, Take, unique_labels
from common import InputError

_PARAMETER_MAGIC = 0x50  # the second byte of every C3D file
log = logging.getLogger(__name__)


def read_c3d(path: Path, allow_truncated: bool = False) -> Take:
    """Read the points of a C3D file as a :class:`Take` in millimetres.

    A file that ends before the last frame its header declares is refused, unless
    ``allow_truncated``: then the frames that are there are read, with a warning.

    Raises
    ------
    InputError
        Naming the file and what is wrong: empty, not a C3D file, truncated, or points missing.
    """
    with open(path, "rb") as fh:
        head = fh.read(512)
        if not head:
            raise InputError("empty file (0 bytes), not a C3D take", path)
        if len(head) < 512 or head[1] != _PARAMETER_MAGIC:
            raise InputError("not a C3D file (the header's second byte must be 0x50)", path)
        fh.seek(0)
        caught: list[str] = []
        try:
            with warnings.catch_warnings(record=True) as seen:
                warnings.simplefilter("always")
                reader = c3d.Reader(fh)
                rate = float(reader.point_rate)
                scale = float(reader.point_scale)
                labels = [str(x) for x in reader.point_labels]
                analog_used = int(reader.analog_used)
                units = _units(reader)
                declared = _declared_frames(reader)
                frames = [points[:, :4].copy() for _, points, _ in reader.read_frames(copy=False, check_nan=True)]
                processor = str(getattr(reader, "proc_type", "unknown"))
            caught = [str(w.message).split("\n")[0].strip() for w in seen
                      if "No analog data" not in str(w.message)]
        except Exception as exc:  # noqa: BLE001 - only library parsing is inside; any failure means a bad file
            raise InputError(f"corrupt or truncated C3D file ({type(exc).__name__}: {exc})", path) from None
    if not np.isfinite(rate) or rate <= 0 or rate > 1e6:
        raise InputError(f"POINT:RATE is {rate!r}; expected a positive frame rate", path)
    if not frames:
        raise InputError("no point frames in the file", path)
    if len(frames) < declared:
        ends = f"the file ends early: it holds {len(frames)} of the {declared} frames its header declares"
        if not allow_truncated:
            raise InputError(f"{ends} (--allow-truncated reads what is there)", path)
        log.warning("%s: %s; reading those", path, ends)
        caught = [*caught, ends]
    if units not in UNIT_MM:
        raise InputError(f'unknown POINT:UNITS "{units}" (known: {", ".join(sorted(UNIT_MM))})', path)
    data = np.stack(frames).astype(np.float64)
    if data.shape[1] != len(labels):
        labels = (labels + [""] * data.shape[1])[: data.shape[1]]
    positions = data[:, :, :3] * UNIT_MM[units]
    positions[data[:, :, 3] < 0] = np.nan
    clean, renamed = unique_labels(labels)
    meta: dict[str, Any] = {"source": "c3d", "file": path.name, "processor": processor,
            "storage": "float" if scale < 0 else "integer", "point_scale": abs(scale), "units_in_file": units,
            "analog_channels_skipped": analog_used}
    if renamed:
        meta["renamed"] = renamed
    if caught:
        meta["warnings"] = caught
    return Take(positions, clean, rate, meta=meta)


def write_c3d(take: Take, path: Path) -> None:
    """Write ``take`` as a float C3D (Intel) in millimetres; gaps get a residual of -1.

    The library writes a header, parameter and data sections that :func:`read_c3d` and other
    readers (Vicon, Motive, ezc3d) accept. Times other than ``frame / rate`` are not kept.
    """
    writer = c3d.Writer(point_rate=float(take.rate), analog_rate=0.0, point_scale=-1.0, point_units="mm  ")
    writer.set_point_labels(list(take.labels))
    seen = take.valid
    empty_analog = np.empty((0, 0), dtype=np.float32)
    frames = []
    for f in range(take.frames):
        points = np.zeros((take.markers, 5), dtype=np.float32)
        points[:, :3] = np.nan_to_num(take.positions[f])
        points[:, 3] = np.where(seen[f], 0.0, -1.0)
        points[:, 4] = np.where(seen[f], 0.0, -1.0)
        frames.append((points, empty_analog))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the library warns that a take has no analog channels
        writer.add_frames(frames)
        with open(path, "wb") as fh:
            writer.write(fh)


def _declared_frames(reader: c3d.Reader) -> int:
    """The frame count the header declares; past the header's 16-bit limit, the parameters' count.

    The header is the one count every writer keeps: PhoeniX's Dance.c3d holds the header's 499
    frames while its parameters say 500.
    """
    header = reader.header
    if int(header.last_frame) < 65535:
        return int(header.last_frame) - int(header.first_frame) + 1
    return int(reader.last_frame) - int(reader.first_frame) + 1


def _units(reader: c3d.Reader) -> str:
    param = reader.get("POINT:UNITS")
    if param is None:
        return "mm"
    text = param.string_value if hasattr(param, "string_value") else param.bytes.decode("latin-1")
    return str(text).strip().lower() or "mm"
