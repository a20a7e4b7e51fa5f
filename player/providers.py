"""Who moves a motor: a live face's values from ordered providers, each with a weight and a fade.

The layers, bottom to top (:data:`LAYERS`):

``idle``
    The face at rest, alive: blinks at a rate with some randomness, breathing (the head rises
    and falls a little), and small saccades of the gaze. Always there, under everything.
``tracking``
    A performer (``play --source``, ``--vmc``, ``--openseeface``, a stream or a track), each
    motor as present as its tracker is sure of it: a motor whose tracking is lost (confidence 0,
    or no frame for ``lost_after`` seconds) passes to idle, and back when tracking returns.
``motions``
    Commands, motions and expressions (the Animator): present on a motor while it moves. Over
    tracking, a motion blends on top and then releases; with no tracking, a motor it left away
    from rest stays where it was put (a plain ``MB 1 500`` holds), one it brought back (a blink)
    returns to idle.
``manual``
    Overrides (``hold CODE VALUE``; ``release``), over everything.

Each layer offers, per motor, a value and a presence (0..1); its envelope follows presence times
the layer's weight, moving at most 1/``fade`` a second, so that a provider that appears or leaves
fades in or out. The face is idle with each layer laid over it in turn:
``out += envelope * (value - out)``. :meth:`Mixer.who` names the layer that gives each motor most.

Settings are a ``toonface.providers/1`` TOML file (:func:`load_providers`), every field optional.
"""

from __future__ import annotations

import math
import os
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from common import read_versioned
from common.validate import Validator, at
from toon import MOTOR_CODES, motor_index

FORMAT = "toonface.providers/1"
LAYERS = ("idle", "tracking", "motions", "manual")
#: Blink times an idle face keeps (a player may run for days).
BLINKS_KEPT = 1000
#: The newest tracked frame: values ``(21,)``, confidence ``(21,)``, seconds since it came.
Tracked = Callable[[], tuple[np.ndarray, np.ndarray, float]]


@dataclass(frozen=True)
class IdleSettings:
    """The idle face: blinks a minute and how irregular (0: a metronome), a blink's length,
    breathing's period and its head motion (motor units of HV), saccades' mean interval and
    reach (motor units of the pupils), and the seed of the randomness."""

    blink_per_minute: float = 15.0
    blink_randomness: float = 0.4
    blink_seconds: float = 0.2
    breathing_seconds: float = 4.0
    breathing_amount: float = 0.01
    saccade_seconds: float = 2.0
    saccade_amount: float = 0.04
    seed: int = 0


@dataclass(frozen=True)
class LayerSettings:
    """A layer's weight (0..1: how much of it shows when fully present) and fade (seconds)."""

    weight: float = 1.0
    fade: float = 0.25


@dataclass(frozen=True)
class Providers:
    """Every layer's settings (defaults: a face that blinks and breathes, tracking fading over
    0.3 s and lost after 0.3 s without a frame)."""

    idle: IdleSettings = IdleSettings()
    tracking: LayerSettings = LayerSettings(fade=0.3)
    motions: LayerSettings = LayerSettings(fade=0.25)
    manual: LayerSettings = LayerSettings(fade=0.1)
    lost_after: float = 0.3
    idle_on: bool = True


def load_providers(path: str | os.PathLike | None) -> Providers:
    """The settings in ``path`` (``toonface.providers/1``), the defaults where it says nothing
    (None: all defaults). Errors name the file and the field."""
    if path is None:
        return Providers()
    doc = read_versioned(path, FORMAT, "providers")
    check = Validator(path)
    check.fields(doc, {"format", "idle", "tracking", "motions", "manual"}, "", "a providers file")
    out = Providers()
    idle = doc.get("idle", {})
    check.fields(idle, {f.name for f in fields(IdleSettings)} | {"enabled"}, "idle", "idle")
    values: dict[str, Any] = {}
    for f in fields(IdleSettings):
        if f.name in idle:
            if f.name == "seed":
                values[f.name] = check.integer(idle[f.name], at("idle", f.name), 0, 2**31 - 1)
            else:
                values[f.name] = check.number(idle[f.name], at("idle", f.name), 0.0, 1e4)
    out = replace(out, idle=replace(out.idle, **values),
                  idle_on=check.boolean(idle.get("enabled", True), at("idle", "enabled")))
    layers: dict[str, LayerSettings] = {}
    for layer in ("tracking", "motions", "manual"):
        spec = doc.get(layer, {})
        check.fields(spec, {"weight", "fade"} | ({"lost_after"} if layer == "tracking" else set()), layer, layer)
        current: LayerSettings = getattr(out, layer)
        layers[layer] = LayerSettings(
            weight=check.number(spec.get("weight", current.weight), at(layer, "weight"), 0.0, 1.0),
            fade=check.number(spec.get("fade", current.fade), at(layer, "fade"), 0.0, 60.0))
    lost = doc.get("tracking", {}).get("lost_after", out.lost_after)
    return replace(out, tracking=layers["tracking"], motions=layers["motions"], manual=layers["manual"],
                   lost_after=check.number(lost, at("tracking", "lost_after"), 0.0, 60.0))


class Idle:
    """The idle face over time (see :class:`IdleSettings`): its values at ``t`` for a ``t`` that
    only grows."""

    def __init__(self, neutral: np.ndarray, settings: IdleSettings) -> None:
        self.neutral = np.asarray(neutral, dtype=float)
        self.s = settings
        self.rng = np.random.default_rng(settings.seed)
        self.blinks: deque[float] = deque(maxlen=BLINKS_KEPT)  # when the latest blinks began
        self._next_blink = self._next_saccade = math.nan
        self._gaze = np.zeros(2)

    def _interval(self, mean: float, spread: float) -> float:
        return mean * max(0.2, 1.0 + spread * float(self.rng.standard_normal())) if mean > 0 else math.inf

    def values(self, t: float) -> np.ndarray:
        """The idle face at ``t`` seconds ``(21,)``."""
        s = self.s
        blink_mean = 60.0 / s.blink_per_minute if s.blink_per_minute > 0 else 0.0
        if math.isnan(self._next_blink):
            self._next_blink = t + self._interval(blink_mean, s.blink_randomness)
            self._next_saccade = t + self._interval(s.saccade_seconds, 0.5)
        while t >= self._next_blink:
            self.blinks.append(self._next_blink)
            self._next_blink += self._interval(blink_mean, s.blink_randomness)
        while t >= self._next_saccade:
            self._gaze = self.rng.uniform(-1.0, 1.0, 2) * s.saccade_amount
            self._next_saccade += self._interval(s.saccade_seconds, 0.5)
        out = self.neutral.copy()
        if self.blinks and s.blink_seconds > 0:
            phase = (t - self.blinks[-1]) / s.blink_seconds
            if 0.0 <= phase < 1.0:
                shut = 1.0 - abs(2.0 * phase - 1.0)  # down and up again
                for lid in ("ERU", "ELU"):
                    out[motor_index(lid)] *= 1.0 - shut
        if s.breathing_seconds > 0:
            out[motor_index("HV")] += s.breathing_amount * math.sin(2 * math.pi * t / s.breathing_seconds)
        for code, k in (("PRH", 0), ("PLH", 0), ("PRV", 1), ("PLV", 1)):
            out[motor_index(code)] += self._gaze[k]
        return np.clip(out, 0.0, 1.0)


@dataclass
class Mixer:
    """The live face's values from the layers (see the module docstring).

    Parameters
    ----------
    neutral : ndarray, shape (21,)
    settings : Providers
    tracking : callable, optional
        The newest tracked frame (a :data:`Tracked`), where a performer drives the face.
    motions : callable, optional
        The Animator's values ``(21,)`` and which motors it is moving ``(21,)`` bool.
    """

    neutral: np.ndarray
    settings: Providers = field(default_factory=Providers)
    tracking: Tracked | None = None
    motions: Callable[[], tuple[np.ndarray, np.ndarray]] | None = None

    def __post_init__(self) -> None:
        self.neutral = np.asarray(self.neutral, dtype=float)
        self.idle = Idle(self.neutral, self.settings.idle)
        self.manual_values = self.neutral.copy()
        self.manual_on = np.zeros(len(MOTOR_CODES), dtype=bool)
        self.envelopes = {layer: np.zeros(len(MOTOR_CODES)) for layer in LAYERS[1:]}
        self.shown = self.neutral.copy()
        self._last: float | None = None

    def hold(self, targets: dict[str, float]) -> None:
        """Manual overrides: these motors (code to value) held until released."""
        for code, value in targets.items():
            i = motor_index(code)
            self.manual_values[i] = min(max(float(value), 0.0), 1.0)
            self.manual_on[i] = True

    def release(self, codes: list[str] | None = None) -> None:
        """Let these motors (None: all) go back to the layers under manual, fading."""
        for code in codes if codes is not None else MOTOR_CODES:
            self.manual_on[motor_index(code)] = False

    def step(self, t: float) -> np.ndarray:
        """The face at ``t`` seconds ``(21,)`` (``t`` only grows); each envelope moves toward its
        layer's presence by at most the time since the last step over its fade."""
        dt = 0.0 if self._last is None else max(t - self._last, 0.0)
        first, self._last = self._last is None, t
        base = self.idle.values(t) if self.settings.idle_on else self.neutral.copy()
        layers: list[tuple[str, np.ndarray, np.ndarray]] = []
        if self.tracking is not None:
            values, confidence, age = self.tracking()
            present = np.clip(confidence, 0.0, 1.0) if age <= self.settings.lost_after else np.zeros_like(confidence)
            layers.append(("tracking", values, present))
        if self.motions is not None:
            values, active = self.motions()
            away = np.abs(values - self.neutral) > 1e-6
            present = active | away if self.tracking is None else active  # hold what was put away, alone
            layers.append(("motions", values, present.astype(float)))
        layers.append(("manual", self.manual_values, self.manual_on.astype(float)))
        out = base
        for name, values, present in layers:
            settings: LayerSettings = getattr(self.settings, name)
            target = present * settings.weight
            envelope = self.envelopes[name]
            if first or settings.fade <= 0:
                envelope[:] = target
            else:
                envelope += np.clip(target - envelope, -dt / settings.fade, dt / settings.fade)
            out = out + envelope * (np.nan_to_num(values, nan=0.0) - out) * np.isfinite(values)
        self.shown = np.clip(out, 0.0, 1.0)
        return self.shown.copy()

    def who(self) -> list[str]:
        """Per motor, the layer that gives it most in the last step."""
        remaining = np.ones(len(MOTOR_CODES))
        shares = {}
        for name in reversed(LAYERS[1:]):
            shares[name] = self.envelopes[name] * remaining
            remaining = remaining * (1.0 - self.envelopes[name])
        shares["idle"] = remaining
        names = list(shares)
        stack = np.array([shares[n] for n in names])
        return [names[k] for k in stack.argmax(axis=0)]
