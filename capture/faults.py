"""Realistic capture faults for synthetic takes, each seeded and switchable.

Applied in this order to a clean take: slow drift (each marker wanders by a smooth random walk
of ``drift_mm`` standard size), jitter (Gaussian, ``jitter_mm`` per coordinate), single-frame
spikes (``spike_rate`` per marker-frame, ``spike_mm`` long), marker swaps (``swap_rate`` per
frame: two nearby markers exchange labels for ``swap_frames`` frames, as a labelling solver
does), and occlusion windows (``gap_rate`` per marker per second, ``gap_seconds`` long: NaN).
The returned mask says which samples were hit, so a cleaning stage can be scored against it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from capture.take import Take


@dataclass(frozen=True)
class Faults:
    """Fault sizes; zero switches a fault off."""

    jitter_mm: float = 0.0
    gap_rate: float = 0.0
    gap_seconds: float = 0.3
    spike_rate: float = 0.0
    spike_mm: float = 15.0
    swap_rate: float = 0.0
    swap_frames: int = 10
    drift_mm: float = 0.0

    def active(self) -> dict[str, float]:
        """The faults switched on, with their settings (``gap_seconds`` only with gaps, and so on)."""
        on = {"jitter_mm": self.jitter_mm, "gap_rate": self.gap_rate, "spike_rate": self.spike_rate,
              "swap_rate": self.swap_rate, "drift_mm": self.drift_mm}
        on = {k: v for k, v in on.items() if v}
        for switch, setting in (("gap_rate", "gap_seconds"), ("spike_rate", "spike_mm"), ("swap_rate", "swap_frames")):
            if switch in on:
                on[setting] = getattr(self, setting)
        return on


def apply_faults(take: Take, faults: Faults, seed: int = 0) -> tuple[Take, dict[str, np.ndarray]]:
    """A faulty copy of ``take`` and, per fault, a bool mask ``(frames, markers)`` of the samples it hit."""
    rng = np.random.default_rng(seed)
    pos = np.array(take.positions)
    frames, markers = pos.shape[:2]
    hit = {name: np.zeros((frames, markers), dtype=bool) for name in ("spike", "swap", "gap")}
    if faults.drift_mm:
        steps = rng.normal(0.0, 1.0, size=(frames, markers, 3))
        walk = np.cumsum(steps, axis=0) / np.sqrt(max(frames, 1))
        pos += faults.drift_mm * walk
    if faults.jitter_mm:
        pos += rng.normal(0.0, faults.jitter_mm, size=pos.shape)
    if faults.spike_rate:
        hit["spike"] = rng.random((frames, markers)) < faults.spike_rate
        direction = rng.normal(size=(frames, markers, 3))
        direction /= np.linalg.norm(direction, axis=2, keepdims=True)
        pos[hit["spike"]] += faults.spike_mm * direction[hit["spike"]]
    if faults.swap_rate and markers > 1:
        for start in np.flatnonzero(rng.random(frames) < faults.swap_rate):
            a = int(rng.integers(markers))
            dist = np.linalg.norm(take.positions[start] - take.positions[start, a], axis=1)
            dist[a] = np.inf
            b = int(np.nanargmin(dist)) if np.isfinite(dist).any() else (a + 1) % markers
            span = slice(start, min(start + faults.swap_frames, frames))
            pos[span, [a, b]] = pos[span, [b, a]]
            hit["swap"][span, [a, b]] = True
    if faults.gap_rate:
        length = max(1, round(faults.gap_seconds * take.rate))
        starts = rng.random((frames, markers)) < faults.gap_rate / take.rate
        for f, m in zip(*np.nonzero(starts), strict=True):
            hit["gap"][f: f + length, m] = True
        pos[hit["gap"]] = np.nan
    meta = {**take.meta, "faults": faults.active(), "fault_seed": seed}
    return Take(pos, take.labels, take.rate, times=take.times, dims=take.dims, meta=meta), hit
