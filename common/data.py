"""Where the built-in data (faces, marker sets, mappings) lives."""

from __future__ import annotations

import functools
import json
import os
import tomllib
from importlib import resources
from pathlib import Path

import tomli_w

from common.atomic import atomic_path
from common.errors import InputError
from common.limits import MAX_DOCUMENT_BYTES, MAX_NESTING, nesting_depth, read_regular


def data_path(*parts: str) -> Path:
    """Path of a built-in data file, such as ``data_path("faces", "classic.json")``.

    The files are the package ``toonface_data`` (the checkout's ``data/`` folder, installed with
    the package), found with :mod:`importlib.resources`; ``$TOONFACE_DATA`` names another folder.
    """
    if env := os.environ.get("TOONFACE_DATA"):
        return Path(env).joinpath(*parts)
    root = resources.files("toonface_data")
    if not isinstance(root, Path):  # a zipped install: the files are not on disk
        raise InputError(f"the built-in data is not a folder on disk ({root}); install toonface unzipped")
    return root.joinpath(*parts)


def builtin_names(folder: str, suffix: str) -> list[str]:
    """Names of the built-in files in ``data/<folder>`` with ``suffix``, sorted."""
    return sorted(p.stem for p in data_path(folder).glob(f"*{suffix}"))


def names_builtin(name_or_path: str | os.PathLike) -> bool:
    """Whether a user's ``name_or_path`` is written as a built-in's name: a bare name, with no
    suffix and no folder part (``round``, ``toon32``). A file or folder of that name in the
    working folder does not change it: a built-in is named the same everywhere, and a file of
    one's own is written as a path (``./round``, ``round.json``).

    >>> names_builtin("round"), names_builtin("./round"), names_builtin("round.json"), names_builtin("my/round")
    (True, False, False, False)
    """
    text = os.fspath(name_or_path)
    return bool(text) and not Path(text).suffix and "/" not in text and os.sep not in text and text not in (".", "..")


def resolve_builtin(name_or_path: str | os.PathLike, folder: str, suffix: str, what: str) -> Path:
    """The file a user named: a bare name (:func:`names_builtin`) means the built-in
    ``data/<folder>/<name><suffix>``, whatever the working folder holds; a bare name that no
    built-in has is taken as a path where such a file exists. Anything with a suffix or a
    folder part is a path.

    Raises
    ------
    InputError
        Naming the missing file, or listing the built-ins when a bare name matches none.
    """
    text = os.fspath(name_or_path)
    path = Path(text)
    if names_builtin(text):
        builtin = data_path(folder, f"{text}{suffix}")
        if builtin.is_file():
            return builtin
        if not path.is_file():
            known = ", ".join(builtin_names(folder, suffix)) or "none"
            raise InputError(f'no built-in {what} "{text}" (built-in: {known}; a file of your own is written as a '
                             f'path, such as ./{text}{suffix})')
    if not path.is_file():
        raise InputError(f"no such {what} file", path)
    return path


def read_document(path: Path) -> dict:
    """Parse a ``.json`` or ``.toml`` file into a dict; an undecodable file is an :class:`InputError`.

    A file is read once per process while it is unchanged (same modification time and size):
    a built-in marker set, mapping or face that several stages load costs one read. Each call
    returns its own copy, free to change.
    """
    stat = path.stat()
    try:
        doc = _copied(_parsed(path.resolve(), stat.st_mtime_ns, stat.st_size))
    except InputError as exc:
        raise InputError(exc.message, path) from None  # named as the caller named it
    assert isinstance(doc, dict)
    return doc


def _copied(value: object) -> object:
    """A copy of a parsed document: its tables and arrays copied, its values (strings, numbers,
    dates: immutable) shared; several times faster than ``copy.deepcopy``, which a marker set's
    hundreds of small tables made a visible share of mapping a take."""
    if isinstance(value, dict):
        return {key: _copied(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_copied(item) for item in value]
    return value


@functools.lru_cache(maxsize=256)
def _parsed(path: Path, mtime_ns: int, size: int) -> dict:
    """The parsed document (the process's one cache: keyed by the file's path, modification time
    and size, so that a changed file is read again; errors are not kept)."""
    kind = "TOML" if path.suffix.lower() == ".toml" else "JSON"
    try:
        text = read_regular(path, MAX_DOCUMENT_BYTES, f"{kind} file").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"not valid {kind} ({exc})", path) from None
    depth = nesting_depth(text)
    if depth > MAX_NESTING:
        raise InputError(f"nested {depth} deep: deeper than the {MAX_NESTING} levels any toonface file has", path)
    try:
        doc = tomllib.loads(text) if kind == "TOML" else json.loads(text)
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise InputError(f"not valid {kind} ({exc})", path) from None
    except ValueError:  # Python refuses to convert an integer of more than 4300 digits
        raise InputError(f"not valid {kind}: a number of thousands of digits", path) from None
    if not isinstance(doc, dict):
        raise InputError(f"expected a {kind} object at the top level, got {type(doc).__name__}", path)
    return doc


def read_versioned(path: str | os.PathLike, fmt: str, what: str) -> dict:
    """Parse a project file and check its ``format`` field (``fmt``, such as
    ``"toonface.profile/1"``); a missing file or another format is an :class:`InputError`."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no such {what} file", path)
    doc = read_document(path)
    if doc.get("format") != fmt:
        raise InputError(f'unsupported format {doc.get("format")!r} (expected "{fmt}")', path, "format")
    return doc


def write_toml(doc: dict, path: str | os.PathLike) -> Path:
    """Write ``doc`` as TOML, atomically; returns the path."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(tomli_w.dumps(doc).encode())
    return Path(path)


def write_document(doc: dict, path: str | os.PathLike, what: str) -> Path:
    """Write ``doc`` as TOML or JSON, as the suffix says (both read back by :func:`read_document`).

    Raises
    ------
    InputError
        For another suffix, naming the two formats.
    """
    suffix = Path(path).suffix.lower()
    if suffix == ".toml":
        return write_toml(doc, path)
    if suffix != ".json":
        raise InputError(f"cannot write a {what} as {suffix or '(no suffix)'!r} (formats: .toml, .json)", path)
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
    return Path(path)
