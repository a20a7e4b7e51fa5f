"""What the independently written synthetic performers share: what they return, the optical
sensor's faults and the rotation matrices of a head's yaw, pitch and roll (each performer
composes them its own way)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture import Take


@dataclass(frozen=True, eq=False)
class PerformedTake:
    """A performer's take, its true motors ``(F, 21)`` in ToonFace order, and its rest ``(21,)``."""

    take: Take
    motors: np.ndarray
    rest: np.ndarray


def sensor_faults(world: np.ndarray, rate: float, rng: np.random.Generator) -> np.ndarray:
    """Positions ``(F, M, 3)`` as an optical system reports them: 0.3 mm jitter, 0.5 s gaps until
    10 % of samples are missing (NaN), and 1 % spikes of 5-15 mm."""
    out = world + rng.normal(0.0, 0.3, world.shape)
    frames, markers = out.shape[:2]
    gap = int(round(0.5 * rate))
    missing = np.zeros((frames, markers), bool)
    while missing.mean() < 0.10:
        start, m = int(rng.integers(0, frames - gap)), int(rng.integers(markers))
        missing[start:start + gap, m] = True
    spikes = rng.random((frames, markers)) < 0.01
    direction = rng.normal(size=(frames, markers, 3))
    direction /= np.linalg.norm(direction, axis=2, keepdims=True)
    out = np.where(spikes[..., None], out + direction * rng.uniform(5, 15, (frames, markers, 1)), out)
    out[missing] = np.nan
    return out


def axis_rotations(yaw: np.ndarray, pitch: np.ndarray, roll: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-frame rotations ``(F, 3, 3)`` about y by ``yaw`` (the face toward +x), about x by
    ``pitch`` (the face toward +y: chin up) and about z by ``roll``, radians ``(F,)``."""
    c, s = np.cos, np.sin
    one, zero = np.ones_like(yaw), np.zeros_like(yaw)
    ry = np.stack([np.stack([c(yaw), zero, s(yaw)], -1), np.stack([zero, one, zero], -1),
                   np.stack([-s(yaw), zero, c(yaw)], -1)], -2)
    rx = np.stack([np.stack([one, zero, zero], -1), np.stack([zero, c(pitch), s(pitch)], -1),
                   np.stack([zero, -s(pitch), c(pitch)], -1)], -2)
    rz = np.stack([np.stack([c(roll), -s(roll), zero], -1), np.stack([s(roll), c(roll), zero], -1),
                   np.stack([zero, zero, one], -1)], -2)
    return ry, rx, rz
