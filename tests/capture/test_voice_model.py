"""The voice's learned mouth (issue 61): the shipped weights, the features they read, and the
training command that rebuilds them."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from bench.lipsync_data import Clip
from bench.lipsync_train import LAGS, PHONE_SCALES, lag_rs, shifted
from capture.voice import LOOKAHEAD, blend
from capture.voice_model import MEL_BANDS, MouthModel, in_context, mel_filters, model_from_dict, shipped_model
from capture.voice_sound import learned_opening, sound_units
from capture.voice_words import WORDS_READ
from common import InputError


def test_the_shipped_model_reads_the_spectrum_no_further_ahead_than_a_live_voice_waits():
    model = shipped_model()
    assert model.magnitude and model.lookahead <= LOOKAHEAD  # the spectra in context, then their magnitudes
    assert len(model.weights) == 2 * len(model.offsets) * MEL_BANDS
    assert model.notes["command"] == "python -m bench.lipsync_train"
    assert set(model.notes["final_speakers"]) <= set(model.notes["trained_on"])
    again = model_from_dict(model.to_dict())
    assert again.weights.tolist() == model.weights.tolist() and again.magnitude  # (round trip, exactly)
    with pytest.raises(InputError, match="not a voice mouth model"):
        model_from_dict({**model.to_dict(), "weights": [1.0]})
    with pytest.raises(InputError, match="magnitude must be true or false"):
        model_from_dict({**model.to_dict(), "magnitude": "yes"})
    with pytest.raises(InputError, match="twice with magnitude"):  # the weights of a model without them
        model_from_dict({**model.to_dict(), "magnitude": False})


def test_a_model_that_reads_a_bands_magnitude_opens_as_the_band_departs_from_the_voices_level_either_way():
    """One weight on the magnitude of one band: the opening grows with the band's distance from 0
    (the voice's level), whether the band swells or falls silent; on the band itself it would
    open one way only. A file of before, without the key, reads the spectra alone."""
    band = 7
    weights = np.zeros(2 * MEL_BANDS)
    weights[MEL_BANDS + band] = 0.25
    model = MouthModel((0,), np.zeros(2 * MEL_BANDS), weights, 0.0, {}, (), magnitude=True)
    spectra = np.zeros((5, MEL_BANDS))
    spectra[:, band] = [-3.0, -1.0, 0.0, 1.0, 3.0]
    assert model.opening(spectra).tolist() == [0.75, 0.25, 0.0, 0.25, 0.75]
    plain = MouthModel((0,), np.zeros(MEL_BANDS), weights[MEL_BANDS:], 0.0, {})
    assert plain.opening(spectra).tolist() == [0.0, 0.0, 0.0, 0.25, 0.75]
    doc = {**plain.to_dict(), "notes": "a file of before"}
    assert "magnitude" not in doc and not model_from_dict(doc).magnitude
    assert model_from_dict(model.to_dict()).opening(spectra).tolist() == [0.75, 0.25, 0.0, 0.25, 0.75]


def test_mel_filters_cover_their_range_once_and_context_clamps_at_the_ends():
    filters = mel_filters(512, 16000)
    freqs = np.fft.rfftfreq(512, 1 / 16000)
    inside = (freqs > 200) & (freqs < 7000)
    assert filters.shape == (MEL_BANDS, 257) and np.allclose(filters[:, inside].sum(axis=0), 1.0, atol=1e-9)
    assert filters[:, freqs > 7700].sum() == 0.0
    rows = np.arange(5.0)[:, None]
    assert in_context(rows, (-2, 0, 1)).tolist() == [[0, 0, 1], [0, 1, 2], [0, 2, 3], [1, 3, 4], [2, 4, 4]]


def _voice(seconds: float = 2.0, seed: int = 0) -> np.ndarray:
    """A buzz whose loudness and first formant rise and fall like syllables."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * 16000)) / 16000
    syllables = 0.5 + 0.5 * np.sin(2 * np.pi * 3 * t)
    buzz = np.sign(np.sin(2 * np.pi * 120 * t)) * syllables + 0.01 * rng.normal(size=len(t))
    from scipy.signal import lfilter

    return lfilter([1.0], [1.0, -1.6, 0.8], buzz).astype(np.float32) * 0.05


def test_a_voices_spectrum_is_normalised_per_voice_so_gain_changes_nothing():
    sound = _voice()
    frames = len(sound) // 160
    loud, quiet = sound_units(sound, frames), sound_units(0.2 * sound, frames)
    assert loud.shape == (frames, 3 + MEL_BANDS)
    assert np.median(np.abs(loud - quiet)) < 1e-4  # (but near the 1e-8 floor of the logarithm: the
    assert np.percentile(np.abs(loud - quiet), 99) < 0.05  # highest bands of a voice that has little there)


def test_the_learned_opening_follows_the_syllables_of_a_voice_it_never_heard_and_silence_is_shut():
    sound = np.concatenate([np.zeros(8000, np.float32), _voice(3.0, seed=1), np.zeros(8000, np.float32)])
    frames = len(sound) // 160
    curve = blend(learned_opening(sound_units(sound, frames)))
    assert (curve[:45] <= 0.1).all() and (curve[-45:] <= 0.1).all()
    curve = curve[50:-50]
    t = np.arange(len(curve)) / 100
    syllables = blend(0.5 + 0.5 * np.sin(2 * np.pi * 3 * t))
    assert np.corrcoef(curve[20:-20], syllables[20:-20])[0, 1] > 0.5


def test_a_clips_truth_is_put_in_step_with_its_sound_by_the_lag_its_opening_follows_best():
    """A clip whose sound comes 50 ms after its mouth (the lip gap now is the opening the sound
    gives 50 ms later): its opening follows the gap best read 5 frames later, and the truth
    shifted by that lag follows the opening itself frame for frame (as sampled at 25 frames/s),
    what training fits; unshifted or shifted the other way, it does not."""
    rng = np.random.default_rng(4)
    frames = 400
    opening = blend(blend((rng.random(frames) < 0.1).astype(float)))  # (frames,) at 100 Hz, smooth
    video_times = np.arange(0.0, (frames - 10) / 100.0, 0.04)  # 25 frames/s
    gap = np.interp(video_times + 0.05, np.arange(frames) / 100.0, opening)
    clip = Clip("c", "c", "grid", np.zeros(frames * 160), video_times, gap)
    lag = int(LAGS[int(np.argmax(lag_rs(opening, clip)))])
    assert lag == 5
    truth = np.interp(np.arange(frames) / 100.0, video_times, gap)  # the gap on the sound's clock
    inside = slice(10, int(video_times[-1] * 100) - 10)
    step = np.corrcoef(shifted(truth, lag)[inside], opening[inside])[0, 1]
    late, early = (np.corrcoef(shifted(truth, k)[inside], opening[inside])[0, 1] for k in (0, -lag))
    assert step > 0.98 and step > late + 0.1 and step > early + 0.2, (step, late, early)


@pytest.mark.slow  # two GRID clips tracked, heard and learned from, twice (about a minute)
def test_the_training_command_rebuilds_the_same_weights_bit_for_bit(tmp_path, realdata):
    """On a small subset (the two GRID clips, two speakers): two runs of the command, in two
    processes, write the same bytes for both models, models that load."""
    outputs = []
    for k in range(2):
        out = tmp_path / f"run{k}"
        subprocess.run([sys.executable, "-m", "bench.lipsync_train", "--corpus", "grid", "--out", str(out)],
                       check=True, capture_output=True, timeout=600)
        outputs.append([(out / name).read_bytes() for name in ("voice_mouth.json", "voice_mouth_words.json")])
        assert not list(out.glob("*.partial"))
    assert outputs[0] == outputs[1]
    sound, words = (model_from_dict(json.loads(doc)) for doc in outputs[0])
    assert sound.notes["trained_on"] == words.notes["trained_on"] == ["bbaf2n", "lbax4n"]
    assert not sound.phones and words.phones == WORDS_READ and words.notes["phone_scale"] in PHONE_SCALES


def test_the_clips_found_beside_the_shared_ones_are_sourced_new_speakers_with_a_face_and_its_sound():
    """``bench/talking`` (issue 61: more speakers): each clip is named in ``SOURCES.md``, is a
    224x224 face at 25 fps with as long a sound, shows no speaker another clip shows, and the
    shipped models were trained on it."""
    import av

    from bench.lipsync_data import OURS, SAME_SPEAKER
    from capture.voice import decode_voice_at
    from capture.voice_model import shipped_words_model

    found = sorted(OURS.glob("*.mp4"))
    sources = (OURS / "SOURCES.md").read_text(encoding="utf-8")
    assert [clip.name for clip in found] == ["vox-00373.mp4", "vox-681600002.mp4"]
    for clip in found:
        assert f"`{clip.name}`" in sources and (OURS / "LICENSE.CC-BY-4.0").is_file()
        with av.open(str(clip)) as container:
            video = container.streams.video[0]
            frames = sum(1 for _ in container.decode(video))
            assert (video.width, video.height, video.average_rate) == (224, 224, 25)
        sound, _ = decode_voice_at(clip)
        assert abs(len(sound) / 16000 - frames / 25) < 0.1, (clip.name, len(sound) / 16000, frames / 25)
        assert clip.stem not in SAME_SPEAKER and clip.stem not in SAME_SPEAKER.values()
        for model in (shipped_model(), shipped_words_model()):
            assert clip.stem in model.notes["trained_on"] and model.notes["corpus"][clip.stem] == "wild"
