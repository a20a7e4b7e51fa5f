"""Who moves a motor: a live face's values from ordered providers, each with a weight and a fade.

The layers, bottom to top (:data:`LAYERS`):

``idle``
    The face at rest, alive: the life layer (:mod:`toon.life`, the same code that brings a voice
    to life) in silence: blinks as people blink, gaze that holds and jumps, breathing and a slow
    sway of the head. Always there, under everything: a motor whose tracking is lost shows it.
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

import os
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from common import InputError, read_versioned
from common.validate import Validator, at
from toon import MOTOR_CODES, motor_index
from toon.life import MOVED, LifeMotion, LifeSettings, lay

FORMAT = "toonface.providers/1"
LAYERS = ("idle", "tracking", "motions", "manual")
#: The motors the idle face moves.
MOVED_CODES = frozenset(MOVED)
#: The newest tracked frame: values ``(21,)``, confidence ``(21,)``, seconds since it came.
Tracked = Callable[[], tuple[np.ndarray, np.ndarray, float]]


@dataclass(frozen=True)
class IdleSettings:
    """The idle face, the life layer (:mod:`toon.life`) in silence: blinks a minute and a
    blink's length, breathing's period and its head motion (motor units of HV), a fixation's
    median length and the gaze's reach near the viewer (motor units of the pupils; a look away
    reaches some three times as far), the head's sway (motor units of HH; its rise and fall in
    HV in proportion), and the seed of the randomness.
    The defaults are the life layer's, set from how people blink and look."""

    blink_per_minute: float = LifeSettings.blinks_per_minute
    blink_seconds: float = LifeSettings.blink_seconds
    breathing_seconds: float = LifeSettings.breathing_seconds
    breathing_amount: float = LifeSettings.breathing_amount
    saccade_seconds: float = LifeSettings.fixation_seconds
    saccade_amount: float = LifeSettings.gaze_near
    sway_amount: float = LifeSettings.sway
    seed: int = 0

    def life(self) -> LifeSettings:
        """These settings as the life layer's."""
        return LifeSettings(seed=self.seed, blinks_per_minute=self.blink_per_minute,
                            speaking_blinks_per_minute=self.blink_per_minute, blink_seconds=self.blink_seconds,
                            fixation_seconds=self.saccade_seconds, gaze_near=self.saccade_amount,
                            gaze_away=self.saccade_amount * LifeSettings.gaze_away / LifeSettings.gaze_near,
                            sway=self.sway_amount,
                            pitch_sway=self.sway_amount * LifeSettings.pitch_sway / LifeSettings.sway,
                            breathing_seconds=self.breathing_seconds,
                            breathing_amount=self.breathing_amount)


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
    if "blink_randomness" in idle:
        raise InputError("idle.blink_randomness is no longer read: an idle face blinks as people do (at random, "
                         "none within a second of another); remove it", path)
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
    """The idle face over time (see :class:`IdleSettings`): the life layer in silence on the
    face's neutral, at ``t`` for a ``t`` that only grows."""

    def __init__(self, neutral: np.ndarray, settings: IdleSettings) -> None:
        self.neutral = np.asarray(neutral, dtype=float)
        self.motion = LifeMotion(settings.life())

    @property
    def blinks(self) -> deque[float]:
        """When the latest blinks began (s)."""
        return self.motion.blinks

    def values(self, t: float) -> np.ndarray:
        """The idle face at ``t`` seconds ``(21,)``."""
        out = self.neutral.copy()
        lay(out, self.motion.step(t, False), MOVED_CODES)
        return out


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
