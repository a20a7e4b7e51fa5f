"""Take files: C3D, TRC, CSV and the project's own ``.npz``, chosen by suffix.

``load_take`` reads any of them; ``save_take`` writes any of them atomically. Every format
round-trips: read -> write -> read gives equal positions, labels, rate and (except C3D, which
stores only a rate) times. Only ``.npz`` keeps a take's channels (a markerless tracker's
blendshape scores); :func:`dropped_channels` words what another format drops.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from capture.c3dfile import read_c3d, write_c3d
from capture.csvfile import read_csv, write_csv
from capture.cues import cues_take, is_cue_table
from capture.markerset import MarkerSet
from capture.sources import SOUND_SUFFIXES
from capture.take import Take
from capture.trcfile import read_trc, write_trc
from capture.voice_take import read_voice
from common import InputError, atomic_path
from common.errors import require_file
from common.npz import NPZ_ERRORS, check_npz

NPZ_FORMAT = "toonface.take/1"
READABLE = (".c3d", ".trc", ".csv", ".tsv", ".txt", ".npz")
WRITABLE = (".c3d", ".trc", ".csv", ".npz")
_TABLES = (".csv", ".tsv", ".txt")


def _write_npz(take: Take, path: Path) -> None:
    with open(path, "wb") as fh:
        np.savez_compressed(fh, format=NPZ_FORMAT, positions=take.positions, labels=np.array(take.labels),
                            rate=np.float64(take.rate), times=take.times, dims=np.int64(take.dims),
                            meta=json.dumps(take.meta), channels=take.channels,
                            channel_names=np.array(take.channel_names, dtype=str))


def _read_npz(path: Path) -> Take:
    try:
        # np.load leaks the handle of a file it opened itself when the zip is corrupt: open it here.
        with open(path, "rb") as fh:
            check_npz(fh, path, "toonface take")
            with np.load(fh, allow_pickle=False) as z:
                if not hasattr(z, "files"):
                    raise InputError("a single .npy array, not a toonface take archive", path)
                if "format" not in z.files or str(z["format"]) != NPZ_FORMAT:
                    raise InputError(f'not a toonface take (missing format "{NPZ_FORMAT}")', path)
                channels = ((z["channels"], tuple(str(x) for x in z["channel_names"])) if "channels" in z.files
                            else (np.empty((len(z["times"]), 0)), ()))  # written before takes had channels
                return Take(z["positions"], tuple(str(x) for x in z["labels"]), float(z["rate"]),
                            times=z["times"], dims=int(z["dims"]), meta=_npz_meta(json.loads(str(z["meta"])), path),
                            channels=channels[0], channel_names=channels[1])
    except InputError as exc:
        raise InputError(exc.message, path) from None
    except NPZ_ERRORS as exc:
        raise InputError(f"not a readable .npz take ({type(exc).__name__}: {exc})", path) from None


def _npz_meta(meta: dict, path: Path) -> dict:
    """A take's meta as read back: the file is this one; units a user gave when the take was
    first read are now the file's (it holds millimetres as they made them), while units the first
    file left unsaid stay an assumption (``meta["units"]``, :mod:`capture.csvfile`)."""
    units = meta.get("units")
    if isinstance(units, dict) and units.get("from") in ("given", "inferred"):
        meta["units"] = {**units, "mm_per_unit": 1.0, "from": "file"}
    elif isinstance(units, dict):
        meta["units"] = {**units, "mm_per_unit": 1.0}
    return {**meta, "file": path.name}


def load_take(path: str | os.PathLike, rate: float | None = None, labels: list[str] | None = None,
              units: str | float | None = None, allow_truncated: bool = False,
              markerset: MarkerSet | None = None, words: str | None = None, listen: str | None = None) -> Take:
    """Read a take file, choosing the reader by suffix.

    Parameters
    ----------
    path : path-like
        ``.c3d``, ``.trc``, ``.csv`` (also ``.tsv``, ``.txt``) or ``.npz``.
    rate, labels, units
        For CSV tables only, which may not say them (see :mod:`capture.csvfile`): the frame rate
        in Hz, the marker names of a headerless table, and the units (``cm`` or millimetres per
        unit). The other formats carry their own; giving these for them is an error.
    allow_truncated
        Read a C3D file that ends before the last frame its header declares (with a warning in
        ``meta["warnings"]``); by default such a file is refused.
    markerset : MarkerSet, optional
        The set a CSV table is for (one the user named): its ``[tables]`` rate and units stand
        for what the table and the options leave unsaid.
    words : str, optional
        A voice's words (a sound file only): aligned with the sound (:mod:`capture.voice`).
    listen : str, optional
        How a voice is heard without words (:data:`capture.voice_take.LISTEN_MODES`; ``sound`` by default).

    Raises
    ------
    InputError
        Naming the file and what is wrong with it.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if (words is not None or listen is not None) and suffix not in SOUND_SUFFIXES:
        option = "words (--text) are" if words is not None else "--listen is"
        raise InputError(f"{option} for a voice: a sound file such as .wav", path)
    if suffix in (".json", ".xml") or (suffix == ".tsv" and is_cue_table(path)):  # Rhubarb's mouth cues
        require_file(path)
        return cues_take(path)
    if suffix in SOUND_SUFFIXES:  # a voice: its mouth shapes (capture/voice.py)
        require_file(path)
        given = [name for name, value in (("rate", rate), ("labels", labels), ("units", units)) if value is not None]
        if given:
            raise InputError(f"a voice has no {', '.join(given)} to give; those options are for CSV tables", path)
        return read_voice(path, words, listen or "sound")
    if suffix not in READABLE:
        from capture.sources import VIDEO_SUFFIXES

        if suffix in VIDEO_SUFFIXES:  # the commands track it; a program says so
            raise InputError("a video, not a take file: capture.takefile.load_take_or_video tracks its face", path)
        moho = "; Moho's .dat switch data is written only: it keeps frames, not seconds" if suffix == ".dat" else ""
        raise InputError(f"unknown take format {path.suffix or '(no suffix)'!r} (readable: {', '.join(READABLE)}, "
                         f"Rhubarb's mouth cues: .tsv, .json, .xml, and a voice: "
                         f"{', '.join(sorted(SOUND_SUFFIXES))}{moho})", path)
    require_file(path)
    given = [name for name, value in (("rate", rate), ("labels", labels), ("units", units)) if value is not None]
    if given and suffix not in _TABLES:
        raise InputError(f"a {suffix} take carries its own {', '.join(given)}; those options are for CSV tables",
                         path)
    try:
        if suffix in _TABLES:
            return read_csv(path, rate=rate, labels=labels, units=units, markerset=markerset)
        if suffix == ".c3d":
            return read_c3d(path, allow_truncated)
        return {".trc": read_trc, ".npz": _read_npz}[suffix](path)
    except InputError as exc:  # what the take itself refuses (Take's checks) names the file too
        if exc.source is None:
            raise InputError(exc.message, path, exc.field) from None
        raise


def is_table(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a CSV-like table, the one kind of take that ``rate``, ``labels`` and
    ``units`` apply to."""
    return Path(path).suffix.lower() in _TABLES


def dropped_channels(take: Take, path: str | os.PathLike) -> str:
    """What writing ``take`` to ``path`` leaves out, as a note for the user ("" when nothing):
    only ``.npz`` keeps channels."""
    if not take.channel_names or Path(path).suffix.lower() == ".npz":
        return ""
    return (f"note: {Path(path).name} keeps the markers only; its {len(take.channel_names)} channels "
            f"({', '.join(take.channel_names[:3])}, ...) need a .npz take")


def save_take(take: Take, path: str | os.PathLike) -> Path:
    """Write a take file atomically, choosing the writer by suffix (``.c3d .trc .csv .npz``)."""
    path = Path(path)
    writers = {".c3d": write_c3d, ".csv": write_csv, ".npz": _write_npz,
               ".trc": lambda t, tmp: write_trc(t, tmp, path.name)}  # its header names the file, not the temporary
    writer = writers.get(path.suffix.lower())
    if writer is None:
        raise InputError(f"unknown take format {path.suffix or '(no suffix)'!r} (writable: {', '.join(WRITABLE)})",
                         path)
    if take.dims == 2 and path.suffix.lower() in (".c3d", ".trc"):
        raise InputError("a planar (2-D) take can be written as .csv or .npz only", path)
    with atomic_path(path) as tmp:
        writer(take, tmp)
    return path


def load_take_or_video(path: str | os.PathLike, units: str | None = None,
                       progress_factory: Callable[[int], Callable[[int], None]] | None = None) -> Take:
    """A take file (:func:`capture.load_take`, its ``units`` where it does not say them), or a
    talking-head video (any of :data:`capture.sources.VIDEO_SUFFIXES`) with its face tracked
    without markers, as ``retarget`` takes it: what every command and page that opens a take
    opens. For dot or ArUco markers in a video, :func:`capture.video_tracking.track_video`
    names the kind.

    Raises
    ------
    InputError
        A bad take or video, or ``units`` given for a video (it is tracked in its own).
    """
    from capture.sources import VIDEO_SUFFIXES

    if Path(path).suffix.lower() not in VIDEO_SUFFIXES:
        return load_take(path, units=units)
    if units:
        raise InputError("a video is tracked in its own units: leave units out", path)
    from capture.video_tracking import track_video  # the trackers: imported for a video only

    return track_video(path, "face", progress_factory=progress_factory)
