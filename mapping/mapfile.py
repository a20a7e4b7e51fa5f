"""The mapping file: how a character's motors follow a performer (TOML, ``toonface.mapping/1``).

One ``[motor.CODE]`` table per mapped motor::

    [motor.MB]
    sources = [{ marker = "LIP_LOW", axis = "y", invert = true }, { distance = ["LIP_UP", "LIP_LOW"] },
               { blendshape = "jawOpen" }, { viseme = "D", weight = 0.9 }]   # kinds: mapping.sources;
                             # a viseme is a voice's mouth shape (capture.voice), read as a blendshape score;
                             # only = "increase" | "decrease": just that motion from rest counts (the other reads
                             # as rest), e.g. { distance = ["MOUTH_R", "MOUTH_L"], only = "increase", invert = true }
                             # takes away the corners' widening and not their narrowing
    combine = "max"          # max | mean | min | weighted (each source's weight)
    normalise = "profile"    # profile: the performer's range -> the motor's 0..1 | scale: units per motor unit
                             # | calibrated: a range-of-motion calibration's range where the profile has one, else scale
                             # | score: the source is a 0..1 score (a blendshape's), its own fraction of the way
    scale = 60.0             # with normalise = "scale" (or "calibrated" without such a range)
    invert = false           # the motor follows the combined value's decrease
    gain = 1.0               # range exaggeration around neutral
    offset = 0.0
    curve = [[0, 0], [0.5, 0.4], [1, 1]]   # piecewise-linear, on the motor value
    clamp = "hard"           # hard | soft | none, to `limits`
    limits = [0.0, 1.0]
    filter = { kind = "one-euro", min_cutoff = 1.0, beta = 0.5 }   # or butterworth / savitzky-golay
    max_speed = 6.0          # motor units per second
    delay = 0.0              # seconds
    loss = { policy = "ease", seconds = 0.5 }   # hold | ease (to neutral) | idle | pair (follow the other
                             # side's motor where it is seen, else ease: lids blink and eyes look together;
                             # made_up = false: not where cleaning made this side's sources up;
                             # near = ["BRC"]: this side's motors, whose moves beyond their partners'
                             # say how far this one moves with its own; theirs alone with it lost too)
    decouple = ["MB"]        # motors whose motion this one should not show (mapping.coupling)

Across motors (top level): ``mirror`` (swap sides), ``copy_side = "right"|"left"`` (one side
drives both), ``symmetric = [["BRL", "BLL"], ...]`` (pairs move as their mean), an ``[eyes]``
table (``lids = ["ERU", "ELU"]``, ``sync = 0.25``, ``closed = 0.35``: a pair of lids that blink
together and wink cleanly, see :func:`mapping.rules.eyes_pair`), and a
``[style]`` table with CharToon's style operators: ``tremble = { amplitude, frequency, motors }``,
``sharpen = { steps, motors }``, ``smooth = { seconds, motors }``, ``time_scale``.
Motors with no table stay at the face's neutral. Errors name the file and the field.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from itertools import pairwise
from pathlib import Path

from capture.voice import VISEMES
from common import read_document, resolve_builtin
from common.validate import Validator, at, is_number
from mapping.sources import AXES, BLENDSHAPE_NAMES, HEAD_AXES, KINDS, Source
from toon import MOTOR_CODES
from toon.motors import ALL_CODES, MIRROR_OF

FORMAT = "toonface.mapping/1"
COMBINES = ("max", "mean", "min", "weighted")
#: A source's ``only``: just its increase from rest counts, or just its decrease.
ONLY = ("increase", "decrease")
CLAMPS = ("hard", "soft", "none")
NORMALISES = ("profile", "scale", "calibrated", "score")
POLICIES = ("hold", "ease", "idle", "pair")
FILTERS = {"one-euro": {"min_cutoff", "beta", "d_cutoff"}, "butterworth": {"cutoff", "order"},
           "savitzky-golay": {"window", "order"}}
_MOTOR_KEYS = {"sources", "combine", "normalise", "scale", "invert", "gain", "offset", "curve", "clamp", "limits",
               "filter", "max_speed", "delay", "loss", "decouple"}
_TOP_KEYS = {"format", "name", "description", "markerset", "mirror", "copy_side", "symmetric", "eyes", "motor",
             "style"}


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
    decouple: tuple[str, ...] = ()
    loss_made_up: bool = True
    loss_near: tuple[str, ...] = ()


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
class Eyes:
    """A pair of lid motors that blink together and wink cleanly (:func:`mapping.rules.eyes_pair`);
    no ``lids``: off."""

    lids: tuple[str, ...] = ()
    sync: float = 0.25
    closed: float = 0.35


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
    eyes: Eyes = Eyes()
    #: Motors whose rules were left out because the take lacks their markers (see
    #: :func:`mapping.workflow.choose_mapping`): they stay at the face's neutral.
    left_out: tuple[str, ...] = ()
    #: The marker set's markers the take lacks that those rules read.
    absent: tuple[str, ...] = ()

    def left_out_note(self) -> str | None:
        """What a user is told of :attr:`left_out` (None where nothing was)."""
        if not self.left_out:
            return None
        which = f" {', '.join(self.absent)}" if self.absent else ""
        return (f"the take has no marker{which}: motor{'' if len(self.left_out) == 1 else 's'} "
                f"{', '.join(self.left_out)} {'stays' if len(self.left_out) == 1 else 'stay'} at the face's neutral "
                "(not driven from other markers)")

    @property
    def extra_codes(self) -> tuple[str, ...]:
        """The parameters beyond the 21 its rules drive (``HT``), in :data:`toon.motors.ALL_CODES` order."""
        driven = {rule.code for rule in self.rules}
        return tuple(code for code in ALL_CODES[len(MOTOR_CODES):] if code in driven)

    def sources(self) -> list[Source]:
        """Every source the rules read (each once, by key)."""
        seen: dict[str, Source] = {}
        for rule in self.rules:
            for source in rule.sources:
                seen.setdefault(source.key, source)
        return list(seen.values())


def load_mapping(name_or_path: str | os.PathLike) -> Mapping:
    """A built-in mapping by name (``toon32``, ``animface41``, ``gluedots16``, ``face``) or a TOML file."""
    path = resolve_builtin(name_or_path, "mappings", ".toml", "mapping")
    return parse_mapping(read_document(path), path)


def parse_mapping(doc: dict, path: str | os.PathLike = "<mapping>") -> Mapping:
    """Validate a mapping document; raises :class:`InputError` naming ``path`` and the field."""
    check = Validator(Path(path))
    if doc.get("format") != FORMAT:
        check.fail(f'unsupported format {doc.get("format")!r} (expected "{FORMAT}")', "format")
    check.fields(doc, _TOP_KEYS, "")
    markerset = check.text(check.present(doc.get("markerset"), "markerset"), "markerset", empty=False)
    if (Path(markerset).suffix or "/" in markerset) and not Path(markerset).is_absolute() and path != "<mapping>":
        markerset = str(Path(path).parent / markerset)  # a file named in a file: beside it, not in the cwd
    motors = doc.get("motor", {})
    check.require(isinstance(motors, dict) and bool(motors), "expected at least one [motor.CODE] table", "motor")
    rules = tuple(_rule(check, code, spec) for code, spec in motors.items())
    copy_side = check.choice(doc.get("copy_side", ""), ("", "right", "left"), "copy_side")
    pairs = doc.get("symmetric", [])
    check.require(isinstance(pairs, list) and all(isinstance(p, list) and len(p) == 2 for p in pairs),
                  f"expected a list of [right, left] motor pairs, got {pairs!r}", "symmetric")
    for i, pair in enumerate(pairs):
        for code in pair:
            check.choice(code, MOTOR_CODES, at("symmetric", i))
    mapped = {r.code for r in rules}
    for rule in rules:
        for i, other in enumerate(rule.decouple):
            check.require(other in mapped, f"motor {other} has no [motor.{other}] table to measure its motion by",
                          at(at(f"motor.{rule.code}", "decouple"), i))
        for i, other in enumerate(rule.loss_near):
            check.require(other in mapped and other != rule.code and MIRROR_OF.get(other) != rule.code,
                          f"expected a mapped motor other than this one and its partner, got {other}",
                          at(at(f"motor.{rule.code}", "loss.near"), i))
        if rule.loss == "pair":
            partner = MIRROR_OF.get(rule.code)
            check.require(partner is not None, f"expected a motor with one on the other side ({', '.join(MIRROR_OF)}) "
                          f"for the pair policy", at(f"motor.{rule.code}", "loss.policy"))
            check.require(partner in mapped, f"the pair policy follows motor {partner}, which has no "
                          f"[motor.{partner}] table",
                          at(f"motor.{rule.code}", "loss.policy"))
    return Mapping(str(doc.get("name", Path(path).stem)), markerset, rules,
                   check.boolean(doc.get("mirror", False), "mirror"), copy_side,
                   tuple(tuple(p) for p in pairs), _style(check, doc.get("style", {})),
                   str(doc.get("description", "")), str(path), _eyes(check, doc.get("eyes", {})))


def _eyes(check: Validator, spec: object) -> Eyes:
    part = check.fields(spec, {"lids", "sync", "closed"}, "eyes")
    if not part:
        return Eyes()
    lids = check.strings(check.present(part.get("lids"), "eyes.lids"), "eyes.lids")
    check.require(len(lids) == 2 and lids[0] != lids[1], f"expected two lid motors [right, left], got {lids!r}",
                  "eyes.lids")
    for i, code in enumerate(lids):
        check.choice(code, MOTOR_CODES, at("eyes.lids", i))
    return Eyes(tuple(lids), check.number(part.get("sync", 0.25), "eyes.sync", 0.0, 1.0),
                check.number(part.get("closed", 0.35), "eyes.closed", 0.0, 0.95))


def _rule(check: Validator, code: str, spec: object) -> MotorRule:
    where = f"motor.{code}"
    check.choice(code, ALL_CODES, where)  # the 21 and the standard extras (HT)
    check.fields(spec, _MOTOR_KEYS, where)
    assert isinstance(spec, dict)  # fields() checked it
    raw = spec.get("sources") or []
    check.require(isinstance(raw, list) and bool(raw), f"expected a list of at least one source, got {raw!r}",
                  at(where, "sources"))
    sources = tuple(_source(check, s, at(at(where, "sources"), i)) for i, s in enumerate(raw))
    combine = check.choice(spec.get("combine", "max"), COMBINES, at(where, "combine"))
    normalise = check.choice(spec.get("normalise", "profile"), NORMALISES, at(where, "normalise"))
    scale = check.number(spec.get("scale", 1.0), at(where, "scale"))
    check.require(scale != 0, "expected a number other than 0, got 0", at(where, "scale"))
    curve = spec.get("curve", [])
    check.require(isinstance(curve, list) and all(isinstance(p, list) and len(p) == 2 and all(is_number(v) for v in p)
                                                  for p in curve),
                  f"expected a list of [input, output] points, got {curve!r}", at(where, "curve"))
    check.require(len(curve) != 1 and all(b[0] > a[0] for a, b in pairwise(curve)),
                  "expected at least 2 points with increasing inputs", at(where, "curve"))
    limits = spec.get("limits", [0.0, 1.0])
    low, high = check.numbers(limits, 2, at(where, "limits"))
    check.require(0 <= low < high <= 1, f"expected [low, high] with 0 <= low < high <= 1, got {limits!r}",
                  at(where, "limits"))
    loss = check.fields(spec.get("loss", {}), {"policy", "seconds", "made_up", "near"}, at(where, "loss"),
                        "a table { policy, seconds }")
    made_up = check.boolean(loss.get("made_up", True), at(where, "loss.made_up"))
    check.require(made_up or loss.get("policy") == "pair", "made_up = false is for the pair policy",
                  at(where, "loss.made_up"))
    near = tuple(check.strings(loss.get("near", []), at(where, "loss.near")))
    check.require(not near or loss.get("policy") == "pair", "near is for the pair policy", at(where, "loss.near"))
    invert = check.boolean(spec.get("invert", False), at(where, "invert"))
    decouple = tuple(check.strings(spec.get("decouple", []), at(where, "decouple")))
    for i, other in enumerate(decouple):
        check.choice(other, tuple(c for c in MOTOR_CODES if c != code), at(at(where, "decouple"), i))
    return MotorRule(code, sources, combine, normalise, scale, invert,
                     check.number(spec.get("gain", 1.0), at(where, "gain")),
                     check.number(spec.get("offset", 0.0), at(where, "offset")),
                     tuple((float(a), float(b)) for a, b in curve),
                     check.choice(spec.get("clamp", "hard"), CLAMPS, at(where, "clamp")), (low, high),
                     _filter(check, spec.get("filter", {}), at(where, "filter")),
                     check.number(spec.get("max_speed", 0.0), at(where, "max_speed"), 0.0),
                     check.number(spec.get("delay", 0.0), at(where, "delay"), 0.0),
                     check.choice(loss.get("policy", "hold"), POLICIES, at(where, "loss.policy")),
                     check.number(loss.get("seconds", 0.5), at(where, "loss.seconds"), 0.0), decouple, made_up, near)


def _source(check: Validator, spec: object, where: str) -> Source:
    check.require(isinstance(spec, dict), f'expected a table such as {{ marker = "LID_R_UP", axis = "y" }}, got '
                  f"{spec!r}", where)
    assert isinstance(spec, dict)
    kinds = [k for k in (*KINDS, "viseme") if k in spec]
    check.require(len(kinds) == 1, f"expected exactly one of {', '.join((*KINDS, 'viseme'))}", where)
    kind = kinds[0]
    check.fields(spec, {kind, "axis", "invert", "weight", "only"} if kind not in ("blendshape", "viseme")
                 else {kind, "invert", "weight", "only"}, where)
    value = spec[kind]
    if kind == "viseme":  # a mouth shape's weight from a voice: a score, read as a blendshape's is
        check.require(value in VISEMES, f"expected one of the mouth shapes {', '.join(VISEMES)}, got {value!r}",
                      at(where, kind))
        kind, value = "blendshape", f"viseme_{value}"
    count = {"marker": 1, "distance": 2, "difference": 2, "angle": 3}.get(kind, 0)
    markers: tuple[str, ...] | list[str]
    channel = ""
    if kind == "blendshape":
        check.require(value in BLENDSHAPE_NAMES or value in {f"viseme_{v}" for v in VISEMES},
                      "expected one of ARKit's blendshape names (jawOpen, "
                      f"eyeBlinkLeft, ...), got {value!r}", at(where, kind))
        markers, axis, channel = (), 0, str(value)
    elif kind == "head":
        markers, axis = (), HEAD_AXES.index(check.choice(value, HEAD_AXES, at(where, "head")))
    else:
        markers = (value,) if kind == "marker" and isinstance(value, str) else value
        check.require(isinstance(markers, (list, tuple)) and len(markers) == count
                      and all(isinstance(m, str) and m for m in markers),
                      f"expected {count} marker name{'s' if count > 1 else ''}, got {value!r}", at(where, kind))
        axis = AXES.index(check.choice(spec.get("axis", "y"), tuple(AXES), at(where, "axis")))
    weight = check.number(spec.get("weight", 1.0), at(where, "weight"))
    only = check.choice(spec["only"], ONLY, at(where, "only")) if "only" in spec else ""
    return Source(kind, tuple(markers), axis, check.boolean(spec.get("invert", False), at(where, "invert")), weight,
                  channel, only)


def _filter(check: Validator, spec: object, where: str) -> dict:
    check.require(isinstance(spec, dict), f'expected a table such as {{ kind = "one-euro", min_cutoff = 1.0, '
                  f"beta = 0.5 }}, got {spec!r}", where)
    assert isinstance(spec, dict)
    if not spec:
        return {}
    kind = check.choice(spec.get("kind"), tuple(FILTERS), at(where, "kind"))
    check.fields(spec, FILTERS[kind] | {"kind"}, where)
    for key in FILTERS[kind]:
        if key in spec:
            check.number(spec[key], at(where, key), 0.0)
    return dict(spec)


def _style(check: Validator, spec: object) -> Style:
    check.fields(spec, {"tremble", "sharpen", "smooth", "time_scale"}, "style")
    assert isinstance(spec, dict)
    parts = {}
    for name, keys in (("tremble", {"amplitude", "frequency", "motors"}), ("sharpen", {"steps", "motors"}),
                       ("smooth", {"seconds", "motors"})):
        where = at("style", name)
        part = check.fields(spec.get(name, {}), keys, where)
        motors = part.get("motors", [])
        check.require(isinstance(motors, list), f"expected a list of motor codes, got {motors!r}", at(where, "motors"))
        for i, code in enumerate(motors):
            check.choice(code, MOTOR_CODES, at(at(where, "motors"), i))
        parts[name] = (part, tuple(motors))
    steps = parts["sharpen"][0].get("steps", 0)
    check.require(isinstance(steps, int) and not isinstance(steps, bool) and steps >= 0 and steps != 1,
                  f"expected 0 (off) or an integer of at least 2, got {steps!r}", "style.sharpen.steps")
    scale = check.number(spec.get("time_scale", 1.0), "style.time_scale")
    check.require(scale > 0, f"expected a number above 0, got {scale:g}", "style.time_scale")
    tremble, smooth = parts["tremble"][0], parts["smooth"][0]
    return Style(check.number(tremble.get("amplitude", 0.0), "style.tremble.amplitude", 0.0),
                 check.number(tremble.get("frequency", 6.0), "style.tremble.frequency", 0.0),
                 parts["tremble"][1], steps, parts["sharpen"][1],
                 check.number(smooth.get("seconds", 0.0), "style.smooth.seconds", 0.0), parts["smooth"][1], scale)
