"""Batch job files (TOML, ``toonface.batch/1``): which takes, which faces, how, and what to write.

Example, with every field and its default::

    format = "toonface.batch/1"
    takes = ["takes/*.c3d", "more/**/*.npz"]   # globs, relative to this file; ** goes into sub-folders
    faces = ["classic", "round", "faces/mine.json"]
    output = "batch-out"      # folder for <take>/<face>.mp4 etc., relative to this file
    mapping = ""              # a mapping file or preset [default: the preset of each take's marker set]
    profile = ""              # a performer profile [default: calibrate on each take]
    neutral = ""              # "first", "stillest" or [start, end] seconds [default: a profile's rest, else first]
    mirror = false

    [write]
    video = true              # <take>/<face>.mp4; or "webm", "mov", "apng", "webp" (alpha), "svg" (animated),
                              # "json" (Lottie), "html" (the web player), "mp4", or false
    motors = "csv"            # <take>/<face>.csv, "npz", or false
    score = true              # <take>/<face>.score.png: the motor curves as staves
    sheet = true              # <take>/<face>.sheet.png: 12 frames through the take, labelled

    [render]
    size = "512"              # N or WxH pixels, even
    fps = 0                   # 0: each take's own rate
    samples = 4               # MSAA samples
    part_seconds = 10.0       # longer MP4s are rendered in parts of at most this long, in parallel
    background = ""           # the face's own; "none" (transparent: not for mp4) or "#rrggbb"

    [clean]
    cutoff = 8.0              # Hz, 0: no smoothing
    max_gap = 2.0             # seconds
    spikes = true
    holds = true              # smooth a marker holding still more (false: the cutoff alone)

    [csv]                     # for CSV takes only, which may not say these
    rate = 0                  # Hz
    units = ""                # mm, cm, m, in, or millimetres per unit
    labels = []               # marker names of a headerless table
"""

from __future__ import annotations

import glob
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from common import InputError, read_versioned
from common.validate import Validator, is_number
from mapping import CleanSettings
from toonface.cli_options import frame_size

FORMAT = "toonface.batch/1"
TAKE_SUFFIXES = (".c3d", ".trc", ".csv", ".tsv", ".txt", ".npz")
OUTPUT_KINDS = ("motors", "video", "score", "sheet")
#: What ``write.video`` may name: the picture formats (``true`` is ``mp4``).
VIDEO_FORMATS = ("mp4", "webm", "mov", "apng", "webp", "svg", "json", "html")


@dataclass(frozen=True)
class WriteSettings:
    """Which outputs each (take, face) pair gets; ``video`` is one of :data:`VIDEO_FORMATS` or
    ``""`` (none), ``motors`` is ``"csv"``, ``"npz"`` or ``""`` (none)."""

    video: str = "mp4"
    motors: str = "csv"
    score: bool = True
    sheet: bool = True

    def kinds(self) -> tuple[str, ...]:
        """The requested output kinds, in :data:`OUTPUT_KINDS` order."""
        wanted = {"motors": bool(self.motors), "video": bool(self.video), "score": self.score, "sheet": self.sheet}
        return tuple(kind for kind in OUTPUT_KINDS if wanted[kind])


@dataclass(frozen=True)
class RenderSettings:
    """Frame size ``(width, height)``, rate (0: the take's), MSAA samples, the longest part, and
    the background (``""``: the face's own, ``"none"``: transparent, or ``"#rrggbb[aa]"``)."""

    size: tuple[int, int] = (512, 512)
    fps: float = 0.0
    samples: int = 4
    part_seconds: float = 10.0
    background: str = ""


@dataclass(frozen=True)
class TakeOptions:
    """What a CSV take may not say about itself (see :func:`capture.load_take`)."""

    rate: float | None = None
    units: str | None = None
    labels: tuple[str, ...] | None = None


@dataclass(frozen=True)
class Job:
    """A parsed job file. Paths are absolute; ``faces`` are built-in names or absolute paths."""

    path: Path
    takes: tuple[Path, ...]
    faces: tuple[str, ...]
    output: Path
    mapping: str | None = None
    profile: Path | None = None
    neutral: tuple[float, float] | str | None = None
    mirror: bool = False
    write: WriteSettings = WriteSettings()
    render: RenderSettings = RenderSettings()
    clean: CleanSettings = CleanSettings()
    take_options: TakeOptions = TakeOptions()
    empty_globs: tuple[str, ...] = field(default=())
    passed_over: tuple[Path, ...] = field(default=())


def load_job(path: str | os.PathLike) -> Job:
    """Read and check a job file; every problem is an :class:`InputError` naming the field.

    Takes are found by the globs now (sorted, each once); a glob that matches nothing is kept in
    ``empty_globs``, and the videos and voices the globs match (which ``map`` and ``retarget``
    read, a batch not) in ``passed_over``, for the caller to warn about; a job with no takes
    at all is an error.
    """
    path = Path(path).resolve()
    doc = read_versioned(path, FORMAT, "batch job")
    fields = _Fields(doc, path)
    base = path.parent
    known = {"format", "takes", "faces", "output", "mapping", "profile", "neutral", "mirror", "write", "render",
             "clean", "csv"}
    fields.check.fields(doc, known, "")
    patterns = fields.strings("takes", required=True)
    output = base / (fields.text("output") or "batch-out")
    takes, empty, passed = _expand(patterns, base, path, output)
    faces = tuple(_face_spec(name, base) for name in fields.strings("faces", required=True))
    if len(set(faces)) != len(faces):
        raise InputError("a face is named twice", path, "faces")
    mapping = fields.text("mapping") or None
    profile = fields.text("profile")
    write, render = _write_settings(fields), _render_settings(fields)
    if write.video == "mp4" and render.background.lower() == "none":
        raise InputError('an MP4 has no alpha channel: write.video = "webm", "mov", "apng", "webp", "svg" or "html" '
                         'for a transparent background', path, "render.background")
    return Job(
        path=path, takes=takes, faces=faces, output=output,
        mapping=_mapping_spec(mapping, base), profile=(base / profile) if profile else None,
        neutral=fields.neutral("neutral"), mirror=fields.flag("mirror", False),
        write=write, render=render, clean=_clean_settings(fields),
        take_options=_take_options(fields), empty_globs=empty, passed_over=passed)


def _expand(patterns: list[str], base: Path, path: Path, output: Path
            ) -> tuple[tuple[Path, ...], tuple[str, ...], tuple[Path, ...]]:
    """The take files the globs match, sorted, each once (files under the output folder, motor
    tracks written as .npz or .csv, are never takes); the globs that match none; and the videos
    and voices they match, which a batch does not read."""
    from capture.sources import SOUND_SUFFIXES, VIDEO_SUFFIXES

    found: dict[Path, None] = {}
    passed: dict[Path, None] = {}
    empty = []
    output = output.resolve()
    for pattern in patterns:
        full = pattern if os.path.isabs(pattern) else str(base / pattern)
        files = sorted(Path(m).resolve() for m in glob.glob(full, recursive=True) if Path(m).is_file())
        files = [m for m in files if output not in m.parents]
        matches = [m for m in files if m.suffix.lower() in TAKE_SUFFIXES]
        passed.update(dict.fromkeys(m for m in files if m.suffix.lower() in VIDEO_SUFFIXES | SOUND_SUFFIXES))
        if not matches:
            empty.append(pattern)
        found.update(dict.fromkeys(matches))
    if not found:
        media = (f"; it matches {len(passed)} videos or voices, which a batch does not read (`toonface retarget` "
                 "each one)") if passed else ""
        raise InputError(f"no take file ({', '.join(TAKE_SUFFIXES)}) matches {patterns}{media}", path, "takes")
    return tuple(found), tuple(empty), tuple(passed)


def _face_spec(name: str, base: Path) -> str:
    """A built-in face name stays a name; anything that looks like a file becomes an absolute path."""
    return str(base / name) if name.endswith(".json") or os.sep in name or "/" in name else name


def _mapping_spec(name: str | None, base: Path) -> str | None:
    return str(base / name) if name and (name.endswith(".toml") or "/" in name) else name


def _write_settings(fields: _Fields) -> WriteSettings:
    table = fields.table("write", {"video", "motors", "score", "sheet"})
    motors = table.get("motors", WriteSettings.motors)
    if motors is False:
        motors = ""
    if motors not in ("csv", "npz", ""):
        raise InputError(f'expected "csv", "npz" or false, got {motors!r}', fields.path, "write.motors")
    video = table.get("video", True)
    video = {True: "mp4", False: ""}.get(video, video) if isinstance(video, bool) else video
    if video not in (*VIDEO_FORMATS, ""):
        raise InputError(f"expected true, false or one of {', '.join(map(repr, VIDEO_FORMATS))}, got {video!r}",
                         fields.path, "write.video")
    default = WriteSettings()
    settings = WriteSettings(video=video, motors=motors,
                             score=fields.flag("write.score", default.score),
                             sheet=fields.flag("write.sheet", default.sheet))
    if not settings.kinds():
        raise InputError("the job writes nothing: enable at least one of video, motors, score, sheet",
                         fields.path, "write")
    return settings


def _render_settings(fields: _Fields) -> RenderSettings:
    table = fields.table("render", {"size", "fps", "samples", "part_seconds", "background"})
    default = RenderSettings()
    size_text = str(table.get("size", "x".join(map(str, default.size))))
    try:
        size = frame_size(size_text)
    except ValueError as exc:
        raise InputError(str(exc), fields.path, "render.size") from None
    if size[0] % 2 or size[1] % 2:
        raise InputError(f"H.264 needs even sides, got {size_text!r}", fields.path, "render.size")
    background = str(table.get("background", ""))
    if background and background.lower() != "none" and not re.fullmatch(r"#[0-9a-fA-F]{6}([0-9a-fA-F]{2})?",
                                                                        background):
        raise InputError(f'expected "", "none" or "#rrggbb[aa]", got {background!r}', fields.path, "render.background")
    return RenderSettings(size=size, fps=fields.number("render.fps", default.fps, 0.0, 240.0),
                          samples=int(fields.number("render.samples", default.samples, 0, 16)),
                          part_seconds=fields.number("render.part_seconds", default.part_seconds, 0.5, 3600.0),
                          background=background)


def _clean_settings(fields: _Fields) -> CleanSettings:
    fields.table("clean", {"cutoff", "max_gap", "spikes", "holds"})
    default = CleanSettings()
    return CleanSettings(spikes=fields.flag("clean.spikes", default.spikes),
                         max_gap_seconds=fields.number("clean.max_gap", default.max_gap_seconds, 0.0, 3600.0),
                         cutoff_hz=fields.number("clean.cutoff", default.cutoff_hz, 0.0, 1000.0),
                         holds=fields.flag("clean.holds", default.holds))


def _take_options(fields: _Fields) -> TakeOptions:
    table = fields.table("csv", {"rate", "units", "labels"})
    rate = fields.number("csv.rate", 0.0, 0.0, 100000.0)
    labels = fields.strings("csv.labels") if "labels" in table else None
    units = table.get("units")
    if units is not None and not isinstance(units, (str, int, float)):
        raise InputError(f"expected a unit name or millimetres per unit, got {units!r}", fields.path, "csv.units")
    return TakeOptions(rate=rate or None, units=str(units) if units not in (None, "") else None,
                       labels=tuple(labels) if labels else None)


class _Fields:
    """A job document's fields by dotted name (``render.size``), checked by the project's
    validator (:class:`common.validate.Validator`), so that each failure names the field."""

    def __init__(self, doc: dict, path: Path) -> None:
        self.doc, self.path, self.check = doc, path, Validator(path)

    def get(self, dotted: str, default: Any = None) -> Any:
        node: Any = self.doc
        for part in dotted.split("."):
            if not isinstance(node, dict) or part not in node:
                return default
            node = node[part]
        return node

    def table(self, name: str, known: set[str]) -> dict:
        return self.check.fields(self.get(name, {}), known, name)

    def strings(self, name: str, required: bool = False) -> list[str]:
        value = self.get(name)
        if value is None and not required:
            return []
        return self.check.strings([value] if isinstance(value, str) else value, name, empty=False)

    def text(self, name: str) -> str:
        return self.check.text(self.get(name, ""), name)

    def flag(self, name: str, default: bool) -> bool:
        return self.check.boolean(self.get(name, default), name)

    def number(self, name: str, default: float, low: float, high: float) -> float:
        return self.check.number(self.get(name, default), name, low, high)

    def neutral(self, name: str) -> tuple[float, float] | str | None:
        value = self.get(name, "")
        if value in ("", None):
            return None
        if value in ("first", "stillest"):
            return value
        if (isinstance(value, list) and len(value) == 2 and all(is_number(v) for v in value)
                and 0 <= value[0] < value[1]):
            return float(value[0]), float(value[1])
        self.check.fail(f'expected "first", "stillest" or [start, end] seconds, got {value!r}', name)
