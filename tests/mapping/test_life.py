"""The life layer (issue 64): a voice's pitch found as it is (YIN, against tones of known pitch),
its cues where they were put, blinks at the rates and places asked, brows that rise on pitch
accents, the same every run with one seed, and never a motor the source drives."""

from __future__ import annotations

import numpy as np
import pytest

from capture.voice_pitch import pitch_hz, semitones
from mapping.life import LIDS, LifeSettings, LiveLife, add_life, life_offsets, voice_cues
from toon import MOTOR_CODES, MotorTrack, standard_neutral

RATE = 100.0
MOUTH = ("MB", "MLH", "MRH", "MLV", "MRV")


def _voice(seconds: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray, list[int], list[int]]:
    """A voice's level and pitch (semitones) at 100 Hz: phrases of 1.5-3 s between pauses of
    0.4-1 s, its pitch at 12 semitones (110 Hz) with an accent of +5 semitones in each phrase;
    with the frames where its pauses and accents were put."""
    rng = np.random.default_rng(seed)
    n = int(seconds * RATE)
    level, pitch = np.zeros(n), np.zeros(n)
    pauses, accents = [], []
    k = 50
    while k < n - 100:
        length = int(rng.uniform(1.5, 3.0) * RATE)
        end = min(n - 50, k + length)
        level[k:end] = 0.3 + 0.5 * np.abs(np.sin(np.arange(end - k) / 6.0))  # syllables
        pitch[k:end] = 12.0 - np.arange(end - k) / RATE  # a declining phrase
        peak = k + (end - k) // 2
        pitch[peak - 10:peak + 10] = 12.0 + 5.0 * np.hanning(20) ** 0.5 + 0.5
        accents.append(peak)
        pauses.append(end)
        k = end + int(rng.uniform(0.4, 1.0) * RATE)
    return level, pitch, pauses, accents


@pytest.mark.parametrize("f0", [85.0, 140.0, 260.0])
def test_the_pitch_of_a_voiced_tone_is_found_and_noise_is_unvoiced(f0):
    t = np.arange(16000) / 16000
    tone = 0.3 * sum(np.sin(2 * np.pi * f0 * k * t) / k for k in range(1, 8))
    found = pitch_hz(tone, 100)[3:97]
    assert np.all(np.abs(found / f0 - 1) < 0.005)
    noise = np.random.default_rng(1).normal(0, 0.3, 16000)
    assert np.mean(pitch_hz(noise, 100) > 0) < 0.05
    assert semitones(np.array([110.0, 0.0])) == pytest.approx([12.0, 0.0])


def test_the_cues_are_the_pauses_and_accents_put_there():
    level, pitch, pauses, accents = _voice(60.0)
    cues = voice_cues(level, pitch, RATE)
    assert [k for k, _ in cues.accents] == pytest.approx(accents, abs=10)  # within 0.1 s of each
    found = list(cues.pauses)
    assert len(found) == len(pauses) and np.all(np.abs(np.array(found) - pauses) <= 1)
    assert cues.speaking[accents].all() and not cues.speaking[np.array(pauses) + 20].any()


@pytest.mark.slow  # five seconds: make test runs it, test-fast does not
def test_blinks_come_as_often_as_asked_fewer_while_speaking_and_at_pauses():
    """Ten minutes of silence blink near 17 a minute (less the second after each blink, when none
    comes); a voice's phrases near 8 a minute; and most pauses start with a blink."""
    silent = voice_cues(np.zeros(60_000), np.zeros(60_000), RATE)
    shut = life_offsets(silent, LifeSettings(seed=3))["shut"]
    rate = np.sum((shut[1:] > 0.5) & (shut[:-1] <= 0.5)) / 10.0
    assert 13.0 < rate < 19.0
    level, pitch, pauses, _ = _voice(600.0, seed=1)
    cues = voice_cues(level, pitch, RATE)
    shut = life_offsets(cues, LifeSettings(seed=3))["shut"]
    starts = np.flatnonzero((shut[1:] > 0.05) & (shut[:-1] <= 0.05)) + 1
    at_pause = [any(0 <= s - p <= 30 for p in pauses) for s in starts]
    during = [s for s, near in zip(starts, at_pause, strict=True) if not near and cues.speaking[s]]
    minutes_speaking = cues.speaking.sum() / RATE / 60
    assert len(during) / minutes_speaking < 11.0  # fewer than in silence
    assert np.mean([any(0 <= s - p <= 30 for s in starts) for p in pauses]) > 0.4  # a blink opens many pauses
    lengths = np.diff(np.flatnonzero(np.diff((shut > 0.01).astype(int))))[::2] / RATE
    assert 0.08 <= np.median(lengths) <= 0.4


def test_brows_rise_on_the_accents_and_gaze_holds_then_jumps():
    level, pitch, _, accents = _voice(60.0)
    cues = voice_cues(level, pitch, RATE)
    add = life_offsets(cues, LifeSettings(seed=5))
    brow = add["brow"]
    for k in accents:
        window = brow[k - 30:k + 30]
        assert window.max() > 0.1 and abs(int(np.argmax(window)) - 30) <= 15  # its top within 0.15 s of the peak
    quiet = np.ones(len(brow), bool)
    for k in accents:
        quiet[k - 40:k + 80] = False
    assert brow[quiet].max() < 1e-9  # nothing between accents
    steps = np.abs(np.diff(add["gaze_h"])) + np.abs(np.diff(add["gaze_v"]))
    moving = steps > 1e-6
    assert 0.02 < moving.mean() < 0.15  # still most of the time: fixations, then quick saccades


def test_the_layer_is_the_same_with_one_seed_and_leaves_what_the_source_drives():
    level, pitch, _, _ = _voice(20.0)
    cues = voice_cues(level, pitch, RATE)
    n = len(level)
    values = np.tile(standard_neutral(), (n, 1))
    values[:, MOTOR_CODES.index("MB")] = 0.2 + 0.5 * level
    track = MotorTrack(values, RATE, extra_codes=("HT",), extra=np.full((n, 1), 0.5))
    one = add_life(track, cues, set(MOUTH), LifeSettings(seed=7))
    again = add_life(track, cues, set(MOUTH), LifeSettings(seed=7))
    other = add_life(track, cues, set(MOUTH), LifeSettings(seed=8))
    assert np.array_equal(one.values, again.values) and np.array_equal(one.extra, again.extra)
    assert not np.array_equal(one.values, other.values)
    for code in MOUTH:
        assert np.array_equal(one.values[:, MOTOR_CODES.index(code)], values[:, MOTOR_CODES.index(code)])
    for code in (*LIDS, "BRM", "PRH", "HV", "HH"):
        assert np.ptp(one.values[:, MOTOR_CODES.index(code)]) > 0.005, code
    assert np.ptp(one.extra) > 0.001  # the head tilts
    kept = add_life(track, cues, {*MOUTH, "ERU", "ELU", "HT"}, LifeSettings(seed=7))
    assert np.array_equal(kept.values[:, MOTOR_CODES.index("ERU")], values[:, MOTOR_CODES.index("ERU")])
    assert np.array_equal(kept.extra, track.extra)
    with pytest.raises(ValueError, match="cues of"):
        add_life(MotorTrack(values[:10], RATE), cues, set())


def test_map_of_a_voice_comes_alive_by_default_and_not_with_no_life(tmp_path):
    from sounds import write_tone

    from toon import load_track
    from toonface.cli import main

    voice = write_tone(tmp_path / "line.wav", seconds=4.0)
    assert main(["map", str(voice), "-o", str(tmp_path / "alive.csv")]) == 0
    assert main(["map", str(voice), "-o", str(tmp_path / "still.csv"), "--no-life"]) == 0
    alive, still = load_track(tmp_path / "alive.csv"), load_track(tmp_path / "still.csv")
    column = {code: i for i, code in enumerate(MOTOR_CODES)}
    for code in MOUTH:
        np.testing.assert_allclose(alive.values[:, column[code]], still.values[:, column[code]], atol=1e-6)
    for code in ("PRH", "HV", "HH"):
        assert np.ptp(alive.values[:, column[code]]) > 0.003 and np.ptp(still.values[:, column[code]]) < 1e-6, code


def test_live_and_offline_are_one_layer_the_same_frames_in_silence():
    """With no cue to act on early or late, the live layer is the offline one, frame for frame."""
    n, neutral = 1500, standard_neutral()
    track = MotorTrack(np.tile(neutral, (n, 1)), RATE)
    offline = add_life(track, voice_cues(np.zeros(n), np.zeros(n), RATE), set(MOUTH), LifeSettings(seed=4))
    live = LiveLife(neutral, RATE, set(MOUTH), LifeSettings(seed=4))
    frames = np.array([live.step(neutral, np.ones(21), k / RATE)[0] for k in range(n)])
    np.testing.assert_array_equal(frames, offline.values)


def test_the_live_layer_follows_the_voice_as_it_comes_and_fills_what_is_lost():
    """Live, a brow rises just after each accent (found three frames after its peak), the driven
    motors are untouched, and pupils whose tracking is lost get the layer, fading in (no jump) to
    fully sure."""
    level, pitch, _, accents = _voice(60.0)
    neutral = standard_neutral()
    pupils = [MOTOR_CODES.index(code) for code in ("PRH", "PLH", "PRV", "PLV")]
    live = LiveLife(neutral, RATE, {*MOUTH, "PRH", "PLH", "PRV", "PLV"}, LifeSettings(seed=2))
    shown, sure = [], []
    for k in range(len(level)):
        values = neutral.copy()
        values[MOTOR_CODES.index("MB")] = 0.2 + 0.5 * level[k]
        values[pupils] = 0.9  # the performer looks far off ...
        confidence = np.ones(21)
        if 3000 <= k < 3500:  # ... until the camera loses the eyes for five seconds (they ease to rest)
            values[pupils] = neutral[pupils] + (0.9 - neutral[pupils]) * np.exp(-(k - 3000) / 20)
            confidence[pupils] = 0.0
        out, certain = live.step(values, confidence, k / RATE, level[k], pitch[k])
        shown.append(out)
        sure.append(certain)
    shown, sure = np.array(shown), np.array(sure)
    brow = shown[:, MOTOR_CODES.index("BRM")] - neutral[MOTOR_CODES.index("BRM")]
    for k in accents:
        assert brow[k:k + 40].max() > 0.1 and brow[k - 30:k].max() < 0.02  # risen within 0.4 s after, not before
    np.testing.assert_array_equal(shown[:, MOTOR_CODES.index("MB")], 0.2 + 0.5 * level)
    assert (shown[:3000, pupils] == 0.9).all() and (shown[3530:, pupils] == 0.9).all()  # (it fades out in 0.3 s)
    lost = shown[3100:3500, pupils] - neutral[pupils]
    assert np.abs(lost).max() < 0.21 and np.ptp(lost) > 0.01 and (sure[3030:3500][:, pupils] == 1.0).all()
    assert np.abs(np.diff(shown[2990:3500, pupils], axis=0)).max() < 0.1  # no jump as the layer comes in


def test_a_performer_the_camera_loses_stays_alive_with_life_and_freezes_without():
    """``send --life``: where the tracked face is lost its eyes and head get the layer, fully sure;
    where it is seen they are the performer's."""
    from dataclasses import replace as copy

    from capture.performance import CODES, NEUTRAL
    from capture.sources import take_source
    from capture.synthetic import performed
    from toonface.send import build_mapper

    rate = 60.0
    take = performed(np.tile([NEUTRAL[c] for c in CODES], (int(8 * rate), 1)), rate, seed=2).take
    positions = take.positions.copy()
    positions[int(3 * rate):int(6 * rate)] = np.nan  # the camera loses the face for three seconds
    take = copy(take, positions=positions)
    lost = slice(int(3.5 * rate), int(6 * rate))
    shown = {}
    for life in (True, False):
        source = take_source(take)
        mapper = build_mapper(source, target_neutral=standard_neutral(), life=life)
        frames = [mapper.step_frame(frame) for frame in source.frames]
        shown[life] = (np.array([f[0] for f in frames]), np.array([f[1] for f in frames]))
    prh, hv = MOTOR_CODES.index("PRH"), MOTOR_CODES.index("HV")
    alive, sure = shown[True]
    still, unsure = shown[False]
    assert np.ptp(alive[lost, prh]) > 0.02 and np.ptp(alive[lost, hv]) > 0.005
    assert (sure[int(4 * rate):int(6 * rate), prh] == 1.0).all()  # (faded in over 0.3 s once lost)
    settled = slice(int(5 * rate), int(6 * rate))  # without it, the lost eyes glide to rest and stay
    assert np.ptp(still[settled, prh]) < 1e-9 and (unsure[lost, prh] < 1.0).all()
    seen = slice(int(1.5 * rate), int(3 * rate))
    np.testing.assert_array_equal(alive[seen, prh], still[seen, prh])  # the performer's own where seen
