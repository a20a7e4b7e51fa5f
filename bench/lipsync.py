"""Lip sync from a voice (issue 40): how well the mouth shapes follow a talking face's lips.

For each GRID clip in ``../shared/realdata/video/grid`` (its name spells its six words: the
transcript for forced alignment), the mouth's opening from the shapes (:func:`capture.voice.openness`)
against the inner-lip gap the face tracker measures in the same clip: Pearson r, the best within
±120 ms of lag; median and worst over clips, from the sound alone (the default), from the phone
loop, and with the words aligned. The plain peer in the same run: the sound's loudness envelope
(RMS per 10 ms). Silence is measured on each clip padded with a second of its own quietest sound
either side: the share of those frames whose opening is at most 0.1.

Other languages: espeak-ng says three sentences each in English, German, Spanish and French
(looked at while the features were chosen) and in Italian, Portuguese, Dutch and Polish (not:
the check); the truth is its own phoneme timings (:mod:`bench.espeak`, openness by vowel height). Speed: seconds
of sound per second of work on one core, decoding included. Live: a clip played in real time as a
microphone gives it, through the voice mapping; ms from a frame's sound to its motors.

The sound's features were chosen looking at the GRID clips and the first of these sentences:
treat those figures as fitted; the languages' other sentences and any new clip are the check.
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
    """Measure the figures on every GRID clip there is and on espeak-ng's sentences."""
    clips = sorted(GRID.glob("*.mpg"))
    figures: list[Figure] = []
    if clips:
        rows = [_clip(clip) for clip in clips]
        scores = {name: [row[0][name] for row in rows] for name in rows[0][0]}
        detail = {"clips": [c.stem for c in clips], **{k: [round(r, 3) for r in v] for k, v in scores.items()}}
        shut = [row[1] for row in rows]
        noisy = {key: [round(row[2][key], 3) for row in rows] for key in rows[0][2]}
        figures += [Figure("lipsync.r_median", float(np.median(scores["sound"])), "r", 0.7, True, detail),
                    Figure("lipsync.r_worst", float(np.min(scores["sound"])), "r", 0.5, True, detail),
                    Figure("lipsync.r_median_text", float(np.median(scores["words"])), "r",
                           float(np.median(scores["sound"])), True, detail),
                    Figure("lipsync.r_median_phones", float(np.median(scores["phones"])), "r", None, True, detail),
                    Figure("lipsync.silence_shut_pct", float(np.mean(shut)), "%", 95.0, True, {"per_clip": shut}),
                    Figure("lipsync.noisy_silence_shut_pct", float(min(np.mean(noisy[f"shut_{snr:g}dB"])
                                                                        for snr in SNRS)), "%", 95.0, True, noisy),
                    Figure("lipsync.noisy_r_median_20dB", float(np.median(noisy["r_20dB"])), "r", None, True, noisy),
                    Figure("lipsync.loudness_r_median", float(np.median(scores["loudness"])), "r", None, True,
                           detail)]
    figures += _languages()
    figures += _text_aligned()
    if clips:
        figures.append(_fill(clips))
    figures += [_speed(clips), _live()]
    from bench import lipsync_heldout

    return figures + lipsync_heldout.run(quick)


def _best_r(curve: np.ndarray, truth: np.ndarray) -> float:
    """Pearson r of ``curve`` against ``truth`` (both 100 Hz), the best within ±120 ms of lag."""
    n = min(len(curve), len(truth))
    return max(float(np.corrcoef(np.roll(curve[:n], -int(round(lag * 100))), truth[:n])[0, 1]) for lag in LAGS)


def _curves(sound: np.ndarray, text: str | None) -> dict[str, np.ndarray]:
    """The mouth's opening (100 Hz) from the sound, the phones, the words where given, and the loudness peer."""
    from capture.voice import openness, recognise, recognise_words, shape_curves, shape_sequence, speaking
    from capture.voice_sound import sound_mouth
    from capture.voice_text import align_text
    from capture.voice_words import words_mouth

    frames = len(sound) // 160
    speech = speaking(sound, frames)
    weights, _ = sound_mouth(sound, frames)
    curves = {"sound": openness(weights),
              "phones": openness(shape_curves(shape_sequence(recognise(sound), frames, speech))),
              "loudness": np.sqrt(np.mean(sound[: frames * 160].reshape(frames, 160) ** 2, axis=1))}
    curves["heard_words"] = openness(words_mouth(sound, frames, recognise_words(sound))[0])
    if text is not None:
        curves["words"] = openness(words_mouth(sound, frames, align_text(sound, text).phones)[0])
    return curves


#: Signal-to-noise ratios (dB, against the clip's speech) of the noisy copies of each clip.
SNRS = (30.0, 20.0, 10.0)


def _clip(path) -> tuple[dict[str, float], float, dict[str, float]]:
    from capture.video_tracking import track_video
    from capture.voice import decode_voice

    sound = decode_voice(path)
    frames = len(sound) // 160
    take = track_video(path, "face")
    lips = take.positions[:, [take.labels.index("LIP_LOW_IN"), take.labels.index("LIP_UP_IN")], 1]
    gap = np.abs(lips[:, 0] - lips[:, 1])
    seen = np.isfinite(gap)
    times = np.arange(frames) / 100.0
    scores = {name: max(float(np.corrcoef(np.interp(take.times + lag, times, curve)[seen], gap[seen])[0, 1])
                        for lag in LAGS) for name, curve in _curves(sound, transcript(path.stem)).items()}
    return scores, _silence_shut(sound), _noisy(sound, take.times[seen], gap[seen])


def _noisy(sound: np.ndarray, times: np.ndarray, gap: np.ndarray) -> dict[str, float]:
    """Silence and speech known by construction: the clip between two seconds of digital
    silence, white noise added throughout at each of :data:`SNRS`; per ratio, the share (%) of
    the added seconds' frames shut (opening at most 0.1, the 0.25 s next to the clip left out)
    and r against the lips."""
    from capture.voice import openness
    from capture.voice_sound import sound_mouth

    rng = np.random.default_rng(0)
    padded = np.concatenate([np.zeros(32000), sound, np.zeros(32000)])
    speech_rms = float(np.sqrt(np.mean(sound.astype(np.float64) ** 2)))
    out = {}
    for snr in SNRS:
        noisy = (padded + rng.normal(0.0, speech_rms * 10 ** (-snr / 20), len(padded))).astype(np.float32)
        frames = len(noisy) // 160
        opening = openness(sound_mouth(noisy, frames)[0])
        out[f"shut_{snr:g}dB"] = float(100.0 * np.mean(np.r_[opening[:175], opening[-175:]] <= 0.1))
        at = np.arange(frames) / 100.0 - 2.0
        out[f"r_{snr:g}dB"] = max(float(np.corrcoef(np.interp(times + lag, at, opening), gap)[0, 1]) for lag in LAGS)
    return out


def _languages() -> list[Figure]:
    """Median r of the opening against espeak-ng's phoneme timings, per language: the worst of
    the languages other than English looked at while the features were chosen (de es fr), and
    the worst of four nobody looked at (it pt nl pl), the check."""
    from bench import espeak

    if not espeak.available():
        return []
    from scipy.signal import resample_poly

    from capture.voice_sound import sound_shapes

    per: dict[str, dict[str, list[float]]] = {}
    held: list[tuple[int, int]] = []  # per sentence: its shortest cue outside closures, its one-frame switches
    for voice, sentences in {**espeak.SENTENCES, **espeak.HELD_OUT}.items():
        for sentence in sentences:
            spoken = espeak.say(sentence, voice)
            sound = resample_poly(spoken.samples, 320, 441).astype(np.float32)  # 22050 Hz to 16 kHz
            truth = spoken.openness()
            for name, curve in _curves(sound, None).items():
                per.setdefault(name, {}).setdefault(voice, []).append(round(_best_r(curve, truth), 3))
            held.append(_holds(sound_shapes(sound, len(sound) // 160)))
    seen = [v for v in espeak.SENTENCES if not v.startswith("en")]
    medians = {name: {v: float(np.median(r)) for v, r in by.items()} for name, by in per.items()}
    detail = {"per_sentence": per, "medians": medians}
    return [Figure("lipsync.r_other_languages_worst", min(medians["sound"][v] for v in seen), "r", 0.6, True, detail),
            Figure("lipsync.r_held_out_languages_worst", min(medians["sound"][v] for v in espeak.HELD_OUT), "r", 0.6,
                   True, detail),
            Figure("lipsync.r_english_espeak", medians["sound"].get("en-us", float("nan")), "r", None, True, detail),
            Figure("lipsync.phones_r_other_languages_worst",
                   min(medians["phones"][v] for v in (*seen, *espeak.HELD_OUT)), "r", None, True, detail),
            Figure("lipsync.cue_min_frames", float(min(shortest for shortest, _ in held)), "frames", 1.0, True,
                   {"fps": 24, "sentences": len(held), "one_frame_switches_outside_closures":
                    sum(flicker for _, flicker in held), "what": "lipsync's cues from the sound, held for 24 fps "
                    "(capture.cues.held_cues): the shortest outside closures, and switches a frame apart"})]


#: Lines of dialogue as written, punctuation and all (issue 69: "sunday," was refused, and "baked
#: apple" and two of espeak-ng's sentences failed to align).
PUNCTUATED = ("She baked apple pies on Sunday, then sliced them.", "Bob, put the map back by the pump!",
              "Baked apple?", "Well... maybe; Pam's brother Bert bought 3 big mops.",
              "\u201cPlease,\u201d said Mabel \u2014 \u201cbe polite!\u201d")


def _text_aligned() -> list[Figure]:
    """``--text`` on espeak-ng's English sentences and :data:`PUNCTUATED`: the share whose words
    all align (:func:`capture.voice_text.align_text`, no phrase left to the sound), and the share
    of their B, P and M phones during which the mouth is shut (shape A)."""
    from bench import espeak

    if not espeak.available():
        return []
    from scipy.signal import resample_poly

    from capture.voice import VISEMES
    from capture.voice_take import mouth_of
    from capture.voice_text import align_text

    aligned, closures, notes = [], [], {}
    for sentence in (*espeak.SENTENCES["en-us"], *PUNCTUATED):
        sound = resample_poly(espeak.say(sentence).samples, 320, 441).astype(np.float32)
        found = align_text(sound, sentence)
        notes[sentence] = found.notes
        aligned.append(bool(found.phones) and not any("could not" in n or "left out" in n for n in found.notes))
        shapes = mouth_of(sound, sentence)[1]
        closures += [VISEMES.index("A") in shapes[int(p.start * 100):max(int(p.end * 100), int(p.start * 100) + 1)]
                     for p in found.phones if p.name in ("B", "P", "M")]
    detail = {"sentences": len(aligned), "closures": len(closures), "notes": notes}
    return [Figure("lipsync.text_aligned_pct", 100.0 * float(np.mean(aligned)), "%", 100.0, True, detail),
            Figure("lipsync.text_closures_shut_pct", 100.0 * float(np.mean(closures)), "%", 100.0, True, detail)]


def _holds(shapes: np.ndarray) -> tuple[int, int]:
    """The shortest of ``lipsync``'s held cues at 24 fps outside closures (frames) and how many of
    its switches come a frame after the last outside closures."""
    from capture.cues import CLOSURES, held_cues
    from capture.voice import mouth_cues

    cues = held_cues(mouth_cues(shapes), 24.0)
    frames = [(round(b * 24) - round(a * 24), s) for a, b, s in cues[:-1]]
    lengths = [f for f, s in frames if s not in CLOSURES]
    return min(lengths, default=99), sum(1 for f, s in frames if f < 2 and s not in CLOSURES)


def _speed(clips: list) -> Figure:
    """Seconds of sound per second of work on one core, decoding and the model included, from
    the sound (the default); the phone loop's, the words heard's (``--listen words``) and the words
    given's (``--text``) in the detail."""
    from capture.voice_take import hear_voice

    sources = clips or []
    speeds: dict[str, list[float]] = {"sound": [], "phones": [], "heard_words": [], "words": []}
    for clip in sources:
        for name in speeds:
            start = time.perf_counter()
            heard = hear_voice(clip, transcript(clip.stem) if name == "words" else None,
                               {"phones": "phones", "heard_words": "words"}.get(name, "sound"))
            speeds[name].append(len(heard.samples) / 16000 / (time.perf_counter() - start))
    medians = {k: round(float(np.median(v)), 1) if v else None for k, v in speeds.items()}
    return Figure("lipsync.realtime_x", float(medians["sound"] or 0.0), "x", 20.0, True, medians)


def _live() -> Figure:
    """Sound to motors in real time: a GRID clip (or an espeak-ng sentence) played as a microphone
    would give it, each frame mapped by the voice mapping; ms from a frame's sound to its motors."""
    import tempfile
    from pathlib import Path

    from capture.sources import open_source
    from toonface.send import build_mapper

    clips = sorted(GRID.glob("*.mpg"))
    with tempfile.TemporaryDirectory() as folder:
        if clips:
            target = clips[0]
        else:
            from bench import espeak

            spoken = espeak.say(espeak.SENTENCES["de"][0], "de")
            target = Path(folder) / "said.wav"
            _write_wav(target, spoken.samples, spoken.rate)
        source = open_source(f"voice:{target}")
        mapper = build_mapper(source)
        delays, start = [], time.perf_counter()
        for frame in source.frames:
            mapper.step_frame(frame)
            delays.append(1000 * (time.perf_counter() - start - frame.t))
    return Figure("lipsync.live_p95_ms", float(np.percentile(delays, 95)), "ms", 150.0, False,
                  {"median_ms": round(float(np.median(delays)), 1), "frames": len(delays),
                   "lookahead_ms": source.meta["lookahead_ms"], "file": target.name})


def _write_wav(path, samples: np.ndarray, rate: int) -> None:
    import av

    with av.open(str(path), "w") as out:
        stream = out.add_stream("pcm_s16le", rate=rate, layout="mono")
        frame = av.AudioFrame.from_ndarray((np.clip(samples, -1, 1) * 32767).astype(np.int16)[None], format="s16",
                                           layout="mono")
        frame.sample_rate = rate
        for packet in (*stream.encode(frame), *stream.encode(None)):
            out.mux(packet)


def covered(clip, path, first: int, last: int) -> None:
    """``clip`` (a video) written to ``path`` (.mkv) with its picture dark from frame ``first``
    to ``last``, its sound kept as PCM (no codec delay): a face lost while its voice goes on."""
    import av

    with av.open(str(clip)) as source, av.open(str(path), "w") as target:
        video = target.add_stream("mpeg4", rate=25)
        video.width, video.height, video.pix_fmt = 360, 288, "yuv420p"
        audio = target.add_stream("pcm_s16le", rate=16000, layout="mono")
        resampler = av.AudioResampler(format="s16", layout="mono", rate=16000)
        index = 0
        for packet in source.demux():
            for frame in packet.decode():
                if isinstance(frame, av.VideoFrame):
                    image = frame.to_ndarray(format="rgb24")
                    if first <= index < last:
                        image = np.full_like(image, 40)
                    index += 1
                    target.mux(video.encode(av.VideoFrame.from_ndarray(image, format="rgb24")))
                elif isinstance(frame, av.AudioFrame):
                    for piece in resampler.resample(frame):
                        piece.pts = None
                        target.mux(audio.encode(piece))
        target.mux(video.encode(None))
        target.mux(audio.encode(None))


def _fill(clips: list) -> Figure:
    """The voice filling a lost face: each GRID clip with 0.8 s of its picture dark (four places),
    the mouth's MB against the same clip's MB with the face seen; mean absolute error with the
    voice filling the dark frames over that without (the face's own hold): below 1 is better."""
    import tempfile
    from pathlib import Path

    from capture.video_tracking import track_video
    from capture.voice_take import read_voice
    from mapping.voicefill import fill_from_voice, lost_mouth
    from mapping.workflow import choose_mapping
    from toon import MOTOR_CODES
    from toonface.pipeline import map_onto_face

    mb = MOTOR_CODES.index("MB")
    held_err, filled_err, detail = [], [], []
    with tempfile.TemporaryDirectory() as folder:
        for clip in clips:
            seen = map_onto_face(track_video(clip, "face")).values[:, mb]
            for first in (5, 20, 35, 50):
                last, path = first + 20, Path(folder) / f"{clip.stem}-{first}.mkv"
                covered(clip, path, first, last)
                take = track_video(path, "face")
                chosen, markerset = choose_mapping(take)
                held = map_onto_face(take)
                voice = read_voice(path)
                filled, _ = fill_from_voice(held, lost_mouth(take, chosen, markerset),
                                            map_onto_face(voice, "first", life=False), voice.times)
                held_err.append(float(np.abs(held.values[first:last, mb] - seen[first:last]).mean()))
                filled_err.append(float(np.abs(filled.values[first:last, mb] - seen[first:last]).mean()))
                detail.append(f"{clip.stem}@{first}: {held_err[-1]:.3f} -> {filled_err[-1]:.3f}")
    return Figure("lipsync.fill_mae_ratio", float(np.mean(filled_err) / np.mean(held_err)), "x", 1.0, False,
                  {"held_mae": round(float(np.mean(held_err)), 3), "filled_mae": round(float(np.mean(filled_err)), 3),
                   "windows": detail})


def _silence_shut(sound: np.ndarray) -> float:
    """The share (%) of a second of quiet either side of ``sound`` whose opening is at most 0.1."""
    from capture.voice import openness
    from capture.voice_sound import sound_mouth

    quiet = sound[np.argsort(np.abs(sound))[: len(sound) // 4]]  # the clip's own quietest samples, as room tone
    pad = np.resize(quiet, 16000)
    padded = np.concatenate([pad, sound, pad]).astype(np.float32)
    frames = len(padded) // 160
    opening = openness(sound_mouth(padded, frames)[0])
    silent = np.r_[opening[:100], opening[-100:]]
    return float(100.0 * np.mean(silent <= 0.1))
