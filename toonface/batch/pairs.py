"""What a batch job has to do: its (take, face) pairs, their outputs, and which are already up to date.

Every output has a key: the SHA-256 of the content hashes of its take, face, mapping, profile and
the job's settings that shape it. After a pair's outputs are written, a stamp
(``<output>/.toonface/<take>/<face>.json``) records each output's key and size, and the take's
size and modification time (a take seen unchanged by those is not hashed again). An output whose
stamp has its current key and whose file still has the recorded size is up to date and is not
made again; a pair whose outputs are all up to date is skipped.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from common import InputError, ToonfaceError, atomic_path, data_path, resolve_builtin
from toonface.batch.job import Job

STAMP_FORMAT = "toonface.batch-stamp/1"
SUFFIXES = {"video": ".mp4", "score": ".score.png", "sheet": ".sheet.png"}


@dataclass(frozen=True)
class Output:
    """One file a pair writes: its kind (``motors``, ``video``, ``score``, ``sheet``), path and key."""

    kind: str
    path: Path
    key: str


@dataclass(frozen=True)
class Pair:
    """One (take, face) pair of a job.

    ``inputs`` maps ``take``, ``face``, ``mapping``, ``profile`` and ``settings`` to SHA-256 hex
    digests; ``stale`` lists the output kinds to make (empty: skip the pair); ``error`` is set when
    the pair cannot even be planned (a take or face file that cannot be read); ``take_stat`` is the
    take's size and modification time (ns) when it was hashed; ``recorded`` is its stamp as read
    when planned (empty outputs where there was none).
    """

    take: Path
    face: str
    name: str
    inputs: dict[str, str]
    outputs: tuple[Output, ...]
    stamp: Path
    stale: tuple[str, ...]
    error: str = ""
    take_stat: tuple[int, int] | None = None
    recorded: dict = field(default_factory=lambda: {"outputs": {}})

    def output(self, kind: str) -> Output:
        """The output of ``kind``."""
        return next(o for o in self.outputs if o.kind == kind)


def plan(job: Job, force: bool = False) -> list[Pair]:
    """Every (take, face) pair of ``job`` in take-then-face order, with what each still needs.

    ``force`` marks every output stale. Takes are hashed once each, whatever the number of faces.
    """
    take_names = _take_names(job.takes)
    face_names = _face_names(job)
    shared = {"mapping": _mapping_digest(job.mapping), "profile": _profile_digest(job.profile),
              "settings": _digest_json(_settings(job))}
    face_digests = {face: _guarded(_face_digest, face) for face in job.faces}
    pairs = []
    for take in job.takes:
        names = {face: f"{take_names[take]}/{face_names[face]}" for face in job.faces}
        stamps = {face: read_stamp(_stamp_path(job, name)) for face, name in names.items()}
        take_digest, seen = _take_digest(take, list(stamps.values()), force)
        for face, name in names.items():
            error = next((d.message for d in (take_digest, face_digests[face]) if isinstance(d, _Unreadable)), "")
            inputs = {"take": str(take_digest), "face": str(face_digests[face]), **shared}
            outputs = tuple(Output(kind, _output_path(job, name, kind), _output_key(inputs, kind, job))
                            for kind in job.write.kinds())
            stale = tuple(o.kind for o in outputs if force or error or not _up_to_date(o, stamps[face]))
            pairs.append(Pair(take, face, name, inputs, outputs, _stamp_path(job, name), stale, error, seen,
                              stamps[face]))
    return pairs


def _stamp_path(job: Job, name: str) -> Path:
    return job.output / ".toonface" / f"{name}.json"


def _take_digest(take: Path, stamps: list[dict], force: bool
                 ) -> tuple[str | _Unreadable, tuple[int, int] | None]:
    """The take's content hash and its size and modification time; the hash is re-used from a
    stamp that saw the file with the same size and time (a rerun over a day of takes does not read
    them all again)."""
    try:
        info = take.stat()
    except OSError as exc:
        return _Unreadable(f"{take}: {exc.strerror or exc}"), None
    seen = (info.st_size, info.st_mtime_ns)
    for doc in stamps if not force else ():
        if doc.get("take_stat") == list(seen) and isinstance(doc.get("inputs", {}).get("take"), str):
            return doc["inputs"]["take"], seen
    return _guarded(file_digest, take), seen


def file_digest(path: str | os.PathLike) -> str:
    """SHA-256 of a file's bytes, as hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def read_stamp(path: Path) -> dict:
    """A pair's stamp, or an empty one where there is none or it cannot be read."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {"outputs": {}}
    return doc if isinstance(doc, dict) and doc.get("format") == STAMP_FORMAT else {"outputs": {}}


def write_stamp(pair: Pair, written: dict[str, int], frames: int, report: dict | None = None) -> None:
    """Record the outputs just ``written`` (kind -> bytes) for ``pair``, keeping earlier up-to-date
    ones, and its take's ``report``, which a rerun that skips the pair reports again."""
    previous = pair.recorded.get("outputs", {})
    outputs = {}
    for output in pair.outputs:
        if output.kind in written:
            outputs[output.kind] = {"path": str(output.path), "key": output.key, "bytes": written[output.kind]}
        elif output.kind not in pair.stale and output.kind in previous:
            outputs[output.kind] = previous[output.kind]
    seen = list(pair.take_stat) if pair.take_stat else None
    doc = {"format": STAMP_FORMAT, "take": str(pair.take), "take_stat": seen, "face": pair.face,
           "inputs": pair.inputs, "frames": frames, "outputs": outputs,
           "report": report if report else pair.recorded.get("report", {})}
    pair.stamp.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(pair.stamp) as tmp:
        tmp.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")


def _up_to_date(output: Output, stamp: dict) -> bool:
    recorded = stamp.get("outputs", {}).get(output.kind)
    if not isinstance(recorded, dict) or recorded.get("key") != output.key:
        return False
    try:
        return output.path.stat().st_size == recorded.get("bytes")
    except OSError:
        return False


def _output_path(job: Job, name: str, kind: str) -> Path:
    suffix = (f".{job.write.motors}" if kind == "motors" else f".{job.write.video}" if kind == "video"
              else SUFFIXES[kind])
    return job.output / f"{name}{suffix}"


def _output_key(inputs: dict[str, str], kind: str, job: Job) -> str:
    """The key of one output: the inputs plus the settings that shape this kind of output."""
    own = {"motors": {"format": job.write.motors},
           "video": {"size": job.render.size, "fps": job.render.fps, "samples": job.render.samples,
                     "format": job.write.video, "background": job.render.background},
           "score": {},
           "sheet": {"samples": job.render.samples}}[kind]
    return _digest_json({"inputs": inputs, "kind": kind, "settings": own})


def _settings(job: Job) -> dict:
    """The job settings every output of a pair depends on."""
    return {"neutral": job.neutral, "mirror": job.mirror, "clean": asdict(job.clean),
            "csv": asdict(job.take_options)}


def _take_names(takes: tuple[Path, ...]) -> dict[Path, str]:
    """Output folder names of the takes (``out/<take>/<face>``): each take's stem; where stems
    clash, as many of the folders above it as tell them apart (``day1-take``, ``day2-take``),
    and the suffix where only that differs (``take-c3d``, ``take-trc``).

    Examples
    --------
    >>> names = _take_names((Path("/a/day1/t.c3d"), Path("/a/day2/t.c3d"), Path("/b/jaw.csv")))
    >>> sorted(names.values())
    ['day1-t', 'day2-t', 'jaw']
    >>> sorted(_take_names((Path("x/t.c3d"), Path("x/t.trc"))).values())
    ['t-c3d', 't-trc']
    >>> sorted(_take_names((Path("/a/t.c3d"), Path("/b/a/t.c3d"))).values())
    ['a-t', 'b-a-t']
    """
    depth = dict.fromkeys(takes, 0)  # folders above the stem that each name shows
    above = {t: [part for part in t.parent.parts if part not in (t.anchor, ".")] for t in takes}

    def name(take: Path) -> str:
        folders = above[take][len(above[take]) - depth[take]:] if depth[take] else []
        return "-".join([*folders, take.stem])

    while True:
        groups: dict[str, list[Path]] = {}
        for take in takes:
            groups.setdefault(name(take), []).append(take)
        clashes = [group for group in groups.values() if len(group) > 1]
        deeper = [t for group in clashes for t in group if depth[t] < len(above[t])
                  and len({p.parent for p in group}) > 1]
        if not deeper:
            break
        for take in deeper:
            depth[take] += 1
    names = {take: name(take) for take in takes}
    counts = {n: list(names.values()).count(n) for n in set(names.values())}
    return {t: n if counts[n] == 1 else f"{n}-{t.suffix.lstrip('.').lower()}" for t, n in names.items()}


def _face_names(job: Job) -> dict[str, str]:
    names = {face: Path(face).stem for face in job.faces}
    seen: dict[str, str] = {}
    for face, name in names.items():
        if name in seen:
            raise InputError(f"two faces would write the same outputs ({seen[name]} and {face}); rename one",
                             job.path, "faces")
        seen[name] = face
    return names


def _face_digest(face: str) -> str:
    """The face file's digest, with the built-in component libraries a face may draw on."""
    path = resolve_builtin(face, "faces", ".json", "face")
    return _digest_files([path, *sorted(data_path("components").glob("*.json"))])


def _mapping_digest(mapping: str | None) -> str:
    """The mapping file's digest (every built-in preset when the mapping is chosen per take), with
    the built-in marker sets the mapping names."""
    presets = sorted(data_path("mappings").glob("*.toml")) if mapping is None else [
        resolve_builtin(mapping, "mappings", ".toml", "mapping")]
    return _digest_files([*presets, *sorted(data_path("markersets").glob("*.toml"))])


def _profile_digest(profile: Path | None) -> str:
    """The profile's digest; without one, the built-in typical profiles' (takes of their marker
    sets use them)."""
    return _digest_files([profile] if profile else sorted(data_path("profiles").glob("*.toml")))


def _digest_files(paths: list[Path]) -> str:
    return _digest_json([file_digest(p) for p in paths])


def _digest_json(value: object) -> str:
    return hashlib.sha256(json.dumps(value, sort_keys=True, default=str).encode()).hexdigest()


class _Unreadable:
    """A digest that could not be taken; its message is the pair's failure reason."""

    def __init__(self, message: str) -> None:
        self.message = message

    def __str__(self) -> str:
        return "unreadable"


def _guarded(digest: Callable[[Any], str], target: Any) -> str | _Unreadable:
    try:
        return digest(target)
    except ToonfaceError as exc:
        return _Unreadable(str(exc))
    except OSError as exc:
        return _Unreadable(f"{exc.filename or target}: {exc.strerror or exc}")
