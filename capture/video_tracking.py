"""Markers from a video file into a :class:`Take` (``toonface track``): planar for dots and ArUco,
3-D for a face without markers (:mod:`capture.face_sources`).

Image positions (x right, y down, pixels) become millimetres with y up: ``(x s, -y s, 0)`` for a
scale ``s`` in mm per pixel, with ``dims=2``. For dots, ``s`` and the origin come from fitting the
marker set's neutral layout on the start frame, so the take lies in the marker set's frame. For
ArUco markers, ``s`` is given (``mm_per_pixel``), or measured from the printed marker size
(``marker_mm``, the median side length over the video), or 1 (the take is then in pixels, and its
``meta`` says so).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from capture.aruco import track_aruco
from capture.dots import pixels_to_mm
from capture.face_sources import face_source
from capture.sources import video_source
from capture.take import SOUND_LEVEL, Take
from capture.videoio import frames, probe
from common import InputError, read_document
from common.sound import sound_envelope


def track_video(path: str | os.PathLike, method: str = "dots", markerset: str = "toon32",
                colour: str = "blue", start_frame: int = 0, names: dict[int, str] | None = None,
                corners: bool = False, dictionary: str = "aruco_original", mm_per_pixel: float | None = None,
                marker_mm: float | None = None, progress_factory: Callable[[int], Callable[[int], None]] | None = None
                ) -> Take:
    """Track ``method`` (``dots``, ``aruco``, or ``face`` for no markers) through a video; see the
    module docstring and :func:`capture.sources.face_source`.

    Raises
    ------
    InputError
        An undecodable video, or one in which no markers are found.
    """
    info = probe(path)
    rate = info.rate or 30.0
    progress = progress_factory(info.frames) if progress_factory else None
    if method == "face":
        take = _some_frames(face_source(path, info).to_take(progress), path)
        if take.frames == 1:
            raise InputError("a still image (one frame), not a video of a face", path)
        seen = np.isfinite(take.positions).all(axis=2).any(axis=1)
        if not seen.any():
            raise InputError(f"no face found in any of its {take.frames} frames; a video of dot or ArUco markers is "
                             "read by `toonface track --markers dots` (or aruco)", path)
        take.meta["faces_found"] = int(seen.sum())
        return with_sound_level(take, path)
    if method == "dots":
        take = _some_frames(video_source(path, colour, markerset, start_frame, info).to_take(progress), path)
        if not np.isfinite(take.positions).any():
            raise InputError(f"no {colour} dot markers found in {take.frames} frames", path)
        return take
    if method != "aruco":
        raise InputError(f"unknown marker kind {method!r} (dots, aruco or face)", path)
    meta: dict[str, Any] = {"source": "video", "file": Path(path).name, "tracker": method,
                            "image_size": [info.width, info.height], "decoder": info.backend}
    try:
        labels_t, pixels = track_aruco(frames(info), names, corners, dictionary, progress=progress)
    except ValueError as exc:
        raise InputError(str(exc), path) from None
    labels = list(labels_t)
    if not labels:
        raise InputError(f"no ArUco markers ({dictionary}) found in the video", path)
    origin = np.zeros(2)
    scale = mm_per_pixel or (_aruco_scale(pixels, marker_mm, corners) if marker_mm else 1.0)
    meta.update(dictionary=dictionary, corners=corners, scale_known=bool(mm_per_pixel or marker_mm))
    if len(pixels) == 0:
        raise InputError("the video has no frames", path)
    meta["mm_per_pixel"] = float(scale)
    return Take(pixels_to_mm(pixels, origin, scale), tuple(labels), rate, dims=2, meta=meta)


def with_sound_level(take: Take, path: str | os.PathLike) -> Take:
    """``take`` with a :data:`~capture.take.SOUND_LEVEL` channel: the loudness of ``path``'s sound
    at each frame (RMS over 20 ms, 1 the loudest; NaN past the sound's end), which says where
    nobody speaks (:mod:`mapping.rest`). A video without sound gives the take unchanged."""
    step = 0.02
    try:
        times, envelope = sound_envelope(path, step)
    except InputError:  # no sound (or none that decodes): nothing to say where nobody speaks
        return take
    if len(times):  # each level holds for its step: the last one up to the sound's end
        level = np.interp(take.times, np.append(times, times[-1] + step), np.append(envelope, envelope[-1]),
                          left=np.nan, right=np.nan)
    else:
        level = np.full(take.frames, np.nan)
    take.meta["sound"] = "sound_level channel: the voice's loudness at each frame"
    return replace(take, channels=np.column_stack([take.channels, level]),
                   channel_names=(*take.channel_names, SOUND_LEVEL))


def _some_frames(take: Take, path: str | os.PathLike) -> Take:
    if not take.frames:
        raise InputError("the video has no frames", path)
    return take


def _aruco_scale(pixels: np.ndarray, marker_mm: float, corners: bool) -> float:
    if not corners:
        raise InputError("--marker-mm measures the printed side from the corners: add --corners")
    quads = pixels.reshape(len(pixels), -1, 4, 2)
    sides = np.linalg.norm(quads - np.roll(quads, 1, axis=2), axis=3)
    return float(marker_mm / np.nanmedian(sides))


def load_aruco_names(path: str | os.PathLike) -> dict[int, str]:
    """An id -> marker name table from TOML (``[names]`` with ``101 = "BROW_L_MED"``)."""
    path = Path(path)
    doc = read_document(path)
    table = doc.get("names")
    if not isinstance(table, dict) or not table:
        raise InputError('expected a [names] table of id = "marker name"', path, "names")
    out: dict[int, str] = {}
    for key, value in table.items():
        if not (key.isdigit() and isinstance(value, str) and value):
            raise InputError(f"expected a marker id = \"name\", got {key} = {value!r}", path, f"names.{key}")
        out[int(key)] = value
    if len(set(out.values())) != len(out):
        raise InputError("two ids share a marker name", path, "names")
    return out
