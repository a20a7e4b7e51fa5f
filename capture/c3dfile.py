"""C3D takes, read through the ``c3d`` library (py-c3d), with ``ezc3d`` as a second reader.

What the reader makes of a C3D file:

* integer and floating-point storage; Intel, DEC and SGI/MIPS (big-endian) processor types; the
  header's section pointers (the library follows them); a non-integer ``POINT:RATE``.
* integer samples multiplied by ``POINT:SCALE``; coordinates converted from ``POINT:UNITS``
  (mm, cm, m, in; padded with spaces, or stored as one unit per row as some exporters do) to
  millimetres.
* a negative residual word marks a gap, which becomes NaN; so does a sample at exactly
  (0, 0, 0) with a non-negative residual, the way some exporters write "not seen" (counted in
  ``meta["zero_gaps"]``).
* points that Vicon Plug-in Gait and similar models store as points but are not markers (the
  labels listed in ``POINT:ANGLES``, ``FORCES``, ``MOMENTS``, ``POWERS``, ``REACTIONS``) are
  left out and named in ``meta["modelled_points"]``.
* analog channels are skipped (their count is kept in ``meta``).
* labels are trimmed; an empty label becomes ``M001`` and so on, and a repeated one gets ``#2``.
  Both changes are listed in ``meta["renamed"]``.

A file the ``c3d`` library refuses for a group with a parameter named twice (as Plug-in Gait
exports have) is read again with ``ezc3d``, which takes the first; ``meta["reader"]`` says
which read it. ``ezc3d`` cannot read SGI/MIPS files nor a float ``ANALOG:OFFSET``, which the
``c3d`` library can. The libraries' warnings about vendor quirks (a ``DATA_START`` of 0, missing
optional parameters, a data section that ends early) are kept in ``meta["warnings"]``.
"""

from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import c3d
import numpy as np

from capture.take import UNIT_MM, Take, unique_labels
from common import InputError

_PARAMETER_MAGIC = 0x50  # the second byte of every C3D file
#: POINT parameters listing labels of modelled outputs stored as points (not markers).
MODELLED_GROUPS = ("ANGLES", "FORCES", "MOMENTS", "POWERS", "REACTIONS")
log = logging.getLogger(__name__)


@dataclass
class _Raw:
    """What a C3D library read: samples ``(F, N, 4)`` in file units, the 4th the residual (< 0: gap)."""

    rate: float
    labels: list[str]
    units: str
    samples: np.ndarray
    declared: int
    meta: dict[str, Any]
    modelled: dict[str, list[str]] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


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
    try:
        raw = _read_with_c3d(path)
    except Exception as first:  # noqa: BLE001 - only library parsing is inside; any failure means a bad file
        # Only the one quirk the second library is known to take goes to it: a corrupt file
        # could make a C++ reader allocate or crash, where the first fails cleanly.
        if not (isinstance(first, KeyError) and "Parameter already exists" in str(first)):
            raise InputError(f"corrupt or truncated C3D file ({type(first).__name__}: {first})", path) from None
        try:
            raw = _read_with_ezc3d(path)
        except Exception:  # noqa: BLE001 - as above, for the second library
            raise InputError(f"corrupt or truncated C3D file ({type(first).__name__}: {first})", path) from None
        raw.warnings.append(f"read with ezc3d: the c3d library stopped at a parameter named twice ({first})")
    return _take(raw, path, allow_truncated)


def _take(raw: _Raw, path: Path, allow_truncated: bool) -> Take:
    """The take from what a library read: units, gaps, modelled points and truncation handled."""
    rate, labels, data = raw.rate, raw.labels, raw.samples
    if not np.isfinite(rate) or rate <= 0 or rate > 1e6:
        raise InputError(f"POINT:RATE is {_plain(rate)}; expected a positive frame rate", path)
    if not len(data):
        raise InputError("no point frames in the file", path)
    if len(data) < raw.declared:
        ends = f"the file ends early: it holds {len(data)} of the {raw.declared} frames its header declares"
        if not allow_truncated:
            raise InputError(f"{ends} (--allow-truncated reads what is there)", path)
        log.warning("%s: %s; reading those", path, ends)
        raw.warnings.append(ends)
    units = _unit_name(raw.units)
    if units not in UNIT_MM:
        raise InputError(f'unknown POINT:UNITS "{raw.units.strip()}" (known: {", ".join(sorted(UNIT_MM))})', path)
    if data.shape[1] != len(labels):
        labels = (labels + [""] * data.shape[1])[: data.shape[1]]
    gap = data[:, :, 3] < 0
    zeros = ~gap & np.all(data[:, :, :3] == 0.0, axis=2)
    positions = data[:, :, :3] * UNIT_MM[units]
    positions[gap | zeros] = np.nan
    stripped = [label.strip() for label in labels]
    modelled = {group: [x for x in names if x.strip() in stripped] for group, names in raw.modelled.items()}
    modelled = {group: names for group, names in modelled.items() if names}
    left_out = {x.strip() for names in modelled.values() for x in names}
    keep = [i for i, label in enumerate(stripped) if label not in left_out or not label]
    clean, renamed = unique_labels([labels[i] for i in keep])
    meta: dict[str, Any] = {"source": "c3d", "file": path.name, **raw.meta, "units_in_file": units}
    if zero_gaps := int(zeros[:, keep].sum()):
        meta["zero_gaps"] = zero_gaps
    if modelled:
        meta["modelled_points"] = modelled
    if renamed:
        meta["renamed"] = renamed
    if raw.warnings:
        meta["warnings"] = raw.warnings
    return Take(positions[:, keep], clean, rate, meta=meta)


def _read_with_c3d(path: Path) -> _Raw:
    with open(path, "rb") as fh, warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        reader = c3d.Reader(fh)
        scale = float(reader.point_scale)
        raw = _Raw(float(reader.point_rate), [str(x) for x in reader.point_labels], _units(reader),
                   np.empty((0, 0, 4)), _declared_frames(reader),
                   {"reader": "c3d", "processor": str(getattr(reader, "proc_type", "unknown")),
                    "storage": "float" if scale < 0 else "integer", "point_scale": abs(scale),
                    "analog_channels_skipped": int(reader.analog_used)})
        for group in MODELLED_GROUPS:
            param = reader.get(f"POINT:{group}")
            if param is not None:
                raw.modelled[group] = _strings(param)
        frames = [points[:, :4].copy() for _, points, _ in reader.read_frames(copy=False, check_nan=True)]
    raw.samples = np.stack(frames).astype(np.float64) if frames else np.empty((0, len(raw.labels), 4))
    raw.warnings = [str(w.message).split("\n")[0].strip() for w in seen if "No analog data" not in str(w.message)]
    return raw


def _read_with_ezc3d(path: Path) -> _Raw:
    import ezc3d  # the second reader, loaded only for the files the first refuses

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        doc = ezc3d.c3d(str(path))
    point = doc["parameters"]["POINT"]
    header = doc["header"]["points"]
    values = doc["data"]["points"]  # (4, N, F): x, y, z, 1, NaN where the residual is negative
    residuals = doc["data"]["meta_points"]["residuals"][0]  # (N, F)
    samples = np.concatenate([np.transpose(values[:3], (2, 1, 0)), residuals.T[:, :, None]], axis=2)
    samples[np.isnan(samples[:, :, :3]).any(axis=2), 3] = -1.0
    scale = float(np.ravel(point.get("SCALE", {}).get("value", [-1.0]))[0])
    raw = _Raw(float(header["frame_rate"]), [str(x) for x in point["LABELS"]["value"]],
               " ".join(str(u) for u in point.get("UNITS", {}).get("value", ["mm"])), samples,
               int(header["last_frame"]) - int(header["first_frame"]) + 1,
               {"reader": "ezc3d", "storage": "float" if scale < 0 else "integer", "point_scale": abs(scale),
                "analog_channels_skipped": int(doc["header"]["analogs"]["size"])})
    for group in MODELLED_GROUPS:
        if group in point:
            raw.modelled[group] = [str(x) for x in point[group]["value"]]
    return raw


def _strings(param: Any) -> list[str]:
    """A character parameter's strings: one per row of a 2-D array, or the one string."""
    if hasattr(param, "string_array"):
        with np.errstate(all="ignore"):
            try:
                return [str(x).strip() for x in np.ravel(param.string_array)]
            except (ValueError, TypeError):
                pass
    return [str(param.string_value).strip()]


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
    """``POINT:UNITS`` as stored, every row of it (see :func:`_unit_name`)."""
    param = reader.get("POINT:UNITS")
    if param is None:
        return "mm"
    return bytes(param.bytes).decode("latin-1")


def _unit_name(text: str) -> str:
    """The unit a ``POINT:UNITS`` names, however it is stored: ``"mm  "``, ``" cm "``, or one per
    row (``"mm  mm  mm  "``), padded with NUL bytes or other control characters (``"mm\\0\\0"``, as
    some exporters write it); an empty value means millimetres."""
    words = "".join(c if c.isprintable() else " " for c in text).lower().split()
    if not words:
        return "mm"
    return words[0] if len(set(words)) == 1 else " ".join(words)


def _plain(value: object) -> str:
    """A number as a user writes it (``0``, ``nan``), not as numpy spells it (``np.float32(0.0)``)."""
    try:
        return f"{float(value):g}"  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return repr(value)

