"""Where a take is at rest, when nobody says: chosen from its motion and, for a video, its sound.

A take without a declared neutral needs a rest pose to measure every motion from. Motion-capture
takes conventionally start at rest, but talking-head clips often start mid-word: a rest taken on
a half-open mouth leaves the cartoon's mouth shut through the whole sentence. :func:`choose_rest`
picks, in this order:

1. **with sound** (a video's ``sound_level`` channel, :mod:`capture.video_tracking`): the stillest
   window where nobody speaks: the sound quieter than :data:`QUIET` of the loudest, kept
   :data:`SPEECH_MARGIN` seconds away from speech (lips part before the sound starts and close
   after it ends); a second long, or as short as :data:`MIN_REST_SECONDS` where the silences are;
2. **the first second** with the head seen, where it is about as restful as the most restful
   second (the convention that takes start at rest holds);
3. **the most restful second** otherwise: the one whose mean pose is nearest the take's median
   pose (the pose a face keeps coming back to; a held expression is still, but not typical) plus
   how far its markers travel in half a second (:func:`window_costs`).

Each choice comes with the reason, said in the map report.
"""

from __future__ import annotations

import warnings

import numpy as np

from mapping.stabilise import Stabilised

#: Seconds of rest looked for.
REST_SECONDS = 1.0
#: The shortest silent rest window taken (seconds).
MIN_REST_SECONDS = 0.3
#: Sound below this share of the take's loudest is silence.
QUIET = 0.1
#: Seconds kept between a rest window and speech.
SPEECH_MARGIN = 0.15
#: A window's travel over this many seconds counts toward how unlike rest it is.
SPEED_SECONDS = 0.5
#: Seconds over which motion is measured (not frame to frame, where a marker's jitter dominates).
SPEED_LAG = 0.2
#: How far a window is from the typical pose: this percentile of its markers' distances from it (a
#: feature that moves shows, where a mean over every marker would dilute it).
AWAY_PERCENTILE = 90
#: The first second is rest where it is within this (mm) of the most restful window.
FIRST_TOLERANCE_MM = 2.0


def frame_speed(stable: Stabilised, lag: int = 1) -> np.ndarray:
    """Mean head-frame marker speed out of each frame, mm per frame, ``(F,)``: each marker's
    displacement over the next ``lag`` frames, over ``lag`` (a longer lag sees motion above
    jitter); ``inf`` where no marker is seen at both ends or the head is not posed (the last
    ``lag`` frames copy the one before them)."""
    local = stable.local
    lag = max(1, min(lag, len(local) - 1)) if len(local) > 1 else 1
    speed = np.linalg.norm(local[lag:] - local[:-lag], axis=2) / lag  # (F-lag, M)
    seen = np.isfinite(speed)
    count = seen.sum(axis=1)
    per_frame = np.where(count > 0, np.where(seen, speed, 0.0).sum(axis=1) / np.maximum(count, 1), np.inf)
    if len(per_frame):
        per_frame = np.concatenate([per_frame, np.repeat(per_frame[-1:], len(local) - len(per_frame))])
    else:
        per_frame = np.full(len(local), np.inf)
    return np.where(stable.ok, per_frame, np.inf)


def window_speeds(speed: np.ndarray, n: int) -> np.ndarray:
    """Mean of ``speed`` ``(F,)`` over each window of ``n`` frames starting at each frame,
    ``(F - n + 1,)``; ``inf`` for windows holding a frame of ``inf``."""
    finite = np.isfinite(speed)
    sums = np.convolve(np.where(finite, speed, 0.0), np.ones(n), mode="valid")
    bad = np.convolve((~finite).astype(float), np.ones(n), mode="valid") > 0
    return np.where(bad, np.inf, sums / n)


def stillest_window(stable: Stabilised, times: np.ndarray, seconds: float = REST_SECONDS) -> tuple[float, float]:
    """The ``seconds``-long window where the face moves least (mean head-frame marker speed)."""
    n = _frames(times, seconds)
    if len(times) <= n:
        return float(times[0]), float(times[-1])
    return _span(times, int(np.argmin(window_speeds(frame_speed(stable), n))), n)


def window_costs(stable: Stabilised, rate: float, n: int, speed: np.ndarray | None = None) -> np.ndarray:
    """How unlike rest each window of ``n`` frames is, ``(F - n + 1,)``, in mm: how far its mean
    pose is from the take's median pose (the :data:`AWAY_PERCENTILE` th percentile of its
    markers' distances; rest is the pose a face keeps coming back to) plus the distance its
    markers travel in :data:`SPEED_SECONDS` (rest is still); ``inf`` where a frame has no head
    pose, or a marker seen in most of the take is never seen."""
    speed = frame_speed(stable, round(SPEED_LAG * rate)) if speed is None else speed
    moving = window_speeds(speed, n) * rate * SPEED_SECONDS
    local = stable.local
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # markers never seen
        typical = np.nanmedian(local, axis=0)  # (M, 3)
    seen = np.isfinite(local)
    sums = np.concatenate([np.zeros((1, *local.shape[1:])), np.cumsum(np.where(seen, local, 0.0), axis=0)])
    counts = np.concatenate([np.zeros((1, *local.shape[1:])), np.cumsum(seen, axis=0)])
    with np.errstate(invalid="ignore", divide="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # windows where no marker is seen
        mean = (sums[n:] - sums[:-n]) / (counts[n:] - counts[:-n])  # (W, M, 3), NaN where never seen
        away = np.nanpercentile(np.linalg.norm(mean - typical, axis=2), AWAY_PERCENTILE, axis=1)
    # a window must see every marker the take mostly sees, or the rest lacks it
    required = seen.all(axis=2).mean(axis=0) >= 0.5  # (M,)
    blind = ((counts[n:] - counts[:-n]).min(axis=2)[:, required] == 0).any(axis=1)
    return np.where(np.isfinite(away) & ~blind, away + moving, np.inf)


def choose_rest(stable: Stabilised, times: np.ndarray, loudness: np.ndarray | None = None
                ) -> tuple[tuple[float, float], str]:
    """The rest window of a take that declares none (see the module docstring) and why.

    Parameters
    ----------
    stable : Stabilised
        The cleaned take in the head frame.
    times : ndarray, shape (F,)
    loudness : ndarray, shape (F,), optional
        The sound's level at each frame, 1 the loudest (NaN: not known).

    Returns
    -------
    ((start, end), reason)
        Seconds ``[start, end)`` and a phrase saying how they were found.
    """
    posed = np.flatnonzero(stable.ok)
    first_second = "first second with the head seen"
    if len(times) < 2 or not len(posed):
        start = float(times[posed[0]]) if len(posed) else float(times[0])
        return (start, start + REST_SECONDS), first_second
    rate = 1.0 / float(np.median(np.diff(times)))
    speed = frame_speed(stable, round(SPEED_LAG * rate))
    silent_note = ""
    if loudness is not None and np.isfinite(loudness).any():
        found = _silent_window(stable, speed, times, rate, loudness)
        if found is not None:
            return found
        silent_note = f"; no {MIN_REST_SECONDS:g} s of the sound is silent"
    n = min(_frames(times, REST_SECONDS), len(times))
    costs = window_costs(stable, rate, n, speed)
    usable = np.isfinite(costs)
    if not usable.any():
        start = float(times[posed[0]])
        return (start, start + REST_SECONDS), first_second + silent_note
    first, best = int(np.argmax(usable)), int(np.argmin(costs))
    if costs[first] <= costs[best] + FIRST_TOLERANCE_MM:
        return _span(times, first, n), f"{first_second}, as still and typical as any{silent_note}"
    return _span(times, best, n), (f"the stillest second nearest the take's typical pose; the first is "
                                   f"{costs[first] - costs[best]:.1f} mm less restful{silent_note}")


def _silent_window(stable: Stabilised, speed: np.ndarray, times: np.ndarray, rate: float, loudness: np.ndarray
                   ) -> tuple[tuple[float, float], str] | None:
    """The most restful window clear of speech, a second long or as long as the silences allow."""
    margin = max(1, int(round(SPEECH_MARGIN * rate)))
    loud = ~(loudness < QUIET)  # NaN counts as speech: not known to be silent
    near_speech = np.convolve(loud.astype(float), np.ones(2 * margin + 1), mode="same") > 0
    calm = np.where(near_speech, np.inf, speed)
    for seconds in (REST_SECONDS, 0.6, MIN_REST_SECONDS):
        n = _frames(times, seconds)
        if n > len(times):
            continue
        if not stable.local.shape[1]:  # no markers (a voice): the first window clear of speech
            clear = np.convolve(near_speech.astype(float), np.ones(n), mode="valid") == 0
            if clear.any():
                return _span(times, int(np.argmax(clear)), n), (
                    f"the first {n / rate:.2g} s where nobody speaks (sound under {QUIET:.0%} of its loudest, "
                    f"{SPEECH_MARGIN:g} s from speech)")
            continue
        costs = window_costs(stable, rate, n, calm)
        if np.isfinite(costs).any():
            best = int(np.argmin(costs))
            return _span(times, best, n), (f"the stillest {n / rate:.2g} s where nobody speaks (sound under "
                                           f"{QUIET:.0%} of its loudest, {SPEECH_MARGIN:g} s from speech)")
    return None


def _frames(times: np.ndarray, seconds: float) -> int:
    return max(1, int(round(seconds / float(np.median(np.diff(times)))))) if len(times) > 1 else 1


def _span(times: np.ndarray, start: int, n: int) -> tuple[float, float]:
    """Seconds ``[start, end)`` of ``n`` frames from frame ``start``."""
    step = float(np.median(np.diff(times)))
    return float(times[start]), float(times[start + n - 1] + step)
