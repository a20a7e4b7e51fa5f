"""Motor tracks drawn as a score: one stave per motor, like CharToon's Animation Editor.

Each stave spans the motor's 0..1 (faint lines at 0, 0.5 and 1), the code at the left; time runs
left to right with second ticks below the last stave. A second track can be drawn over the first
(before/after a filter, truth/mapped), with each stave's RMS difference at its right. The same
staves can be printed as text (one line of block characters per motor) for terminals and notes.
"""

from __future__ import annotations

import os
from itertools import pairwise
from pathlib import Path

import cv2
import numpy as np

from player.sheet import save_image
from toon import MOTOR_CODES, MotorTrack

STAVE_PX = 48
MARGIN_LEFT, MARGIN_RIGHT, MARGIN_BOTTOM = 70, 90, 36
FIRST, SECOND = (30, 60, 150), (235, 120, 20)  # RGB
_BLOCKS = "▁▂▃▄▅▆▇█"  # 0 is the lowest bar, not a blank that reads as missing data


def score_image(track: MotorTrack, other: MotorTrack | None = None, codes: tuple[str, ...] | None = None,
                width: int = 1200, sound: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """The score as an RGB image ``(height, width, 3)`` uint8.

    Parameters
    ----------
    track : MotorTrack
    other : MotorTrack, optional
        Drawn over ``track``; its own times are used (its rate may differ).
    codes : tuple of str, optional
        Motors to draw, in order; default all 21 and then the track's parameters beyond them.
    width : int
        Pixels.
    sound : tuple of ndarray, optional
        ``(times, loudness in [0, 1])`` drawn as a last stave, ``sound``, filled (to check a
        mouth against the voice; :func:`common.sound.sound_envelope`).
    """
    codes = tuple(codes or (*MOTOR_CODES, *track.extra_codes))
    for code in codes:
        track.column(code)  # unknown codes raise, naming the code
    duration = max(track.duration, other.duration if other is not None else 0.0, 1e-6)
    plot_w = width - MARGIN_LEFT - MARGIN_RIGHT
    rows = len(codes) + (sound is not None)
    height = STAVE_PX * rows + MARGIN_BOTTOM
    image = np.full((height, width, 3), 255, np.uint8)
    for row, code in enumerate(codes):
        top = row * STAVE_PX + 6
        span = STAVE_PX - 12
        for level in (0.0, 0.5, 1.0):
            y = int(round(top + span * (1 - level)))
            grey = (225, 225, 225) if level == 0.5 else (190, 190, 190)
            cv2.line(image, (MARGIN_LEFT, y), (width - MARGIN_RIGHT, y), grey, 1)
        cv2.putText(image, code, (8, top + span // 2 + 5), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
        for source, colour in ((track, FIRST), (other, SECOND)):
            if source is None:
                continue
            if code not in MOTOR_CODES and code not in source.extra_codes:
                continue  # the other track has no such parameter
            values = source.column(code)
            xs = MARGIN_LEFT + source.times / duration * plot_w
            ys = top + span * (1 - np.clip(values, 0, 1))
            points = np.round(np.column_stack([xs, ys]) * 16).astype(np.int32)  # 4 fractional bits
            cv2.polylines(image, [points[:, None, :]], False, colour, 1, cv2.LINE_AA, shift=4)
        if other is not None and (code in MOTOR_CODES or code in other.extra_codes):
            theirs = np.interp(track.times, other.times, other.column(code))
            rms = float(np.sqrt(np.mean((track.column(code) - theirs) ** 2)))
            cv2.putText(image, f"{100 * rms:.1f}%", (width - MARGIN_RIGHT + 8, top + span // 2 + 5),
                        cv2.FONT_HERSHEY_SIMPLEX, 0.45, (90, 90, 90), 1, cv2.LINE_AA)
    if sound is not None:
        top, span = len(codes) * STAVE_PX + 6, STAVE_PX - 12
        cv2.putText(image, "sound", (8, top + span // 2 + 5), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1,
                    cv2.LINE_AA)
        times, loud = sound
        xs = MARGIN_LEFT + np.clip(times / duration, 0, 1) * plot_w
        ys = top + span * (1 - np.clip(loud, 0, 1))
        outline = np.column_stack([np.r_[xs[:1], xs, xs[-1:]], np.r_[top + span, ys, top + span]])
        cv2.fillPoly(image, [np.round(outline).astype(np.int32)[:, None, :]], (150, 150, 150), cv2.LINE_AA)
    axis_y = STAVE_PX * rows + 4
    step = _tick_step(duration)
    for second in np.arange(0.0, duration + 1e-9, step):
        x = int(round(MARGIN_LEFT + second / duration * plot_w))
        cv2.line(image, (x, axis_y), (x, axis_y + 5), (0, 0, 0), 1)
        cv2.putText(image, f"{second:g}s", (x - 10, axis_y + 20), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (0, 0, 0), 1,
                    cv2.LINE_AA)
    return image


def save_score(track: MotorTrack, path: str | os.PathLike, other: MotorTrack | None = None,
               codes: tuple[str, ...] | None = None, width: int = 1200,
               sound: tuple[np.ndarray, np.ndarray] | None = None) -> Path:
    """Write :func:`score_image` as PNG (atomically)."""
    return save_image(score_image(track, other, codes, width, sound), path)


def score_text(track: MotorTrack, codes: tuple[str, ...] | None = None, columns: int = 60) -> list[str]:
    """One line per motor: its code, then ``columns`` block characters (the mean value in each
    slice of time, 0 blank to 1 full), then its range."""
    lines = []
    edges = np.linspace(0, track.frames, columns + 1).astype(int)
    for code in codes or (*MOTOR_CODES, *track.extra_codes):
        values = track.column(code)
        means = [values[a:max(b, a + 1)].mean() for a, b in pairwise(edges)]
        bar = "".join(_BLOCKS[int(round(np.clip(v, 0, 1) * (len(_BLOCKS) - 1)))] for v in means)
        lines.append(f"{code:>3} {bar} {values.min():.2f}-{values.max():.2f}")
    return lines


def _tick_step(duration: float) -> float:
    for step in (0.1, 0.25, 0.5, 1, 2, 5, 10, 15, 30, 60, 120, 300, 600):
        if duration / step <= 12:
            return float(step)
    return 1200.0
