"""Which picture sink an output names: by its suffix, or ``--format`` for a folder of frames.

Kept apart from the sinks themselves (:mod:`player.sinks`, :mod:`player.alpha_sinks`,
:mod:`player.vector_sinks`), which this module imports: a render loop needs none of them to
start (it asks :func:`player.sinks.keeps_alpha` whether a sink takes straight RGBA).
"""

from __future__ import annotations

import os
from pathlib import Path

from common import InputError
from player.alpha_sinks import ALPHA_FORMATS, AlphaVideoSink
from player.sinks import LiveMp4Sink, Mp4Sink, PngSink, RawSink
from player.vector_sinks import AnimatedSvgSink, SvgFolderSink

#: What a picture output can be, by suffix, for messages (a folder has none: PNG frames).
PICTURE_SUFFIXES = {".mp4": "an H.264 MP4", ".webm": "a WebM (VP9 with alpha)",
                    ".mov": "a QuickTime .mov (ProRes 4444 with alpha)", ".apng": "an animated PNG",
                    ".webp": "an animated WebP", ".svg": "an animated SVG", ".json": "a Lottie animation"}
#: What a folder of frames can hold (``--format``).
FOLDER_FORMATS = ("png", "svg")


def open_sink(target: str | os.PathLike, fps: float, size: tuple[int, int], live: bool = False,
              fmt: str | None = None
              ) -> Mp4Sink | LiveMp4Sink | PngSink | RawSink | AlphaVideoSink | AnimatedSvgSink | SvgFolderSink:
    """An MP4 sink for ``*.mp4`` (``live``: one that a kill does not lose, :class:`LiveMp4Sink`),
    a moving picture with alpha for ``.webm .mov .apng .webp`` (:mod:`player.alpha_sinks`), an
    animated SVG for ``.svg`` and a Lottie animation for ``.json`` (:mod:`player.vector_sinks`),
    raw RGB on standard output for ``-``, otherwise a folder of PNG frames (or of SVG frames,
    ``fmt="svg"``): a name with no suffix, an existing folder, or any name but a picture file's
    with ``fmt`` ``png`` or ``svg``."""
    if str(target) == "-":
        return RawSink()
    target = Path(target)
    suffix = target.suffix.lower()
    if fmt == "lottie" and suffix != ".json":
        raise InputError("--format lottie writes a .json file", target)
    folder = fmt in FOLDER_FORMATS or target.is_dir()  # a folder's name may hold a dot: "take.v2"
    if fmt is not None and fmt != "lottie" and (suffix in PICTURE_SUFFIXES or fmt not in FOLDER_FORMATS):
        raise InputError(f"--format {fmt} is for a folder of frames ({' or '.join(FOLDER_FORMATS)}); a file's "
                         "suffix says its format", target)
    if suffix == ".mp4":
        return LiveMp4Sink(target, fps, size) if live else Mp4Sink(target, fps, size)
    if suffix in ALPHA_FORMATS:
        return AlphaVideoSink(target, fps, size)
    if suffix in (".svg", ".json"):
        return AnimatedSvgSink(target, fps, size, lottie=suffix == ".json")
    if target.suffix and not folder:
        known = ", ".join(f"{k} ({v})" for k, v in PICTURE_SUFFIXES.items())
        raise InputError(f"unknown output type {target.suffix!r}: give {known}, a folder for PNG frames or - for "
                         "raw RGB on standard output", target)
    return SvgFolderSink(target, size) if fmt == "svg" else PngSink(target)
