"""Learn the voice's mouth (:mod:`capture.voice_model`) from the talking-face clips.

``python -m bench.lipsync_train`` (``make lipsync-model``) rebuilds ``data/models/voice_mouth.json``
bit for bit from ``../shared/realdata/video`` and ``bench/talking``: the same clips, the same
seeded augmentation, the same choices, the same arithmetic.

1. Each clip's truth is the lip gap its face tracker measured (:mod:`bench.lipsync_data`). Its
   sound is heard as it is and in seven copies (seeded): 20 dB quieter, white noise at 30, 20
   and 10 dB below the speech, a room's reverberation, a telephone's band (300-3400 Hz) and a
   laptop microphone's (200 Hz-7 kHz with a little hiss). Every copy has the clip's truth. Each
   fit is made twice: the second time each clip's truth is shifted by the lag (within ±120 ms)
   at which the first fit's opening of that clip follows its lip gap best (:func:`lags`), so
   that a clip whose sound is late on its picture does not teach an early mouth.
2. The speakers of :data:`FINAL` (one of each corpus, the last of each in name order, set before
   any figure was seen) are put aside. On the others, each choice (:data:`CONTEXTS`, the frames
   read; :data:`ALPHAS`, the ridge's strength) is judged by leave-one-speaker-out: a model fitted
   without a speaker, scored on that speaker's clips as heard (the opening as the shipped code
   makes it: gated and blended; Pearson r against the lip gap, the best within ±120 ms).
3. The figures reported are nested: each training speaker scored by a model whose choice was made
   without it. Then the final speakers are scored once by a model fitted on all the others with
   the choice made on them.
4. The shipped weights are fitted on every speaker with that choice.

It does so twice: for the model of the spectrum alone (``voice_mouth.json``, any language) and
for the model of the spectrum and the phones of the words an English recogniser hears in the
clip (``voice_mouth_words.json``, :mod:`capture.voice_words`), whose choices also include how
strongly the phones count (:data:`PHONE_SCALES`). The words are heard once, in the clip as it
is, and given to each of its copies (a recogniser's mistakes in noise are not learned from).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.lipsync_data import Clip, clips, corpus, load_clip

#: Frames (10 ms) around a frame whose spectra its opening reads: at most 50 ms ahead (what a
#: live voice waits for), up to 300 ms back.
CONTEXTS: tuple[tuple[int, ...], ...] = ((0,), tuple(range(-12, 6, 3)), tuple(range(-20, 6, 4)),
                                         tuple(range(-30, 6, 6)))
#: The ridge's strength, per frame and feature.
ALPHAS = (0.03, 0.1, 0.3, 1.0, 3.0, 10.0)
#: Speakers kept for the last check: the last clip of each corpus in name order.
FINAL = ("lbax4n", "retalking-5", "vox-796100172")
#: How strongly the phones count against the spectrum in the words model: their presence (0..1)
#: times this before the ridge, whose one strength then shrinks them less.
PHONE_SCALES = (3.0, 10.0, 30.0)
#: Both models read the spectra's magnitudes too (:attr:`capture.voice_model.MouthModel.magnitude`).
MAGNITUDE = True
#: The augmentation's seed.
SEED = 61
LAGS = np.arange(-12, 13)
MODELS = Path(__file__).resolve().parents[1] / "data" / "models"
#: Each model's weights file: the spectrum alone, and the spectrum with the words' phones.
WEIGHTS = {"sound": MODELS / "voice_mouth.json", "words": MODELS / "voice_mouth_words.json"}
#: A choice of the frames read, the ridge's strength and the phones' scale (0: no phones).
Choice = tuple[tuple[int, ...], float, float]


def copies(sound: np.ndarray, rng: np.random.Generator) -> list[np.ndarray]:
    """``sound`` (16 kHz) as heard and in the seven copies of the module docstring."""
    from scipy.signal import butter, fftconvolve, sosfilt

    sound = sound.astype(np.float64)
    speech = float(np.sqrt(np.mean(sound ** 2))) or 1e-4

    def noisy(x: np.ndarray, snr: float) -> np.ndarray:
        return x + rng.normal(0.0, speech * 10 ** (-snr / 20), len(x))

    t = np.arange(int(0.4 * 16000)) / 16000
    room = rng.normal(0.0, 1.0, len(t)) * np.exp(-6.9 * t / 0.4)  # a 0.4 s reverberation time
    room[0] = 8.0  # the direct sound
    reverberant = fftconvolve(sound, room / np.abs(room).sum() * 4)[:len(sound)]
    phone = sosfilt(butter(4, (300, 3400), "bandpass", fs=16000, output="sos"), sound)
    laptop = noisy(sosfilt(butter(2, (200, 7000), "bandpass", fs=16000, output="sos"), sound), 35.0)
    return [sound, 0.1 * sound, noisy(sound, 30.0), noisy(sound, 20.0), noisy(sound, 10.0), reverberant, phone,
            laptop]


@dataclass
class Prepared:
    """A clip's training rows per context (and phones' scale): sums that add across clips (for
    ridge by folds), and its sound as heard, for scoring."""

    clip: Clip
    units: np.ndarray  # (frames, 3 + MEL_BANDS) the sound as heard (capture.voice_sound.sound_units)
    # n, sum x, sum xx^T, then sum y (len(LAGS),) and sum xy (len(LAGS), D) with the truth shifted by each lag
    sums: dict[tuple[tuple[int, ...], float], tuple[np.ndarray, ...]]
    presence: np.ndarray | None = None  # (frames, len(WORDS_READ)) what the words model reads of the words heard in it
    phones: list | None = None  # the phones of the words heard in it (capture.voice.Phone), for the words model


def rows(units: np.ndarray, presence: np.ndarray | None, context: tuple[int, ...], scale: float) -> np.ndarray:
    """A clip's feature rows: its spectra in ``context`` and their magnitudes
    (:func:`capture.voice_model.spectra_read`), then (``scale`` > 0) what the words model reads of
    its words (:func:`capture.voice_words.words_read`) times ``scale``."""
    from capture.voice_model import spectra_read

    x = spectra_read(units[:, 3:], context, MAGNITUDE)
    if not scale:
        return x
    assert presence is not None, "a words model's rows need the phones heard"
    return np.concatenate([x, scale * presence], axis=1)


def prepare(clip: Clip, rng: np.random.Generator, words: bool = False) -> Prepared:
    """Every copy of ``clip``'s sound as features in each of :data:`CONTEXTS` (and, with
    ``words``, each of :data:`PHONE_SCALES` with the words heard in it), with its target."""
    from capture.voice import recognise_words, speaking
    from capture.voice_sound import sound_units
    from capture.voice_words import words_read

    target = clip.target()
    targets = np.stack([shifted(target, int(lag)) for lag in LAGS], axis=1)  # (frames, len(LAGS))
    phones = recognise_words(clip.sound) if words else None
    heard_phones = words_read(phones, clip.frames, speaking(clip.sound, clip.frames)) if phones is not None else None
    keys = [(context, scale) for context in CONTEXTS for scale in ((0.0, *PHONE_SCALES) if words else (0.0,))]
    sums: dict[tuple[tuple[int, ...], float], tuple[np.ndarray, ...]] = {}
    heard = None
    for k, sound in enumerate(copies(clip.sound, rng)):
        units = sound_units(sound, clip.frames)
        if k == 0:
            heard = units
        for key in keys:
            x = rows(units, heard_phones, *key)
            part = (np.array(float(len(x))), x.sum(axis=0), x.T @ x, targets.sum(axis=0), (x.T @ targets).T)
            sums[key] = part if key not in sums else tuple(a + b for a, b in zip(sums[key], part, strict=True))
    assert heard is not None
    return Prepared(clip, heard, sums, heard_phones, phones)


def shifted(target: np.ndarray, lag: int) -> np.ndarray:
    """``target`` ``(frames,)`` ``lag`` frames later (its value at frame ``i - lag`` at ``i``, the
    ends held, as :func:`capture.voice_model.in_context` reads a frame's neighbours): the truth of a
    clip whose sound comes ``lag`` frames after its mouth, put in step."""
    from capture.voice_model import in_context

    return in_context(target[:, None], (-lag,))[:, 0]


def fit(prepared: Sequence[Prepared], context: tuple[int, ...], alpha: float, scale: float = 0.0
        ) -> tuple[np.ndarray, np.ndarray, float]:
    """Ridge regression on ``prepared``'s rows, each clip's truth put in step with its sound
    (:func:`lags`), rescaled so that its openings over those clips as heard span 0 to 1 between
    their 5th and 95th percentiles (a ridge's predictions shrink towards their mean; the mouth
    should still shut and open wide): ``(mean, weights, bias)`` of features whose columns of the
    words (``scale`` > 0: :data:`capture.voice_words.WORDS_READ`) are unscaled."""
    first = _fit(prepared, context, alpha, scale, {})
    return _fit(prepared, context, alpha, scale, lags(prepared, model_of(first, context, words=scale > 0)))


def lags(prepared: Sequence[Prepared], model) -> dict[str, int]:
    """Each clip's lag (frames, :data:`LAGS`) at which ``model``'s opening of its sound as heard
    follows its lip gap best: how far its sound comes after its mouth (a clip's own sync, and how
    far a mouth moves before the sound it makes). A clip's truth is shifted by it before the
    model is fitted again (:func:`fit`): fitted at a lag of 0 for every clip, a wild clip whose
    sound is 0.2 s late taught the model a mouth 0.2 s early. Chosen on the 16 training speakers'
    17 clips, each as heard (not its copies), each speaker held out, the words model's choices of
    then: mean r 0.508 -> 0.534, ``bbaf2n`` 0.493 -> 0.541; the lags the other way round 0.445,
    one lag for every clip (their median) 0.519; a second pass drifts past the window's ends."""
    return {p.clip.name: int(LAGS[int(np.argmax(lag_rs(opening_of(p, model), p.clip)))]) for p in prepared}


def _fit(prepared: Sequence[Prepared], context: tuple[int, ...], alpha: float, scale: float, by_clip: dict[str, int]
         ) -> tuple[np.ndarray, np.ndarray, float]:
    """:func:`fit`'s ridge with each clip's truth shifted by its lag in ``by_clip`` (0 where absent)."""
    from capture.voice_words import WORDS_READ

    key = (context, scale)
    at = {p.clip.name: int(np.flatnonzero(LAGS == by_clip.get(p.clip.name, 0))[0]) for p in prepared}
    n, sx, sxx = (sum(p.sums[key][k] for p in prepared) for k in range(3))
    sy = sum(p.sums[key][3][at[p.clip.name]] for p in prepared)
    sxy = sum(p.sums[key][4][at[p.clip.name]] for p in prepared)
    mean, y_mean = sx / n, float(sy / n)
    gram = sxx - n * np.outer(mean, mean)
    cross = sxy - n * mean * y_mean
    weights = np.linalg.solve(gram + alpha * n * np.eye(len(gram)), cross)
    heard = np.concatenate([(rows(p.units, p.presence, context, scale) - mean) @ weights for p in prepared]) + y_mean
    low, high = np.percentile(heard, [5.0, 95.0])
    span = max(float(high - low), 1e-9)
    mean = np.asarray(mean, float)
    unscale = np.ones(len(mean))
    if scale:
        unscale[len(mean) - len(WORDS_READ):] = scale
    return mean / unscale, weights * unscale / span, (y_mean - float(low)) / span


def model_of(parts: tuple[np.ndarray, np.ndarray, float], context: tuple[int, ...], notes: dict | None = None,
             words: bool = False):
    from capture.voice_model import MouthModel
    from capture.voice_words import WORDS_READ

    mean, weights, bias = parts
    return MouthModel(tuple(context), mean, weights, bias, notes or {}, WORDS_READ if words else (), MAGNITUDE)


def opening_of(prepared: Prepared, model) -> np.ndarray:
    """The clip's opening by ``model`` from its sound as heard, gated as silence is and blended as
    shapes are, ``(frames,)``."""
    from capture.voice import blend
    from capture.voice_sound import learned_opening
    from capture.voice_words import words_opening

    if model.phones:
        assert prepared.presence is not None, "a words model is scored on the phones heard"
        return blend(words_opening(prepared.units, prepared.presence, model))
    return blend(learned_opening(prepared.units, model))


def score(prepared: Prepared, model) -> float:
    """Pearson r of the clip's :func:`opening_of` against its lip gap, the best within ±120 ms."""
    return best_r(opening_of(prepared, model), prepared.clip)


def lag_rs(curve: np.ndarray, clip: Clip) -> np.ndarray:
    """Pearson r of a 100 Hz ``curve`` against the clip's lip gap at its video frames with the
    curve read each of :data:`LAGS` frames later, ``(len(LAGS),)`` (a constant curve scores 0)."""
    seen = np.isfinite(clip.gap)
    at = clip.video_times[seen][None, :] + LAGS[:, None] / 100.0  # (len(LAGS), seen frames), all at once
    moved = np.interp(at.ravel(), np.arange(len(curve)) / 100.0, curve).reshape(at.shape)
    flat = np.ptp(moved, axis=1) == 0  # a constant curve scores 0
    moved = moved - moved.mean(axis=1, keepdims=True)
    gap = clip.gap[seen] - clip.gap[seen].mean()
    spread = np.sqrt((moved * moved).sum(axis=1) * float(gap @ gap))
    return np.where(flat, 0.0, (moved @ gap) / np.where(flat, 1.0, spread))


def best_r(curve: np.ndarray, clip: Clip) -> float:
    """Pearson r of a 100 Hz ``curve`` against the clip's lip gap, the best within ±120 ms of lag
    (:func:`lag_rs`)."""
    return float(lag_rs(curve, clip).max())


def by_speaker(prepared: Sequence[Prepared]) -> dict[str, list[Prepared]]:
    out: dict[str, list[Prepared]] = {}
    for p in prepared:
        out.setdefault(p.clip.speaker, []).append(p)
    return out


def choose(prepared: Sequence[Prepared], words: bool = False) -> tuple[Choice, float]:
    """The context, alpha and phones' scale (with ``words``; else 0) whose leave-one-speaker-out
    mean r over ``prepared``'s speakers is highest (the first of equals, in :data:`CONTEXTS`,
    :data:`PHONE_SCALES` and :data:`ALPHAS` order), and that r."""
    speakers = by_speaker(prepared)
    best: tuple[Choice, float] | None = None
    for context in CONTEXTS:
        for scale in PHONE_SCALES if words else (0.0,):
            for alpha in ALPHAS:
                rs = []
                for name, own in speakers.items():
                    parts = fit([p for p in prepared if p.clip.speaker != name], context, alpha, scale)
                    model = model_of(parts, context, words=words)
                    rs.append(float(np.mean([score(p, model) for p in own])))
                mean = float(np.mean(rs))
                if best is None or mean > best[1]:
                    best = ((context, alpha, scale), mean)
    assert best is not None
    return best


def held_out(prepared: Sequence[Prepared], nested: bool, choice: Choice = ((0,), 1.0, 0.0), words: bool = False
             ) -> dict[str, float]:
    """Each clip's r from a model fitted without its speaker: with the choice made without it too
    (``nested``), or with ``choice`` given."""
    out = {}
    for name, own in by_speaker(prepared).items():
        others = [p for p in prepared if p.clip.speaker != name]
        chosen = choose(others, words)[0] if nested else choice
        model = model_of(fit(others, *chosen), chosen[0], words=words)
        out.update({p.clip.name: round(score(p, model), 4) for p in own})
    return out


def train(prepared: Sequence[Prepared], final: Sequence[str] = FINAL, say=print, words: bool = False) -> dict:
    """The whole procedure of the module docstring on ``prepared`` clips (prepared with
    ``words`` for the words model); the weights file's document."""
    training = [p for p in prepared if p.clip.speaker not in final]
    kept = [p for p in prepared if p.clip.speaker in final]
    what = "the spectrum and the words' phones" if words else "the spectrum"
    say(f"{what}: choosing by leave-one-speaker-out over {len(by_speaker(training))} speakers")
    choice, inner = choose(training, words)
    context, alpha, scale = choice
    say(f"chose {len(context)} frames {min(context) * 10} to {max(context) * 10} ms, alpha {alpha:g}"
        + (f", phones x{scale:g}" if words else "") + f": r {inner:.3f}")
    nested = held_out(training, nested=True, words=words) if len(by_speaker(training)) > 2 else {}
    model = model_of(fit(training, *choice), context, words=words)
    check = {p.clip.name: round(score(p, model), 4) for p in kept}
    corpora = {p.clip.name: p.clip.corpus for p in prepared}
    notes = {"trained_on": sorted(p.clip.name for p in prepared), "alpha": alpha, "seed": SEED,
             **({"phone_scale": scale} if words else {}), "command": "python -m bench.lipsync_train",
             "chosen_by": f"leave-one-speaker-out mean r {inner:.4f} over {len(by_speaker(training))} speakers",
             "held_out_nested": nested, "final_check": check, "final_speakers": list(final),
             "corpus": corpora}
    shipped = model_of(fit(prepared, *choice), context, notes, words)
    return shipped.to_dict()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.lipsync_train", description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", choices=("sound", "words", "both"), default="both",
                        help="which model to rebuild [both]")
    parser.add_argument("--out", type=Path, default=MODELS,
                        help=f"the folder the weights go to, as {WEIGHTS['sound'].name} and {WEIGHTS['words'].name} "
                             f"[{MODELS}]")
    parser.add_argument("--clips", type=int, default=None, help="only the first N clips (a quick check)")
    parser.add_argument("--corpus", choices=("grid", "studio", "wild"), default=None,
                        help="only this corpus's clips (a quick check)")
    args = parser.parse_args(argv)
    paths = [p for p in clips(ours=True) if args.corpus is None or corpus(p) == args.corpus][:args.clips]
    if not paths:
        print("no shared talking-face clips found (../shared/realdata/video)", file=sys.stderr)
        return 2
    final = FINAL if args.clips is None and args.corpus is None else ()
    kinds = ("sound", "words") if args.model == "both" else (args.model,)
    rng = np.random.default_rng(SEED)
    prepared = []
    for path in paths:
        print(f"tracking and hearing {path.name}", file=sys.stderr)
        prepared.append(prepare(load_clip(path), rng, words="words" in kinds))
    args.out.mkdir(parents=True, exist_ok=True)
    for kind in kinds:
        doc = train(prepared, final, say=lambda line: print(line, file=sys.stderr), words=kind == "words")
        out = args.out / WEIGHTS[kind].name
        partial = out.with_name(out.name + ".partial")  # an interrupted run leaves the old weights whole
        partial.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
        partial.replace(out)
        print(json.dumps({"model": kind, **{k: doc[k] for k in ("alpha", "held_out_nested", "final_check",
                                                                  "chosen_by")}}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
