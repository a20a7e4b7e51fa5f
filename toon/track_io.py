"""Motor track files: CharToon's CSV "movie script" and the project's ``.npz``.

The movie script has a header ``time,BRL,BRC,...,HV`` and one row per frame: the time in
seconds, then the 21 motor values. Frames must be evenly spaced; the rate is read from them.
"""

from __future__ import annotations

import csv
import io
import json
import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from common import InputError, atomic_path
from common.errors import require_file
from common.limits import MAX_TAKE_BYTES, read_regular
from common.npz import NPZ_ERRORS, check_npz
from toon.motors import EXTRA_CODE, MOTOR_CODES
from toon.track import MotorTrack

_SUFFIXES = (".csv", ".npz")


def save_track(track: MotorTrack, path: str | os.PathLike) -> Path:
    """Write ``track`` to ``path`` (``.csv`` movie script or ``.npz``), atomically."""
    path = Path(path)
    if path.suffix.lower() not in _SUFFIXES:
        raise InputError(f"unknown motor track format {path.suffix!r} (use .csv or .npz)", path)
    with atomic_path(path) as tmp:
        if path.suffix.lower() == ".csv":
            tmp.write_text(_to_csv(track), encoding="utf-8")
        else:
            extra: dict[str, Any] = {} if track.confidence is None else {"confidence": track.confidence}
            if track.extra is not None:
                extra.update(extra_codes=np.array(track.extra_codes), extra=track.extra)
            with open(tmp, "wb") as fh:
                np.savez_compressed(fh, values=track.values, rate=np.float64(track.rate),
                                    codes=np.array(MOTOR_CODES), meta=json.dumps(track.meta), **extra)
    return path


def load_track(path: str | os.PathLike) -> MotorTrack:
    """Read a motor track written by :func:`save_track` (or any conforming movie script)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in _SUFFIXES:
        raise InputError(f"unknown motor track format {path.suffix!r} (use .csv or .npz)", path)
    require_file(path)
    if suffix == ".csv":
        return _from_csv(path)
    try:
        with open(path, "rb") as fh:
            check_npz(fh, path, "toonface motor track")
            with np.load(fh, allow_pickle=False) as z:
                codes = tuple(str(c) for c in z["codes"])
                conf = z["confidence"] if "confidence" in z.files else None
                meta = json.loads(str(z["meta"])) if "meta" in z.files else {}
                if conf is not None:
                    conf = conf[:, [codes.index(c) for c in MOTOR_CODES]]
                more = {"extra_codes": tuple(str(c) for c in z["extra_codes"]), "extra": z["extra"]} if (
                    "extra_codes" in z.files) else {}
                return MotorTrack.from_columns(codes, z["values"], float(z["rate"]), confidence=conf, meta=meta,
                                               **more)
    except InputError as exc:
        raise InputError(exc.message, path) from None
    except NPZ_ERRORS as exc:
        raise InputError(f"not a toonface motor track .npz ({type(exc).__name__}: {exc})", path) from None


def _to_csv(track: MotorTrack) -> str:
    buf = io.StringIO()
    buf.write(",".join(("time", *MOTOR_CODES, *track.extra_codes)) + "\n")
    table = np.column_stack([track.times, track.table()])
    np.savetxt(buf, table, delimiter=",", fmt="%.6f")
    return buf.getvalue()


def _from_csv(path: Path) -> MotorTrack:
    raw = read_regular(path, MAX_TAKE_BYTES, "motor track")
    try:
        if b"\x00" in raw[:65536]:
            raise UnicodeDecodeError("utf-8", raw, raw.index(b"\x00"), raw.index(b"\x00") + 1, "NUL byte")
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"binary data (byte {exc.start}), not a text movie script (time,BRL,...,HV)", path) from None
    rows = list(csv.reader(io.StringIO(text, newline="")))
    if not rows:
        raise InputError("empty file; expected a header time,BRL,...,HV", path)
    header = [h.strip() for h in rows[0]]
    if not header or header[0].lower() not in ("time", "time_s"):  # a lone "\r" made an empty header
        raise InputError(f'first column must be "time", got {header[0] if header else ""!r}', path, "line 1")
    codes = header[1:]
    unknown = [c for c in codes if c not in MOTOR_CODES and not re.fullmatch(EXTRA_CODE, c)]
    missing = [c for c in MOTOR_CODES if c not in codes]
    if unknown or missing or len(set(codes)) != len(codes):
        raise InputError(f"header must name the 21 motors once each (and a face's extra parameters, such as HT); "
                         f"unknown {unknown}, missing {missing}", path, "line 1")
    data = np.empty((len(rows) - 1, len(codes) + 1))
    for i, row in enumerate(rows[1:]):
        if len(row) != len(codes) + 1:
            raise InputError(f"expected {len(codes) + 1} fields, found {len(row)}", path, f"line {i + 2}")
        try:
            data[i] = [float(x) for x in row]
        except ValueError:
            raise InputError(f"not a number in {row!r}", path, f"line {i + 2}") from None
    if len(data) < 2:
        raise InputError("a movie script needs at least two frames to know its rate", path)
    times = data[:, 0]
    step = (times[-1] - times[0]) / (len(times) - 1)
    steps = np.diff(times)
    if step <= 0 or np.max(np.abs(steps - step)) > max(2e-6, 1e-3 * step):
        line = int(np.argmax(np.abs(steps - step))) + 3
        raise InputError("frame times are not evenly spaced", path, f"line {line}")
    rate = round(1.0 / step, 4)  # times are written with 6 decimals
    try:
        return MotorTrack.from_columns(codes, data[:, 1:], rate, meta={"source": str(path)})
    except InputError as exc:
        raise InputError(exc.message, path) from None
