"""The mapping file: how a character's motors follow a performer (TOML, ``toonface.mapping/1``).

One ``[motor.CODE]`` table per mapped motor::

    [motor.MB]
    sources = [{ marker = "LIP_LOW", axis = "y", invert = true }, { distance = ["LIP_UP", "LIP_LOW"] }]
    combine = "max"          # max | mean | min | weighted (each source's weight)
    normalise = "profile"    # profile: the performer's range -> the motor's 0..1 | scale: units per motor unit
    scale = 60.0             # with normalise = "scale"
    invert = false           # the motor follows the combined value's decrease
    gain = 1.0               # range exaggeration around neutral
    offset = 0.0
    curve = [[0, 0], [0.5, 0.4], [1, 1]]   # piecewise-linear, on the motor value
    clamp = "hard"           # hard | soft | none, to `limits`
    limits = [0.0, 1.0]
    filter = { kind = "one-euro", min_cutoff = 1.0, beta = 0.5 }   # or butterworth / savitzky-golay
    max_speed = 6.0          # motor units per second
    delay = 0.0              # seconds
    loss = { policy = "ease", seconds = 0.5 }   # hold | ease (to neutral) | idle

Across motors (top level): ``mirror`` (swap sides), ``copy_side = "right"|"left"`` (one side
drives both), ``symmetric = [["BRL", "BLL"], ...]`` (pairs move as their mean), and a
``[style]`` table with CharToon's style operators: ``tremble = { amplitude, frequency, motors }``,
``sharpen = { steps, motors }``, ``smooth = { seconds, motors }``, ``time_scale``.
Motors with no table stay at the face's neutral. Errors name the file and the field.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path
from typing import NoReturn

from common import InputError, read_document, resolve_builtin
from mapping.sources import AXES, Source
from toon import MOTOR_CODES

FORMAT = "toonface.mapping/1"
COMBINES = ("max", "mean", "min", "weighted")
CLAMPS = ("hard", "soft", "none")
POLICIES = ("hold", "ease", "idle")
FILTERS = {"one-euro": {"min_cutoff", "beta", "d_cutoff"}, "butterworth": {"cutoff", "order"},
           "savitzky-golay": {"window", "order"}}
_MOTOR_KEYS = {"sources", "combine", "normalise", "scale", "invert", "gain", "offset", "curve", "clamp", "limits",
               "filter", "max_speed", "delay", "loss"}
_TOP_KEYS = {"format", "name", "description", "markerset", "mirror", "copy_side", "symmetric", "motor", "style"}


@dataclass(frozen=True)
class MotorRule:
    """How one motor follows its sources (fields as in the module docstring)."""

    code: str
    sources: tuple[Source, ...]
    combine: str = "max"
    normalise: str = "profile"
    scale: float = 1.0
    invert: bool = False
    gain: float = 1.0
    offset: float = 0.0
    curve: tuple[tuple[float, float], ...] = ()
    clamp: str = "hard"
    limits: tuple[float, float] = (0.0, 1.0)
    filter: dict = field(default_factory=dict)
    max_speed: float = 0.0
    delay: float = 0.0
    loss: str = "hold"
    loss_seconds: float = 0.5


@dataclass(frozen=True)
class Style:
    """CharToon's style operators, applied after mapping (empty motors tuple: all motors)."""

    tremble_amplitude: float = 0.0
    tremble_frequency: float = 6.0
    tremble_motors: tuple[str, ...] = ()
    sharpen_steps: int = 0
    sharpen_motors: tuple[str, ...] = ()
    smooth_seconds: float = 0.0
    smooth_motors: tuple[str, ...] = ()
    time_scale: float = 1.0


@dataclass(frozen=True)
class Mapping:
    """A parsed mapping file."""

    name: str
    markerset: str
    rules: tuple[MotorRule, ...]
    mirror: bool = False
    copy_side: str = ""
    symmetric: tuple[tuple[str, str], ...] = ()
    style: Style = Style()
    description: str = ""
    source: str = ""  # the file it was read from, for messages

    def sources(self) -> list[Source]:
        """Every source the rules read (each once, by key)."""
        seen: dict[str, Source] = {}
        for rule in self.rules:
            for source in rule.sources:
                seen.setdefault(source.key, source)
        return list(seen.values())


def load_mapping(name_or_path: str | os.PathLike) -> Mapping:
    """A built-in mapping by name (``toon32``, ``animface41``, ``gluedots16``) or a TOML file."""
    path = resolve_builtin(name_or_path, "mappings", ".toml", "mapping")
    return parse_mapping(read_document(path), path)


def parse_mapping(doc: dict, path: str | os.PathLike = "<mapping>") -> Mapping:
    """Validate a mapping document; raises :class:`InputError` naming ``path`` and the field."""
    check = _Checker(Path(path))
    if doc.get("format") != FORMAT:
        check.fail("format", f'unsupported format {doc.get("format")!r} (expected "{FORMAT}")')
    check.keys(doc, _TOP_KEYS, "")
    markerset = check.typed(doc, "markerset", str, "", required=True)
    if (Path(markerset).suffix or "/" in markerset) and not Path(markerset).is_absolute() and path != "<mapping>":
        markerset = str(Path(path).parent / markerset)  # a file named in a file: beside it, not in the cwd
    motors = doc.get("motor", {})
    if not isinstance(motors, dict) or not motors:
        check.fail("motor", "expected at least one [motor.CODE] table")
    rules = tuple(_rule(check, code, spec) for code, spec in motors.items())
    copy_side = check.typed(doc, "copy_side", str, "", default="")
    if copy_side not in ("", "right", "left"):
        check.fail("copy_side", f'expected "right" or "left", got {copy_side!r}')
    pairs = doc.get("symmetric", [])
    if not (isinstance(pairs, list) and all(isinstance(p, list) and len(p) == 2 for p in pairs)):
        check.fail("symmetric", "expected a list of [right, left] motor pairs")
    for i, pair in enumerate(pairs):
        for code in pair:
            check.motor(code, f"symmetric[{i}]")
    return Mapping(str(doc.get("name", Path(path).stem)), markerset, rules,
                   check.typed(doc, "mirror", bool, "", default=False), copy_side,
                   tuple(tuple(p) for p in pairs), _style(check, doc.get("style", {})),
                   str(doc.get("description", "")), str(path))


def _rule(check: _Checker, code: str, spec: object) -> MotorRule:
    where = f"motor.{code}"
    check.motor(code, where)
    if not isinstance(spec, dict):
        check.fail(where, "expected a table")
    check.keys(spec, _MOTOR_KEYS, where)
    raw = spec.get("sources")
    if not isinstance(raw, list) or not raw:
        check.fail(f"{where}.sources", "expected a list of at least one source")
    sources = tuple(_source(check, s, f"{where}.sources[{i}]") for i, s in enumerate(raw))
    combine = check.choice(spec, "combine", COMBINES, where, "max")
    normalise = check.choice(spec, "normalise", ("profile", "scale"), where, "profile")
    scale = check.number(spec, "scale", where, 1.0)
    if scale == 0:
        check.fail(f"{where}.scale", "must not be 0")
    curve = spec.get("curve", [])
    if not (isinstance(curve, list) and all(isinstance(p, list) and len(p) == 2
                                            and all(isinstance(v, (int, float)) for v in p) for p in curve)):
        check.fail(f"{where}.curve", "expected a list of [input, output] points")
    if len(curve) == 1 or any(b[0] <= a[0] for a, b in pairwise(curve)):
        check.fail(f"{where}.curve", "needs at least 2 points with increasing inputs")
    limits = spec.get("limits", [0.0, 1.0])
    if not (isinstance(limits, list) and len(limits) == 2 and all(isinstance(v, (int, float)) for v in limits)
            and 0 <= limits[0] < limits[1] <= 1):
        check.fail(f"{where}.limits", f"expected [low, high] with 0 <= low < high <= 1, got {limits!r}")
    loss = spec.get("loss", {})
    if not isinstance(loss, dict):
        check.fail(f"{where}.loss", "expected a table { policy, seconds }")
    check.keys(loss, {"policy", "seconds"}, f"{where}.loss")
    invert = check.typed(spec, "invert", bool, where, default=False)
    return MotorRule(code, sources, combine, normalise, float(scale), invert,
                     check.number(spec, "gain", where, 1.0), check.number(spec, "offset", where, 0.0),
                     tuple((float(a), float(b)) for a, b in curve), check.choice(spec, "clamp", CLAMPS, where, "hard"),
                     (float(limits[0]), float(limits[1])), _filter(check, spec.get("filter", {}), f"{where}.filter"),
                     check.number(spec, "max_speed", where, 0.0, minimum=0.0),
                     check.number(spec, "delay", where, 0.0, minimum=0.0),
                     check.choice(loss, "policy", POLICIES, f"{where}.loss", "hold"),
                     check.number(loss, "seconds", f"{where}.loss", 0.5, minimum=0.0))


def _source(check: _Checker, spec: object, where: str) -> Source:
    if not isinstance(spec, dict):
        check.fail(where, "expected a table such as { marker = \"LID_R_UP\", axis = \"y\" }")
    kinds = [k for k in ("marker", "distance", "difference", "angle", "head") if k in spec]
    if len(kinds) != 1:
        check.fail(where, "needs exactly one of marker, distance, difference, angle, head")
    kind = kinds[0]
    check.keys(spec, {kind, "axis", "invert", "weight"}, where)
    value = spec[kind]
    count = {"marker": 1, "distance": 2, "difference": 2, "angle": 3}.get(kind, 0)
    markers: tuple[str, ...] | list[str]
    if kind == "head":
        if value not in ("yaw", "pitch"):
            check.fail(f"{where}.head", f'expected "yaw" or "pitch", got {value!r}')
        markers, axis = (), ("yaw", "pitch").index(value)
    else:
        markers = (value,) if kind == "marker" and isinstance(value, str) else value
        if not (isinstance(markers, (list, tuple)) and len(markers) == count
                and all(isinstance(m, str) and m for m in markers)):
            check.fail(f"{where}.{kind}", f"expected {count} marker name{'s' if count > 1 else ''}, got {value!r}")
        axis_name = spec.get("axis", "y")
        if axis_name not in tuple(AXES):
            check.fail(f"{where}.axis", f'expected "x", "y" or "z", got {axis_name!r}')
        axis = AXES.index(axis_name)
    weight = check.number(spec, "weight", where, 1.0)
    return Source(kind, tuple(markers), axis, check.typed(spec, "invert", bool, where, default=False), weight)


def _filter(check: _Checker, spec: object, where: str) -> dict:
    if not isinstance(spec, dict):
        check.fail(where, "expected a table such as { kind = \"one-euro\", min_cutoff = 1.0, beta = 0.5 }")
    if not spec:
        return {}
    kind = spec.get("kind")
    if kind not in FILTERS:
        check.fail(f"{where}.kind", f"expected one of {', '.join(FILTERS)}, got {kind!r}")
    check.keys(spec, FILTERS[kind] | {"kind"}, where)
    for key in FILTERS[kind]:
        if key in spec:
            check.number(spec, key, where, 0.0, minimum=0.0)
    return dict(spec)


def _style(check: _Checker, spec: object) -> Style:
    if not isinstance(spec, dict):
        check.fail("style", "expected a table")
    check.keys(spec, {"tremble", "sharpen", "smooth", "time_scale"}, "style")
    parts = {}
    for name, keys in (("tremble", {"amplitude", "frequency", "motors"}), ("sharpen", {"steps", "motors"}),
                       ("smooth", {"seconds", "motors"})):
        part = spec.get(name, {})
        if not isinstance(part, dict):
            check.fail(f"style.{name}", "expected a table")
        check.keys(part, keys, f"style.{name}")
        motors = part.get("motors", [])
        if not isinstance(motors, list):
            check.fail(f"style.{name}.motors", "expected a list of motor codes")
        for code in motors:
            check.motor(code, f"style.{name}.motors")
        parts[name] = (part, tuple(motors))
    steps = parts["sharpen"][0].get("steps", 0)
    if not isinstance(steps, int) or isinstance(steps, bool) or steps < 0 or steps == 1:
        check.fail("style.sharpen.steps", f"expected 0 (off) or an integer >= 2, got {steps!r}")
    scale = check.number(spec, "time_scale", "style", 1.0)
    if scale <= 0:
        check.fail("style.time_scale", f"must be > 0, got {scale:g}")
    return Style(check.number(parts["tremble"][0], "amplitude", "style.tremble", 0.0, minimum=0.0),
                 check.number(parts["tremble"][0], "frequency", "style.tremble", 6.0, minimum=0.0),
                 parts["tremble"][1], steps, parts["sharpen"][1],
                 check.number(parts["smooth"][0], "seconds", "style.smooth", 0.0, minimum=0.0), parts["smooth"][1],
                 scale)


class _Checker:
    """Raises :class:`InputError` with the file and the dotted field path."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def fail(self, where: str, message: str) -> NoReturn:
        raise InputError(message, self.path, where or None)

    def keys(self, table: dict, known: set[str], where: str) -> None:
        unknown = sorted(set(table) - known)
        if unknown:
            self.fail(f"{where}.{unknown[0]}" if where else unknown[0],
                      f"unknown key (known: {', '.join(sorted(known))})")

    def motor(self, code: object, where: str) -> None:
        if code not in MOTOR_CODES:
            self.fail(where, f"unknown motor {code!r} (motors: {' '.join(MOTOR_CODES)})")

    def typed(self, table: dict, key: str, kind: type, where: str, default: object = None, required: bool = False):
        name = f"{where}.{key}" if where else key
        if key not in table:
            if required:
                self.fail(name, "missing")
            return default
        if not isinstance(table[key], kind):
            self.fail(name, f"expected {kind.__name__}, got {table[key]!r}")
        return table[key]

    def number(self, table: dict, key: str, where: str, default: float, minimum: float | None = None) -> float:
        value = table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(f"{where}.{key}", f"expected a number, got {value!r}")
        if minimum is not None and value < minimum:
            self.fail(f"{where}.{key}", f"must be >= {minimum:g}, got {value:g}")
        return float(value)

    def choice(self, table: dict, key: str, options: tuple[str, ...], where: str, default: str) -> str:
        value = table.get(key, default)
        if value not in options:
            self.fail(f"{where}.{key}", f"expected one of {', '.join(options)}, got {value!r}")
        return value
