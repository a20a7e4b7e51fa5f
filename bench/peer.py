"""A plain peer for the fidelity figures: the pipeline anyone would write in forty lines.

Kabsch on the head references (against their mean shape over the rest window), every marker in
that frame, gaps bridged by straight lines, a 5-sample median, a zero-phase 4th-order 5 Hz
Butterworth, then each motor's sources (the mapping's marker coordinates and head angles)
normalised by their 1st and 99th percentiles over the range-of-motion sweep, straight onto the
motor's 0..1, and averaged. No spike test, no gap model, no two-sided normalisation.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from capture import MarkerSet, Take
from mapping import Mapping
from toon import MOTOR_CODES


def plain_pipeline(take: Take, mapping: Mapping, markerset: MarkerSet, rest: tuple[float, float],
                   sweep: tuple[float, float]) -> np.ndarray:
    """Motors ``(F, 21)`` of ``take`` by the plain pipeline; ``rest`` and ``sweep`` in seconds."""
    rows = [take.index(r) for r in markerset.head_reference]
    at_rest = take.window(*rest)
    shape = np.nanmean(take.positions[at_rest][:, rows], axis=0)
    rotation = np.tile(np.eye(3), (take.frames, 1, 1))
    local = np.full(take.positions.shape, np.nan)
    for f in range(take.frames):
        seen = np.isfinite(take.positions[f, rows, 0])
        if seen.sum() < 3:
            continue
        a, b = shape[seen], take.positions[f, rows][seen]
        u, _, vt = np.linalg.svd((b - b.mean(0)).T @ (a - a.mean(0)))
        r = u @ np.diag([1, 1, np.sign(np.linalg.det(u @ vt))]) @ vt
        rotation[f] = r
        local[f] = (take.positions[f] - b.mean(0) + r @ a.mean(0)) @ r
    face = rotation[:, :, 2]
    head = np.degrees(np.column_stack([np.arctan2(face[:, 0], face[:, 2]), np.arcsin(np.clip(face[:, 1], -1, 1))]))
    channels = np.column_stack([local.reshape(take.frames, -1), head])
    for c in range(channels.shape[1]):
        seen = np.isfinite(channels[:, c])
        if seen.any():
            channels[:, c] = np.interp(take.times, take.times[seen], channels[seen, c])
    channels = signal.medfilt(channels, (5, 1))
    channels = signal.sosfiltfilt(signal.butter(4, 5.0, fs=take.rate, output="sos"), channels, axis=0)
    in_sweep = take.window(*sweep)
    out = np.full((take.frames, len(MOTOR_CODES)), np.nan)
    for rule in mapping.rules:
        if rule.code not in MOTOR_CODES:  # the peer maps the 21 motors (HT: issue 42)
            continue
        parts = []
        for source in rule.sources:
            if source.kind == "head":
                x = channels[:, -2 + source.axis]
            else:
                x = channels[:, take.index(source.markers[0]) * 3 + source.axis]
            low, high = np.percentile(x[in_sweep], [1, 99])
            part = (x - low) / max(high - low, 1e-9)
            parts.append(1 - part if source.invert != rule.invert else part)
        out[:, MOTOR_CODES.index(rule.code)] = np.clip(np.mean(parts, axis=0), 0, 1)
    return out


def scores(values: np.ndarray, truth: np.ndarray, rest: np.ndarray | None = None) -> dict:
    """RMSE (% of range) raw, with each motor's gain and offset fitted away, and (given the
    performer's ``rest`` ``(21,)``) with a separate gain either side of it (``two_sided_pct``:
    how a rest maps onto a face's own does not count), and each motor's correlation with the
    truth, over frames ``(F, 21)`` (``r`` leaves out a motor whose truth never moves: its
    correlation means nothing, and read as 0 it would be any take's lowest)."""
    fitted = np.empty_like(values)
    sided = np.empty_like(values)
    r = np.empty(values.shape[1])
    for c in range(values.shape[1]):
        design = np.column_stack([values[:, c], np.ones(len(values))])
        coef, *_ = np.linalg.lstsq(design, truth[:, c], rcond=None)
        fitted[:, c] = design @ coef
        if rest is not None:
            off = values[:, c] - rest[c]
            both = np.column_stack([np.minimum(off, 0.0), np.maximum(off, 0.0), np.ones(len(values))])
            coef, *_ = np.linalg.lstsq(both, truth[:, c], rcond=None)
            sided[:, c] = both @ coef
        spread = values[:, c].std() * truth[:, c].std()
        r[c] = float(np.mean((values[:, c] - values[:, c].mean()) * (truth[:, c] - truth[:, c].mean())) / spread) \
            if spread > 0 else 0.0
    moving = truth.std(axis=0) > 1e-6
    out = {"raw_pct": 100 * float(np.sqrt(np.mean((values - truth) ** 2))),
           "fitted_pct": 100 * float(np.sqrt(np.mean((fitted - truth) ** 2))),
           "r": {code: round(float(x), 3) for code, x, moves in zip(MOTOR_CODES, r, moving, strict=True) if moves},
           "per_motor_pct": {code: round(100 * float(x), 2) for code, x in
                             zip(MOTOR_CODES, np.sqrt(np.mean((values - truth) ** 2, axis=0)), strict=True)}}
    if rest is not None:
        out["two_sided_pct"] = 100 * float(np.sqrt(np.mean((sided - truth) ** 2)))
    return out
