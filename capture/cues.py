"""Rhubarb Lip Sync's mouth cues, written and read: the shapes a voice gave, as other tools keep them.

Rhubarb's formats: TSV (each line a cue's start, seconds, a tab and its shape; the last line the
end, at rest), JSON (``metadata`` with the sound file and its duration, and ``mouthCues``, each
``{"start", "end", "value"}``), XML (``rhubarbResult`` with ``metadata`` and ``mouthCues`` of
``<mouthCue start end>SHAPE</mouthCue>``), and Moho's and OpenToonz's switch data, ``.dat``
(``MohoSwitch1``, then ``FRAME SHAPE`` lines, frames counted from 1 at a chosen rate; written
only, as it keeps no seconds). Read back, cues are the voice take they came
from (:func:`cues_take`): the same shapes at 100 Hz, blended as :func:`capture.voice.shape_curves`
blends them, so a track mapped from the cues is the track mapped from the voice where the
voice was a shape a frame (its phones or words), and that track a shape at a time where the
sound weighed two (:func:`capture.voice_sound.sound_mouth`).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from capture.take import Take
from capture.voice import FRAME_RATE, VISEMES, shape_curves
from common import InputError
from common.limits import check_cue_end, read_regular_text

#: What cues are written as, by suffix (all but ``.dat`` are read back too).
CUE_SUFFIXES = (".tsv", ".json", ".xml", ".dat")
#: Moho's switch files count frames at this rate unless told (Rhubarb's default).
DAT_FPS = 24.0
#: The shapes that shut the lips (b, p, m), kept however short (:func:`held_cues`).
CLOSURES = ("A",)


def held_cues(cues: list[tuple[float, float, str]], fps: float = DAT_FPS,
              closures: tuple[str, ...] = CLOSURES) -> list[tuple[float, float, str]]:
    """``cues`` (``(start, end, shape)``, seconds) for an animation at ``fps`` frames a second,
    as an editor needs them: each on whole frames, and held two frames at least (a shape for one
    frame is a flicker), but a closure (``A``, the lips shut for b, p and m: without it a word
    does not read), which keeps one frame at least even where it was shorter. A shape too short
    to keep joins the shape before it (the first, or one after a closure: the shape after it);
    neighbours of one shape become one cue. The first cue still starts where the first began and
    the last ends where the last ended, on the nearest frame."""
    spans = [[int(round(a * fps)), int(round(b * fps))] for a, b, _ in cues]  # (start, end) frames
    shapes = [shape for _, _, shape in cues]
    for k, span in enumerate(spans):  # a closure shorter than a frame takes one from its successor
        if shapes[k] in closures and span[1] <= span[0]:
            span[1] = span[0] + 1
            if k + 1 < len(spans):
                spans[k + 1][0] = max(spans[k + 1][0], span[1])
                spans[k + 1][1] = max(spans[k + 1][1], spans[k + 1][0])

    def least(shape: str) -> int:
        return 1 if shape in closures else 2

    changed = True
    while changed and len(spans) > 1:
        changed = False
        kept: list[list[int]] = []
        named: list[str] = []
        carried: int | None = None  # where a shape too short after a closure began: the next shape's start
        for k, (span, shape) in enumerate(zip(spans, shapes, strict=True)):
            start = span[0] if carried is None else carried
            carried = None
            if named and named[-1] == shape:  # the same shape again: one cue
                kept[-1][1] = span[1]
            elif span[1] - start < least(shape) and named and named[-1] not in closures:
                kept[-1][1], changed = span[1], True  # too short: joins the shape before it
            elif span[1] - start < least(shape) and named and k + 1 < len(spans):
                carried, changed = start, True  # too short after a closure: the shape after it takes its time
            else:
                kept.append([start, span[1]])
                named.append(shape)
        if len(kept) > 1 and kept[0][1] - kept[0][0] < least(named[0]):
            kept[1][0], changed = kept[0][0], True  # the first, too short: the next shape from the start
            del kept[0], named[0]
        pairs = [(span, shape) for span, shape in zip(kept, named, strict=True) if span[1] > span[0] or len(kept) == 1]
        spans, shapes = [span for span, _ in pairs], [shape for _, shape in pairs]
    return [(a / fps, b / fps, shape) for (a, b), shape in zip(spans, shapes, strict=True)]


def cues_text(cues: list[tuple[float, float, str]], suffix: str, sound: str | os.PathLike = "",
              words: str | None = None, fps: float = DAT_FPS) -> str:
    """``cues`` (``(start, end, shape)``, seconds) as the text of a ``.tsv``, ``.json``, ``.xml``
    or ``.dat`` (frames at ``fps``) file."""
    if suffix == ".dat":  # each cue from the frame it starts on; a cue shorter than a frame is lost
        switches: list[tuple[int, str]] = []
        for start, _, shape in cues:
            frame = int(round(start * fps)) + 1
            if switches and switches[-1][0] == frame:  # a later cue on the same frame replaces it
                switches.pop()
            if not switches or switches[-1][1] != shape:  # and a switch to the shape shown already is none
                switches.append((frame, shape))
        return "".join(f"{line}\n" for line in ["MohoSwitch1", *(f"{frame} {shape}" for frame, shape in switches)])
    if suffix == ".xml":
        from xml.sax.saxutils import escape

        duration = cues[-1][1] if cues else 0.0
        body = "\n".join(f'    <mouthCue start="{a:.2f}" end="{b:.2f}">{s}</mouthCue>' for a, b, s in cues)
        return ('<?xml version="1.0" encoding="utf-8"?>\n<rhubarbResult>\n  <metadata>\n'
                f"    <soundFile>{escape(str(Path(sound).resolve()) if sound else '')}</soundFile>\n"
                f"    <duration>{duration:.2f}</duration>\n"
                + (f"    <dialog>{escape(words)}</dialog>\n" if words else "")
                + f"  </metadata>\n  <mouthCues>\n{body}\n  </mouthCues>\n</rhubarbResult>\n")
    if suffix == ".tsv":
        lines = [f"{start:.2f}\t{shape}" for start, _, shape in cues]
        if cues:
            lines.append(f"{cues[-1][1]:.2f}\tX")
        return "\n".join(lines) + "\n"
    duration = cues[-1][1] if cues else 0.0
    doc: dict[str, Any] = {"metadata": {"soundFile": str(Path(sound).resolve()) if sound else "",
                                        "duration": round(duration, 2)},
                           "mouthCues": [{"start": round(a, 2), "end": round(b, 2), "value": s} for a, b, s in cues]}
    if words:
        doc["metadata"]["dialog"] = words
    return json.dumps(doc, indent=2) + "\n"


def read_cues(path: str | os.PathLike) -> list[tuple[float, float, str]]:
    """The cues of a Rhubarb ``.tsv`` or ``.json`` file, ``(start, end, shape)`` seconds.

    Raises
    ------
    InputError
        Naming the file and the line or cue that is not a cue.
    """
    source = Path(path)
    text = read_regular_text(source, what="file of mouth cues")
    if source.suffix.lower() == ".json":
        return _json_cues(text, source)
    if source.suffix.lower() == ".xml":
        return _xml_cues(text, source)
    starts: list[tuple[float, str]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        parts = line.split("\t")
        try:
            start = float(parts[0])
        except ValueError:
            raise InputError("expected start<TAB>shape (Rhubarb's TSV)", source, f"line {number}") from None
        if len(parts) != 2 or parts[1].strip() not in VISEMES or not np.isfinite(start) or start < 0:
            raise InputError(f"expected start<TAB>shape with a shape of {', '.join(VISEMES)}", source,
                             f"line {number}")
        if starts and start < starts[-1][0]:
            raise InputError("cue times must not go back", source, f"line {number}")
        check_cue_end(start, source, f"line {number}")
        starts.append((start, parts[1].strip()))
    if len(starts) < 2:
        raise InputError("no mouth cues: expected start<TAB>shape lines ending with the end at rest", source)
    return [(a, b, shape) for (a, shape), (b, _) in zip(starts, starts[1:], strict=False)]


def _json_cues(text: str, source: Path) -> list[tuple[float, float, str]]:
    try:
        doc = json.loads(text)
    except (json.JSONDecodeError, RecursionError, ValueError) as exc:
        raise InputError(f"not valid JSON ({exc})", source) from None
    listed = doc.get("mouthCues") if isinstance(doc, dict) else None
    if not isinstance(listed, list) or not listed:
        raise InputError('expected Rhubarb\'s JSON: an object with "mouthCues"', source)
    sound = _duration(doc.get("metadata"), source)
    cues: list[tuple[float, float, str]] = []
    for k, cue in enumerate(listed):
        where = f"mouthCues[{k}]"
        if not isinstance(cue, dict) or cue.get("value") not in VISEMES:
            raise InputError(f"expected {{\"start\", \"end\", \"value\"}} with a value of {', '.join(VISEMES)}",
                             source, where)
        times = [cue.get("start"), cue.get("end")]
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) for v in times):
            raise InputError("expected numbers of seconds for start and end", source, where)
        start, end = float(times[0]), float(times[1])  # type: ignore[arg-type]
        if not 0 <= start <= end or (cues and start < cues[-1][1] - 1e-9):
            raise InputError("expected 0 <= start <= end, each cue after the one before", source, where)
        check_cue_end(end, source, where, sound)
        cues.append((start, end, str(cue["value"])))
    return cues


def _xml_cues(text: str, source: Path) -> list[tuple[float, float, str]]:
    import xml.etree.ElementTree as ElementTree

    if "<!DOCTYPE" in text or "<!ENTITY" in text:  # no entity expansion from a stranger's file
        raise InputError("an XML document type is not read in mouth cues", source)
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as exc:
        raise InputError(f"not valid XML ({exc})", source) from None
    listed = root.findall("./mouthCues/mouthCue")
    if root.tag != "rhubarbResult" or not listed:
        raise InputError("expected Rhubarb's XML: rhubarbResult with mouthCues", source)
    sound = _duration({"duration": root.findtext("./metadata/duration")}, source)
    cues: list[tuple[float, float, str]] = []
    for k, cue in enumerate(listed):
        where = f"mouthCue {k + 1}"
        shape = (cue.text or "").strip()
        try:
            start, end = float(cue.get("start", "")), float(cue.get("end", ""))
        except ValueError:
            raise InputError("expected start and end in seconds", source, where) from None
        if shape not in VISEMES or not (np.isfinite(start) and np.isfinite(end)) or not 0 <= start <= end \
                or (cues and start < cues[-1][1] - 1e-9):
            raise InputError(f"expected 0 <= start <= end after the cue before, and a shape of {', '.join(VISEMES)}",
                             source, where)
        check_cue_end(end, source, where, sound)
        cues.append((start, end, shape))
    return cues


def _duration(metadata: object, source: Path) -> float | None:
    """The length of the sound the cues came with, seconds, where their metadata gives one
    (Rhubarb writes ``duration``); an :class:`InputError` where it is not a length."""
    value = metadata.get("duration") if isinstance(metadata, dict) else None
    if value is None or value == "":
        return None
    try:
        seconds = float(value)
    except (TypeError, ValueError):
        raise InputError(f"expected the sound's duration in seconds, got {str(value)[:40]!r}", source,
                         "metadata.duration") from None
    if not (math.isfinite(seconds) and seconds >= 0):
        raise InputError(f"expected the sound's duration in seconds, got {str(value)[:40]!r}", source,
                         "metadata.duration")
    return seconds


def cues_take(path: str | os.PathLike) -> Take:
    """Mouth cues as the voice take they describe: no markers, at 100 Hz, the shapes' weights
    (``viseme_A`` ... ``viseme_X``), blended as a voice's are, and a ``sound_level`` of 1 where a
    shape other than rest is (where the voice was), 0 elsewhere."""
    cues = read_cues(path)
    frames = max(2, int(round(cues[-1][1] * FRAME_RATE)))
    shapes = np.full(frames, VISEMES.index("X"))
    for start, end, shape in cues:
        shapes[int(round(start * FRAME_RATE)):int(round(end * FRAME_RATE))] = VISEMES.index(shape)
    curves = shape_curves(shapes)
    voiced = (shapes != VISEMES.index("X")).astype(float)  # where a voice was: what says where rest is
    return Take(np.zeros((frames, 0, 3)), (), FRAME_RATE, channels=np.column_stack([curves, voiced]),
                channel_names=(*(f"viseme_{v}" for v in VISEMES), "sound_level"),
                meta={"source": "mouth cues", "file": Path(path).name, "cues": len(cues)})


def is_cue_table(path: str | os.PathLike) -> bool:
    """Whether a ``.tsv`` file holds Rhubarb's cues (``0.00<TAB>X`` lines) rather than a table of
    markers."""
    try:
        with open(path, encoding="utf-8") as handle:
            first = next((line for line in handle if line.strip()), "")
    except (OSError, UnicodeDecodeError):
        return False
    parts = first.rstrip("\n").split("\t")
    return len(parts) == 2 and parts[1].strip() in VISEMES and parts[0].replace(".", "", 1).isdigit()
