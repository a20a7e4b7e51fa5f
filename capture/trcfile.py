"""TRC takes (OpenSim, Cortex, Motive, Vicon exports): tab- or comma-delimited text.

Layout: a ``PathFileType`` line; a line of header names (``DataRate CameraRate NumFrames
NumMarkers Units ...``) and one of their values; ``Frame# Time <marker> <blank> <blank> ...``; a
line of ``X1 Y1 Z1 ...``; then one row per frame, perhaps after blank lines. Empty cells are
gaps. The reader is lenient where real exporters are sloppy: trailing separators, blank lines,
rows that stop before their last unseen markers. A header whose frame or marker count disagrees
with the data is reported as a warning with both counts, not refused.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import numpy as np

from capture.take import UNIT_MM, Take, unique_labels
from capture.textio import check_rate, detect_separator, is_blank, numeric_rows, read_lines, split
from common import InputError

log = logging.getLogger("toonface")
HEADER_LINES = 5


def read_trc(path: Path) -> Take:
    """Read a TRC file as a :class:`Take` in millimetres."""
    lines = read_lines(path)
    if len(lines) < HEADER_LINES or not lines[0].lstrip('"').startswith("PathFileType"):
        raise InputError("not a TRC file (the first line must start with PathFileType)", path, "line 1")
    sep = detect_separator(lines[0]) or "\t"
    keys, values = split(lines[1], sep), split(lines[2], sep)
    header = {k: v for k, v in zip(keys, values, strict=False) if k}  # a short row of values is reported below
    for needed in ("DataRate", "NumFrames", "NumMarkers", "Units"):
        if needed not in header:
            raise InputError(f"the header has no {needed}", path, "line 2")
    try:
        rate = float(header["DataRate"])
        claimed_frames, claimed_markers = int(float(header["NumFrames"])), int(float(header["NumMarkers"]))
    except (ValueError, OverflowError):
        raise InputError(f"DataRate, NumFrames and NumMarkers must be numbers, got {values[:4]}", path,
                         "line 3") from None
    rate = check_rate(rate, path, "DataRate")
    units = header["Units"].strip().lower()
    if units not in UNIT_MM:
        raise InputError(f'unknown Units "{header["Units"]}" (known: {", ".join(sorted(UNIT_MM))})', path, "line 3")
    names = split(lines[3], sep)
    if len(names) < 3 or names[0].lower() not in ("frame#", "frame") or names[1].lower() != "time":
        raise InputError("expected the column line Frame#, Time, <markers>", path, "line 4")
    labels = [names[c] for c in range(2, len(names), 3) if names[c]]
    if not labels:
        raise InputError("no marker names in the column line", path, "line 4")
    rows = [(i + 1, split(line, sep)) for i, line in enumerate(lines[HEADER_LINES:], HEADER_LINES)
            if not is_blank(line, sep)]
    if not rows:
        raise InputError("no data rows (zero frames)", path)
    columns = [1] + [2 + c for c in range(3 * len(labels))]
    column_names = ["Time"] + [f"{m}.{a}" for m in labels for a in "XYZ"]
    data = numeric_rows(rows, columns, column_names, path, short_ok=True)
    warnings = []
    if claimed_frames != len(rows):
        warnings.append(f"header says NumFrames {claimed_frames} but the file holds {len(rows)} rows")
    if claimed_markers != len(labels):
        warnings.append(f"header says NumMarkers {claimed_markers} but the column line names {len(labels)}")
    for text in warnings:
        log.warning("%s: %s", path, text)
    times = data[:, 0]
    if np.isnan(times).any() or (len(times) > 1 and not np.all(np.diff(times) > 0)):
        times = np.arange(len(rows)) / rate  # a broken Time column: fall back to frame / DataRate
        warnings.append("the Time column is incomplete or not increasing; times taken from DataRate")
    positions = data[:, 1:].reshape(len(rows), len(labels), 3) * UNIT_MM[units]
    clean, renamed = unique_labels(labels)
    meta: dict[str, Any] = {"source": "trc", "file": path.name, "units_in_file": units}
    if renamed:
        meta["renamed"] = renamed
    if warnings:
        meta["warnings"] = warnings
    return Take(positions, clean, rate, times=times, meta=meta)


def write_trc(take: Take, path: Path, name: str | None = None) -> None:
    """Write ``take`` as a tab-delimited TRC in millimetres; gaps are empty cells. ``name`` is the
    file name the header gives (``path``'s by default; the final name where ``path`` is a
    temporary file that will be renamed)."""
    n = take.markers
    out = [
        f"PathFileType\t4\t(X/Y/Z)\t{name or path.name}",
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames",
        f"{take.rate!r}\t{take.rate!r}\t{take.frames}\t{n}\tmm\t{take.rate!r}\t1\t{take.frames}",
        "Frame#\tTime\t" + "\t".join(f"{m}\t\t" for m in take.labels).rstrip("\t"),
        "\t\t" + "\t".join(f"X{k}\tY{k}\tZ{k}" for k in range(1, n + 1)),
        "",
    ]
    flat = take.positions.reshape(take.frames, 3 * n)
    for f in range(take.frames):
        cells = ["" if v != v else repr(float(v)) for v in flat[f]]
        out.append(f"{f + 1}\t{float(take.times[f])!r}\t" + "\t".join(cells))
    path.write_text("\n".join(out) + "\n", encoding="utf-8")
