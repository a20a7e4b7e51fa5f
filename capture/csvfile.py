"""CSV takes: Vicon Nexus "Trajectories" exports, wide marker tables and headerless tables.

* **Nexus** — a ``Trajectories`` line, the rate, subject-prefixed marker names every third
  column, ``Frame,Sub Frame,X,Y,Z...``, a units line, then rows; empty cells are gaps. Other
  sections (``Devices``, ``Model Outputs``) are skipped.
* **Wide** — a header of ``<marker>_x, <marker>_y[, <marker>_z]`` columns (also ``.x`` or
  `` X``), any separator (``,`` ``;`` tab ``|``), ``NA`` or empty cells for gaps, and a ``time``
  or ``time_s`` column in seconds, or a ``frame`` column with the rate given. Other columns
  (``Stimulustype``) are ignored and named in ``meta["ignored_columns"]``. Without z columns
  the take is planar (``dims=2``).
* **Headerless** — rows of numbers only, given ``labels`` and ``rate``: 3 columns per label
  (or 2 for planar data).

Units are millimetres unless ``units`` says otherwise (``cm``, ``m``, ``in`` or a number of
millimetres per unit): a CSV does not say its units, except Nexus's units line.
"""

from __future__ import annotations

import logging
import re
from pathlib import Path
from typing import Any

import numpy as np

from capture.markerset import MarkerSet, find_markerset
from capture.take import UNIT_MM, Take, unique_labels
from capture.textio import (
    check_rate,
    detect_separator,
    is_blank,
    is_number,
    numeric_rows,
    read_lines,
    split,
    times_from_column,
)
from common import InputError

log = logging.getLogger(__name__)

_AXIS = re.compile(r"^(?P<marker>.+?)[ _.:-](?P<axis>[xyzXYZ])$")
_TIME_NAMES = ("time", "time_s", "times", "t", "seconds", "time (s)")
_FRAME_NAMES = ("frame", "frames", "frame#", "frame_no", "frame number")


def read_csv(path: Path, rate: float | None = None, labels: list[str] | None = None,
             units: str | float | None = None, markerset: MarkerSet | None = None) -> Take:
    """Read a CSV take; see the module docstring for the layouts and options. ``markerset``: the
    set the take is for (one the user named), whose ``[tables]`` rate and units stand for what
    the table and the options leave unsaid, as a built-in set's do for the labels it knows."""
    lines = read_lines(path)
    first = next((i for i, line in enumerate(lines) if line.strip().strip(",;|")), None)  # any whitespace
    if first is None:
        raise InputError("no data (only blank lines)", path)
    cells = split(lines[first], detect_separator(lines[first]))
    if cells and cells[0].lower() == "trajectories":
        return _read_nexus(path, lines, first, units)
    sep = detect_separator(lines[first])
    header = split(lines[first], sep)
    if labels is not None or all(is_number(c) for c in header if c):
        return _read_headerless(path, lines, sep, rate, labels, units, markerset)
    return _read_wide(path, lines, first, sep, header, rate, units, markerset)


def _read_wide(path: Path, lines: list[str], first: int, sep: str | None, header: list[str],
               rate: float | None, units: str | float | None, markerset: MarkerSet | None = None) -> Take:
    lowered = [h.lower() for h in header]
    time_col = next((lowered.index(n) for n in _TIME_NAMES if n in lowered), None)
    frame_col = next((lowered.index(n) for n in _FRAME_NAMES if n in lowered), None)
    markers: dict[str, dict[str, int]] = {}
    ignored = []
    for c, name in enumerate(header):
        match = _AXIS.match(name) if c not in (time_col, frame_col) else None
        if match is None:
            if name and c not in (time_col, frame_col):
                ignored.append(name)
            continue
        axes = markers.setdefault(match["marker"], {})
        axis = match["axis"].lower()
        if axis in axes:
            raise InputError(f'duplicate column "{name}" (marker "{match["marker"]}" axis {axis} twice)', path,
                             f"line {first + 1}")
        axes[axis] = c
    markers = {m: a for m, a in markers.items() if "x" in a or "y" in a}
    if not markers:
        raise InputError(f"no marker columns (<marker>_x, _y, _z) in the header; read it as separated by "
                         f"{_describe(sep)}", path, f"line {first + 1}")
    incomplete = [m for m, a in markers.items() if not ("x" in a and "y" in a)]
    if incomplete:
        raise InputError(f"markers without both x and y columns: {incomplete[:5]}", path, f"line {first + 1}")
    has_z = [("z" in a) for a in markers.values()]
    if any(has_z) and not all(has_z):
        flat = [m for m, a in markers.items() if "z" not in a][:5]
        raise InputError(f"some markers have z columns and some do not: {flat}",
                         path, f"line {first + 1}")
    dims = 3 if all(has_z) else 2
    clock = time_col if time_col is not None else frame_col  # the column that says when each row is
    from_set = _set_defaults(list(markers), time_col is None and rate is None, units is None, markerset)
    rate, units = from_set.get("rate", rate), from_set.get("units", units)
    if time_col is None and rate is None:
        what = (f'a "{header[frame_col]}" column but no time column' if frame_col is not None
                else "no time or frame column")
        raise MissingRate(f"{what}: give the frame rate (--rate)", path)
    rows = _data_rows(lines, first + 1, sep, path)
    columns, names = ([clock], [header[clock]]) if clock is not None else ([], [])
    for a in markers.values():
        for axis in "xyz"[:dims]:
            columns.append(a[axis])
            names.append(header[a[axis]])
    data = numeric_rows(rows, columns, names, path)  # one pass over the rows for every column
    if clock is not None:
        clock_values, data = data[:, 0], data[:, 1:]
    positions = np.zeros((len(rows), len(markers), 3))
    positions[:, :, :dims] = data.reshape(len(rows), len(markers), dims)
    positions[np.isnan(positions).any(axis=2)] = np.nan
    times: np.ndarray | None = None  # None: frame / rate
    if time_col is not None:
        times, implied = times_from_column(clock_values, path, header[time_col])
        rate = check_rate(rate if rate is not None else implied, path,
                          "rate" if rate is not None else f'the rate implied by column "{header[time_col]}"')
    else:
        rate = check_rate(rate, path)
        if frame_col is not None:
            times, _ = times_from_column(clock_values / rate, path, header[frame_col])
    clean, renamed = unique_labels(list(markers))
    meta: dict[str, Any] = {"source": "csv", "layout": "wide", "file": path.name, "separator": _describe(sep)}
    if ignored:
        meta["ignored_columns"] = ignored
    if from_set:
        meta["defaults_from_markerset"] = from_set
    if renamed:
        meta["renamed"] = renamed
    if times is None:
        times = np.arange(len(rows)) / rate
    scale = _mm_per_unit(units, path)
    meta["units"] = units_meta(scale, "marker set " + from_set["markerset"] if "units" in from_set
                               else "given" if units is not None else "assumed")
    return Take(positions * scale, clean, rate, times=times, dims=dims, meta=meta)


def _read_headerless(path: Path, lines: list[str], sep: str | None, rate: float | None,
                     labels: list[str] | None, units: str | float | None, markerset: MarkerSet | None = None) -> Take:
    if not labels:
        raise InputError("a table without a header needs the marker names (--labels A,B,C) and --rate", path)
    from_set = _set_defaults(list(labels), rate is None, units is None, markerset)
    rate, units = from_set.get("rate", rate), from_set.get("units", units)
    if rate is None:
        raise MissingRate("a table without a header needs the frame rate (--rate)", path)
    rate = check_rate(rate, path)
    rows = _data_rows(lines, 0, sep, path)
    width = len(rows[0][1])
    if width not in (2 * len(labels), 3 * len(labels)):
        raise InputError(f"{width} columns for {len(labels)} labels; expected {3 * len(labels)} (x, y, z each) "
                         f"or {2 * len(labels)} (x, y)", path, f"line {rows[0][0]}")
    dims = width // len(labels)
    ragged = next(((n, len(c)) for n, c in rows if len(c) != width), None)
    if ragged:
        raise InputError(f"{ragged[1]} columns where the first row has {width}", path, f"line {ragged[0]}")
    names = [f"{m}_{a}" for m in labels for a in "xyz"[:dims]]
    data = numeric_rows(rows, list(range(width)), names, path)
    positions = np.zeros((len(rows), len(labels), 3))
    positions[:, :, :dims] = data.reshape(len(rows), len(labels), dims)
    positions[np.isnan(positions).any(axis=2)] = np.nan
    scale = _mm_per_unit(units, path)
    meta: dict[str, Any] = {"source": "csv", "layout": "headerless", "file": path.name, "separator": _describe(sep),
                            "units": units_meta(scale, "marker set " + from_set["markerset"] if "units" in from_set
                                                else "given" if units is not None else "assumed")}
    return Take(positions * scale, tuple(labels), rate, dims=dims, meta=meta)


def _read_nexus(path: Path, lines: list[str], first: int, units: str | float | None) -> Take:
    if len(lines) < first + 5:
        raise InputError("a Trajectories section needs a rate, names, columns and units lines", path)
    sep = detect_separator(lines[first + 2]) or ","
    rate_cells = split(lines[first + 1], sep)
    try:
        rate = float(rate_cells[0])
    except ValueError:
        raise InputError(f"expected the frame rate, got {rate_cells[0]!r}", path, f"line {first + 2}") from None
    rate = check_rate(rate, path, f"the rate on line {first + 2}")
    names = split(lines[first + 2], sep)
    labels = [(c, names[c]) for c in range(2, len(names)) if names[c]]
    if not labels:
        raise InputError("no marker names after Trajectories", path, f"line {first + 3}")
    unit_cells = split(lines[first + 4], sep)
    file_units = next((u for u in unit_cells[2:] if u), "mm").lower()
    if units is None and file_units not in UNIT_MM:
        raise InputError(f'unknown units "{file_units}"', path, f"line {first + 5}")
    rows = _data_rows(lines, first + 5, sep, path, stop_at_blank=True)
    columns = [c + k for c, _ in labels for k in range(3)]
    data = numeric_rows(rows, [0, *columns], ["Frame"] + [f"{m}.{a}" for _, m in labels for a in "XYZ"], path,
                        short_ok=True)
    frames = data[:, 0]
    times, _ = times_from_column((frames - frames[0]) / rate, path, "Frame")
    positions = data[:, 1:].reshape(len(rows), len(labels), 3)
    positions[np.isnan(positions).any(axis=2)] = np.nan
    scale = _mm_per_unit(units, path) if units is not None else UNIT_MM[file_units]
    clean, renamed = unique_labels([m for _, m in labels])
    meta: dict[str, Any] = {"source": "csv", "layout": "nexus", "file": path.name, "units_in_file": file_units,
                            "units": units_meta(scale, "given" if units is not None else "file")}
    if renamed:
        meta["renamed"] = renamed
    return Take(positions * scale, clean, rate, times=times, meta=meta)


def write_csv(take: Take, path: Path) -> None:
    """Write ``take`` as a wide CSV: ``frame,time_s,<marker>_x,_y[,_z]`` in mm; gaps empty."""
    axes = "xyz"[: take.dims]
    header = ["frame", "time_s"] + [f"{m}_{a}" for m in take.labels for a in axes]
    flat = take.positions[:, :, : take.dims].reshape(take.frames, -1)
    out = [",".join(header)]
    for f in range(take.frames):
        cells = ["" if v != v else repr(float(v)) for v in flat[f]]
        out.append(f"{f},{float(take.times[f])!r}," + ",".join(cells))
    path.write_text("\n".join(out) + "\n", encoding="utf-8")


def _data_rows(lines: list[str], start: int, sep: str | None, path: Path,
               stop_at_blank: bool = False) -> list[tuple[int, list[str]]]:
    rows: list[tuple[int, list[str]]] = []
    for i in range(start, len(lines)):
        if is_blank(lines[i], sep):
            if stop_at_blank and rows:
                break
            continue
        rows.append((i + 1, split(lines[i], sep)))
    if not rows:
        raise InputError("no data rows (zero frames)", path)
    return rows


class MissingRate(InputError):
    """A table that does not say its frame rate, read without one: what a user can answer (the
    studio asks for it)."""


def units_meta(mm_per_unit: float, origin: str) -> dict[str, Any]:
    """A take's ``meta["units"]``: the millimetres per unit it was read with, and who said so
    (``"given"``, ``"file"``, ``"marker set NAME"``, or ``"assumed"`` for a table that does not
    say, read as millimetres). A take without it carries units its file stated."""
    return {"mm_per_unit": mm_per_unit, "from": origin}


def _mm_per_unit(units: str | float | None, path: Path) -> float:
    if units is None:
        return 1.0
    if isinstance(units, (int, float)):
        value = float(units)
    elif units.strip().lower() in UNIT_MM:
        return UNIT_MM[units.strip().lower()]
    else:
        try:
            value = float(units)
        except ValueError:
            raise InputError(f'unknown units "{units}" (mm, cm, m, in, or millimetres per unit)', path) from None
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"units must be a positive number of millimetres per unit, got {units!r}", path)
    return value


def _set_defaults(names: list[str], need_rate: bool, need_units: bool,
                  given: MarkerSet | None = None) -> dict[str, Any]:
    """The rate and units a table's marker set declares for what the table and the options leave
    unsaid (``{"markerset": ..., "rate": ..., "units": ...}``; empty when nothing is taken): the
    ``given`` set where it names half the table's markers, else the built-in set that does."""
    if not (need_rate or need_units):
        return {}
    markerset = given if given is not None and len(given.match(names)) >= len(names) / 2 else find_markerset(names)
    if markerset is None:
        return {}
    taken: dict[str, Any] = {}
    if need_rate and markerset.table_rate is not None:
        taken["rate"] = markerset.table_rate
    if need_units and markerset.table_units is not None:
        taken["units"] = markerset.table_units
    if taken:
        log.info("rate/units of marker set %s: %s", markerset.name, taken)
        taken["markerset"] = markerset.name
    return taken


def _describe(sep: str | None) -> str:
    return {",": "commas", ";": "semicolons", "\t": "tabs", "|": "bars", None: "spaces"}[sep]
