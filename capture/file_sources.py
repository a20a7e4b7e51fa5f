"""The sources of :data:`capture.sources.KINDS` that read a file whose kind is found by
reading it: a take file (any format :func:`capture.takefile.load_take` reads) and a video
(dot markers, or the face tracked without them). They sit above the readers and trackers they
call, so that :mod:`capture.sources`, which those readers build on, imports none of them.
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from capture.sources import Source, take_source, video_source
from capture.take import Take
from common import InputError


def take_file_source(path: str, read_take: Callable[[str], Take] | None = None, repeat: bool = False,
                     **_: Any) -> Source:
    """A take file played from its start; ``read_take`` reads it (:func:`capture.load_take` by default)."""
    if read_take is None:
        from capture.takefile import load_take
        read_take = load_take
    return take_source(read_take(path), repeat)


def any_video_source(path: str | os.PathLike, colour: str = "blue", markerset: str = "toon32", start_frame: int = 0,
                     named: bool = False, repeat: bool = False, **options: Any) -> Source:
    """A video: dot markers (:func:`video_source`) where its kind was named (``video:VIDEO``) or
    its first frame shows at least half the marker set's dots in ``colour``; else the face in it
    tracked without markers (``face:VIDEO``), the choice and why in ``meta["note"]``."""
    from capture.dots import DotStyle, find_dots, sticker_labels
    from capture.markerset import load_markerset
    from capture.videoio import frames, probe

    info = probe(path)
    if named:
        return video_source(path, colour, markerset, start_frame, info=info, repeat=repeat)
    wanted = len(sticker_labels(load_markerset(markerset).labels))
    first = next(itertools.islice(frames(info), start_frame, None), None)
    try:
        found = 0 if first is None else len(find_dots(first, DotStyle.named(colour)))
    except ValueError as exc:
        raise InputError(str(exc), path) from None
    if found >= wanted // 2:
        return video_source(path, colour, markerset, start_frame, info=info, repeat=repeat)
    from capture.face_sources import face_source

    source = face_source(path, info=info, repeat=repeat)
    name = Path(path).name
    source.meta["note"] = (f"{name}: {found} {colour} dots on frame {start_frame}, not the {wanted} of marker set "
                           f"{markerset}: the face is tracked without markers (face:{name}); video:{name} takes "
                           "it as dot markers")
    return source
