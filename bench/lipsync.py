"""Lip sync from a voice (issue 40): how well the mouth shapes follow a talking face's lips.

For each GRID clip in ``../shared/realdata/video/grid`` (its name spells its six words: the
transcript for forced alignment), the mouth's opening from the shapes (:func:`capture.voice.openness`)
against the inner-lip gap the face tracker measures in the same clip: Pearson r, the best within
±120 ms of lag; median and worst over clips, from the phone loop (no words) and with the words
aligned. The plain peer in the same run: the sound's loudness envelope (RMS per 10 ms). Silence
is measured on each clip padded with a second of its own quietest sound either side: the share of
those frames whose opening is at most 0.1. Speed: seconds of sound per second of recognition on
one core, the model's loading included. Skipped (no figures) where the clips are absent.

Not yet measured: speech in other languages (espeak-ng is not installed by the Makefile yet)
and the live path (there is none yet).
"""

from __future__ import annotations

import time

import numpy as np

from bench.core import REALDATA, Figure

GRID = REALDATA / "video" / "grid"
#: GRID's grammar, letter by letter of a clip's name: command, colour, preposition, letter, digit, adverb.
_WORDS = ({"b": "bin", "l": "lay", "p": "place", "s": "set"},
          {"b": "blue", "g": "green", "r": "red", "w": "white"},
          {"a": "at", "b": "by", "i": "in", "w": "with"},
          None,  # the letter itself
          {"z": "zero", "1": "one", "2": "two", "3": "three", "4": "four", "5": "five", "6": "six", "7": "seven",
           "8": "eight", "9": "nine"},
          {"a": "again", "n": "now", "p": "please", "s": "soon"})
LAGS = np.arange(-12, 13) / 100.0


def transcript(name: str) -> str:
    """The words of the GRID clip called ``name`` (``bbaf2n``: "bin blue at f two now")."""
    return " ".join(name[k] if table is None else table[name[k]] for k, table in enumerate(_WORDS))


def run(quick: bool = False) -> list[Figure]:
    """Measure the figures on every GRID clip there is."""
    clips = sorted(GRID.glob("*.mpg"))
    if not clips:
        return []
    loop, aligned, loud, shut, speeds = [], [], [], [], []
    for clip in clips:
        scores, silent, speed = _clip(clip)
        loop.append(scores["loop"])
        aligned.append(scores["aligned"])
        loud.append(scores["loudness"])
        shut.append(silent)
        speeds.append(speed)
    detail = {"clips": [c.stem for c in clips], "loop": [round(r, 3) for r in loop],
              "aligned": [round(r, 3) for r in aligned], "loudness": [round(r, 3) for r in loud]}
    return [Figure("lipsync.r_median", float(np.median(loop)), "r", 0.7, True, detail),
            Figure("lipsync.r_worst", float(np.min(loop)), "r", 0.5, True, detail),
            Figure("lipsync.r_median_text", float(np.median(aligned)), "r", float(np.median(loop)), True, detail),
            Figure("lipsync.silence_shut_pct", float(np.mean(shut)), "%", 95.0, True, {"per_clip": shut}),
            Figure("lipsync.realtime_x", float(np.median(speeds)), "x", 20.0, True,
                   {"per_clip": [round(s, 1) for s in speeds]}),
            Figure("lipsync.loudness_r_median", float(np.median(loud)), "r", None, True, detail)]


def _clip(path) -> tuple[dict[str, float], float, float]:
    from capture.video_tracking import track_video
    from capture.voice import decode_voice, openness, recognise, shape_curves, shape_sequence, speaking

    sound = decode_voice(path)
    frames = len(sound) // 160
    take = track_video(path, "face")
    lips = take.positions[:, [take.labels.index("LIP_LOW_IN"), take.labels.index("LIP_UP_IN")], 1]
    gap = np.abs(lips[:, 0] - lips[:, 1])
    seen = np.isfinite(gap)
    start = time.perf_counter()
    speech = speaking(sound, frames)
    curves = {"loop": openness(shape_curves(shape_sequence(recognise(sound), frames, speech))),
              "aligned": openness(shape_curves(shape_sequence(recognise(sound, transcript(path.stem)), frames,
                                                              speech)))}
    speed = len(sound) / 16000 / ((time.perf_counter() - start) / 2)  # two recognitions in that time
    curves["loudness"] = np.sqrt(np.mean(sound[: frames * 160].reshape(frames, 160) ** 2, axis=1))
    times = np.arange(frames) / 100.0
    scores = {name: max(float(np.corrcoef(np.interp(take.times + lag, times, curve)[seen], gap[seen])[0, 1])
                        for lag in LAGS) for name, curve in curves.items()}
    return scores, _silence_shut(sound), speed


def _silence_shut(sound: np.ndarray) -> float:
    """The share (%) of a second of quiet either side of ``sound`` whose opening is at most 0.1."""
    from capture.voice import openness, recognise, shape_curves, shape_sequence, speaking

    quiet = sound[np.argsort(np.abs(sound))[: len(sound) // 4]]  # the clip's own quietest samples, as room tone
    pad = np.resize(quiet, 16000)
    padded = np.concatenate([pad, sound, pad]).astype(np.float32)
    frames = len(padded) // 160
    opening = openness(shape_curves(shape_sequence(recognise(padded), frames, speaking(padded, frames))))
    silent = np.r_[opening[:100], opening[-100:]]
    return float(100.0 * np.mean(silent <= 0.1))
