"""``life``: the life layer (:mod:`mapping.life`) against real talking faces (issue 64).

Each shared talking-face clip with sound (:mod:`bench.lipsync_data`; ``--quick``: the first four)
is heard as ``map`` hears a voice (its level and pitch), and the layer is laid on its voice; the
same clip's face is tracked (MediaPipe) and mapped onto the motors as ``retarget`` maps a video.
The same statistics are taken of both, each clip on its own (the layer seeded by the clip's
place in the list, so that the clips do not share one draw of its randomness), and the layer's
median over the clips is reported beside the clips' median and range:

``life.blinks_per_minute``, ``life.blink_seconds``
    Blinks (a lid more than half shut: the layer's, or MediaPipe's ``eyeBlink`` scores above 0.5)
    a minute, and their median length.
``life.blinks_at_pauses``
    The share of blinks that start within half a second after a pause in the voice begins.
``life.fixation_seconds``
    The median time between saccades (a step of the gaze larger than a fifth of its own range in
    one video frame: the layer's pupils, or the tracked eyes' look scores; both median-filtered
    over :data:`SMOOTH_FRAMES` first), at the video's rate.
``life.brow_range``, ``life.brow_speed``, ``life.head_range``, ``life.head_speed``
    The brows' (BRM and BLM) and the head's (HV) motion in motor units: the 5th-95th percentile
    range, and the 95th percentile of the speed (units a second).
``life.outside_real_range``
    How many of those statistics fall outside the range the clips span (goal 0).
``life.brow_pitch_lag_ms``
    The median time from each of the layer's brow raises to the nearest raise of the tracked
    brows (a peak of BRM and BLM), against the same for raises placed at random in the clip's
    speech at the same rate (the goal: the shuffled baseline, measured in the same run, 50 draws).

Where the shared clips are absent the figures are 0 without goals, ``"skipped"`` saying why.
The layer's fitted constants are chosen on these statistics by :mod:`bench.life_fit`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.signal import find_peaks, medfilt

from bench.core import Figure
from bench.lipsync_data import clips, speaker
from common import InputError
from mapping.life import LifeSettings, life_offsets, take_cues

STATS = ("blinks_per_minute", "blink_seconds", "blinks_at_pauses", "fixation_seconds", "brow_range", "brow_speed",
         "head_range", "head_speed")
#: The gaze is median-filtered over this many video frames before its saccades are counted: the
#: tracker's look scores jitter from frame to frame (unfiltered, a real speaker's eyes would
#: "jump" every 0.2 s); the layer's gaze is filtered the same way.
SMOOTH_FRAMES = 5
UNITS = {"blinks_per_minute": "1/min", "blink_seconds": "s", "blinks_at_pauses": "share", "fixation_seconds": "s",
         "brow_range": "motor units", "brow_speed": "units/s", "head_range": "motor units", "head_speed": "units/s"}


@dataclass(frozen=True)
class Tracked:
    """One clip's voice and its face, tracked and mapped, and the face's statistics."""

    name: str
    speaker: str
    rate: float  # the video's
    face_times: np.ndarray  # (frames,) on the voice's clock
    voice_times: np.ndarray  # (n,) 100 Hz
    voice: dict[str, np.ndarray]  # the voice take's channels
    real: dict[str, float]
    brow_peaks: np.ndarray  # the tracked brows' raises (s)


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``life.*`` figures."""
    found = clips()[:4] if quick else clips()
    if not found:
        why = "the shared talking-face clips are absent (../shared/realdata/video)"
        return [Figure(f"life.{name}", 0.0, UNITS[name], None, False, {"skipped": why}) for name in STATS]
    real: dict[str, list[float]] = {name: [] for name in STATS}
    layer: dict[str, list[float]] = {name: [] for name in STATS}
    lags, shuffled = [], []
    unmapped: list[str] = []
    for seed, clip in enumerate(found):
        try:
            seen = tracked(clip)
        except InputError as exc:  # a face the mapping cannot calibrate on (said in the detail)
            unmapped.append(f"{clip.name}: {exc}")
            continue
        one_layer, lag, chance = laid(seen, LifeSettings(seed=seed))
        for name in STATS:
            if np.isfinite(seen.real[name]):
                real[name].append(seen.real[name])
            if np.isfinite(one_layer[name]):
                layer[name].append(one_layer[name])
        if lag is not None and chance is not None:
            lags.append(lag)
            shuffled.append(chance)
    figures, outside = [], []
    for name in STATS:
        value = float(np.median(layer[name])) if layer[name] else float("nan")
        low, high = (min(real[name]), max(real[name])) if real[name] else (float("nan"), float("nan"))
        within = bool(low <= value <= high)
        if not within:
            outside.append(name)
        figures.append(Figure(f"life.{name}", value, UNITS[name], None, False,
                              {"real_median": round(float(np.median(real[name])), 4) if real[name] else None,
                               "real_range": [round(low, 4), round(high, 4)], "within_real_range": within,
                               "clips": len(layer[name])}))
    figures.append(Figure("life.outside_real_range", float(len(outside)), "statistics", 0.0, False,
                          {"outside": outside, "clips": len(found) - len(unmapped), "left_out": unmapped}))
    if lags:
        baseline = float(np.median(shuffled))
        figures.append(Figure("life.brow_pitch_lag_ms", float(np.median(lags)), "ms", baseline, False,
                              {"shuffled_ms": round(baseline, 1), "clips": len(lags),
                               "per_clip_ms": [round(x, 1) for x in lags]}))
    return figures


def tracked(path: Path) -> Tracked:
    """One clip heard as ``map`` hears a voice, and its face tracked (MediaPipe) and mapped as
    ``retarget`` maps a video, with the face's statistics; an InputError where its face cannot
    be mapped."""
    from capture.video_tracking import track_video
    from capture.voice_take import read_voice
    from toon import MOTOR_CODES
    from toonface.pipeline import map_onto_face

    voice = read_voice(path)
    face = track_video(path, "face")
    rate = face.rate
    motors = map_onto_face(face, life=False)  # (the first second at rest, as bench.lipsync maps them)
    column = {code: i for i, code in enumerate(MOTOR_CODES)}
    channels = {name: voice.channel(name) for name in voice.channel_names}
    cues = take_cues(channels, voice.frames, voice.rate)
    pauses = voice.times[cues.pauses] if len(cues.pauses) else np.zeros(0)

    def blend(name: str) -> np.ndarray:
        return face.channel(name) if name in face.channel_names else np.full(face.frames, np.nan)

    blink = np.nanmean([blend("eyeBlinkLeft"), blend("eyeBlinkRight")], axis=0)
    look_h = np.nanmean([blend("eyeLookOutLeft") - blend("eyeLookInLeft"),
                         blend("eyeLookInRight") - blend("eyeLookOutRight")], axis=0)
    look_v = np.nanmean([blend("eyeLookUpLeft") - blend("eyeLookDownLeft"),
                         blend("eyeLookUpRight") - blend("eyeLookDownRight")], axis=0)
    brow = motors.values[:, [column["BRM"], column["BLM"]]].mean(axis=1)
    real = {**_blinks(np.nan_to_num(blink) > 0.5, rate, face.times, pauses),
            "fixation_seconds": _fixations(look_h, look_v, rate),
            **_motion("brow", brow, rate), **_motion("head", motors.values[:, column["HV"]], rate)}
    peaks, _ = find_peaks(np.nan_to_num(brow, nan=float(np.nanmedian(brow))),
                          prominence=0.3 * max(_range(brow), 1e-6), distance=max(1, int(0.3 * rate)))
    return Tracked(path.stem, speaker(path), rate, face.times, voice.times, channels, real, face.times[peaks])


def laid(clip: Tracked, settings: LifeSettings) -> tuple[dict[str, float], float | None, float | None]:
    """The layer's statistics on a clip's voice (as :func:`tracked` takes the face's, at the
    video's frames), and the brow lag and its shuffled baseline (ms; None where there are no
    raises of either)."""
    from toon import MOTOR_CODES, standard_neutral

    column = {code: i for i, code in enumerate(MOTOR_CODES)}
    frames, times, rate = len(clip.voice_times), clip.voice_times, clip.rate
    cues = take_cues(clip.voice, frames, 1 / float(np.median(np.diff(times))), settings)
    add = life_offsets(cues, settings)
    on_video = np.clip(np.round((clip.face_times - times[0]) * cues.rate).astype(int), 0, frames - 1)
    pauses = times[cues.pauses] if len(cues.pauses) else np.zeros(0)
    neutral = standard_neutral()
    stats = {**_blinks(add["shut"][on_video] > 0.5, rate, clip.face_times, pauses),
             "fixation_seconds": _fixations(add["gaze_h"][on_video], add["gaze_v"][on_video], rate),
             **_motion("brow", neutral[column["BRM"]] + add["brow"][on_video], rate),
             **_motion("head", neutral[column["HV"]] + add["hv"][on_video], rate)}
    raises = np.array([k / cues.rate + times[0] for k, _ in cues.accents])  # each risen by its accent's peak
    if not len(raises) or not len(clip.brow_peaks):
        return stats, None, None
    lag = float(np.median([np.abs(clip.brow_peaks - t).min() for t in raises]) * 1000)
    rng = np.random.default_rng(0)
    speech = times[cues.speaking] if cues.speaking.any() else times
    chance = float(np.median([np.median([np.abs(clip.brow_peaks - t).min() for t in rng.choice(speech, len(raises))])
                              for _ in range(50)]) * 1000)
    return stats, lag, chance


def _blinks(shut: np.ndarray, rate: float, times: np.ndarray, pauses: np.ndarray) -> dict[str, float]:
    starts = np.flatnonzero(shut & ~np.concatenate([[False], shut[:-1]]))
    ends = np.flatnonzero(shut & ~np.concatenate([shut[1:], [False]])) + 1
    minutes = len(shut) / rate / 60
    at_pause = [bool(np.any((times[s] - pauses >= 0) & (times[s] - pauses <= 0.5))) for s in starts]
    return {"blinks_per_minute": len(starts) / minutes if minutes else float("nan"),
            "blink_seconds": float(np.median((ends - starts) / rate)) if len(starts) else float("nan"),
            "blinks_at_pauses": float(np.mean(at_pause)) if len(starts) else float("nan")}


def _fixations(h: np.ndarray, v: np.ndarray, rate: float) -> float:
    h, v = medfilt(np.nan_to_num(h), SMOOTH_FRAMES), medfilt(np.nan_to_num(v), SMOOTH_FRAMES)
    size = max(_range(h), _range(v), 1e-6)
    jumps = np.flatnonzero(np.hypot(np.diff(h), np.diff(v)) > 0.2 * size)
    if len(jumps):  # a saccade over two frames is one
        jumps = jumps[np.concatenate([[True], np.diff(jumps) > 1])]
    return float(np.median(np.diff(jumps)) / rate) if len(jumps) > 1 else float("nan")


def _motion(name: str, x: np.ndarray, rate: float) -> dict[str, float]:
    x = np.asarray(x, dtype=float)
    x = np.where(np.isfinite(x), x, np.nanmedian(x))
    return {f"{name}_range": _range(x), f"{name}_speed": float(np.percentile(np.abs(np.diff(x)) * rate, 95))}


def _range(x: np.ndarray) -> float:
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(np.percentile(x, 95) - np.percentile(x, 5)) if len(x) else float("nan")
