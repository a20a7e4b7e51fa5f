"""Shared parsing for the text take formats (TRC, CSV): lines, separators and numeric cells.

Every problem is an :class:`InputError` naming the file and the line (1-based, as an editor shows
it), and for a bad cell its column.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from common import InputError
from common.limits import MAX_TAKE_BYTES, read_regular

#: Cells that mean "not seen" in the exports we read.
MISSING_CELLS = frozenset({"", "na", "nan", "n/a", "null", "none", "-", "?"})
SEPARATORS = (",", ";", "\t", "|")


def read_lines(path: Path) -> list[str]:
    """The file's lines without line ends; refuses empty and binary files."""
    raw = read_regular(path, MAX_TAKE_BYTES, "text take")
    if not raw:
        raise InputError("empty file (0 bytes)", path)
    if b"\x00" in raw[:65536]:
        raise InputError("binary data in what should be a text file", path)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return text.splitlines()


def detect_separator(line: str) -> str | None:
    """The separator of a header or data line: the most frequent of , ; tab |; ``None``: whitespace."""
    counts = {sep: line.count(sep) for sep in SEPARATORS}
    best = max(counts, key=lambda s: counts[s])
    return best if counts[best] else None


def split(line: str, sep: str | None) -> list[str]:
    """Cells of ``line``, stripped (and unquoted); ``sep=None`` splits on runs of whitespace."""
    cells = line.split(sep) if sep is not None else line.split()
    return [c.strip().strip('"').strip() for c in cells]


def is_blank(line: str, sep: str | None) -> bool:
    """A line with nothing but separators and spaces."""
    return not any(split(line, sep))


def is_number(cell: str) -> bool:
    """Whether ``cell`` reads as a finite number."""
    try:
        return math.isfinite(float(cell))
    except ValueError:
        return False


def numeric_rows(rows: list[tuple[int, list[str]]], columns: list[int], names: list[str], path: Path,
                 short_ok: bool = False) -> np.ndarray:
    """Parse the cells ``columns`` of each ``(line number, cells)`` row; missing cells are NaN.

    Parameters
    ----------
    rows : list of (int, list of str)
        1-based line numbers and the split cells of each data line.
    columns : list of int
        Which cells to read, in output order.
    names : list of str
        The column names, for errors.
    short_ok : bool
        Whether a row may end early (its missing cells become NaN), as some exporters write rows
        whose last markers are unseen.

    Returns
    -------
    ndarray of float64, shape (len(rows), len(columns))
    """
    out = np.full((len(rows), len(columns)), np.nan)
    width = max(columns) + 1 if columns else 0
    for r, (line_no, cells) in enumerate(rows):
        if len(cells) < width and not short_ok:
            raise InputError(f"{len(cells)} cells where the header has at least {width}", path, f"line {line_no}")
        for k, c in enumerate(columns):
            if c >= len(cells):
                break
            cell = cells[c]
            if cell.lower() in MISSING_CELLS:
                continue
            try:
                value = float(cell)
            except ValueError:
                raise InputError(f'column "{names[k]}": not a number: {cell[:40]!r}', path,
                                 f"line {line_no}") from None
            if not math.isfinite(value):
                raise InputError(f'column "{names[k]}": {cell!r} is not a finite number', path, f"line {line_no}")
            out[r, k] = value
    return out


#: The frame rates a take may have, Hz: a frame a minute to 100 kHz (a time column of 1e300-second
#: steps made a rate of 1e-300 Hz and a take of 1e302 seconds).
RATE_BOUNDS = (1 / 60, 100_000.0)


def check_rate(rate: float | None, path: Path, where: str = "rate") -> float:
    """A frame rate that makes sense (:data:`RATE_BOUNDS`), else an error naming where it came from."""
    low, high = RATE_BOUNDS
    if not (isinstance(rate, (int, float)) and math.isfinite(rate) and low <= rate <= high):
        raise InputError(f"{where} is {rate:g}; expected frames per second from {low:.3g} (a frame a minute) to "
                         f"{high:g}" if isinstance(rate, (int, float)) else f"{where} is {rate!r}", path)
    return float(rate)


def times_from_column(values: np.ndarray, path: Path, column: str) -> tuple[np.ndarray, float]:
    """Seconds from a time column and the rate they imply (the mean step)."""
    if np.isnan(values).any():
        raise InputError(f'column "{column}" has empty cells; every row needs a time', path)
    if len(values) > 1:
        steps = np.diff(values)
        if not np.all(steps > 0):
            bad = int(np.argmax(~(steps > 0))) + 1
            raise InputError(f'column "{column}" must increase from row to row (data row {bad + 1} does not)', path)
        # The mean step, to 10 significant digits: exporters round times (60 Hz as 0.016667 s),
        # and a rate written as frame / rate must read back as the same number.
        return values, float(f"{(len(values) - 1) / (values[-1] - values[0]):.10g}")
    return values, math.nan
