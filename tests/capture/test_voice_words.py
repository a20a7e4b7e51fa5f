"""The mouth from the words an English voice says (issue 61): the phones' presence, the learned
opening and its gate, the shapes, the shipped model, and ``lipsync --listen words`` on a real clip."""

from __future__ import annotations

import numpy as np
import pytest

from capture.voice import KERNEL, VISEMES, Phone, blend, openness
from capture.voice_model import MEL_BANDS, MouthModel, model_from_dict, shipped_words_model
from capture.voice_sound import BANDS, GATE
from capture.voice_words import (
    LENGTH,
    LONG_VOWEL,
    PHONES,
    WORDS_READ,
    presence,
    vowel_length,
    words_mouth,
    words_opening,
    words_read,
)
from common import InputError
from toonface.cli import main


def test_presence_is_each_phone_a_frame_blended_and_silence_the_rest():
    got = presence([Phone("AA", 0.10, 0.30), Phone("M", 0.30, 0.35)], 60)
    aa, m, sil = PHONES.index("AA"), PHONES.index("M"), len(PHONES) - 1
    assert got.shape == (60, len(PHONES)) and np.allclose(got.sum(axis=1), 1.0)
    assert got[20, aa] == pytest.approx(1.0) and got[0, sil] == pytest.approx(1.0)
    assert got[50, sil] == pytest.approx(1.0)
    assert got[10, aa] == pytest.approx(KERNEL[5:].sum())  # the first frame of AA: the kernel's half from its centre
    assert got[32, m] == pytest.approx(KERNEL[3:8].sum())  # frames 30-34 of M seen from frame 32
    speech = np.ones(60, bool)
    speech[:25] = False  # no voice heard there: silence, whatever the phones say
    assert presence([Phone("AA", 0.10, 0.30)], 60, speech)[15, sil] == pytest.approx(1.0)


def test_a_vowels_length_is_read_beside_the_phones_and_an_older_models_names_read_only_the_phones():
    phones = [Phone("AA", 0.10, 0.25), Phone("M", 0.25, 0.35), Phone("IY", 0.35, 0.95)]
    length = vowel_length(phones, 100)
    assert length[17] == pytest.approx(0.15 / LONG_VOWEL)  # well inside AA: its 150 ms of the 300
    assert length[60] == pytest.approx(1.0) and length[0] == 0.0  # a long IY reads 1; silence 0
    assert length[27] == pytest.approx(0.5 * KERNEL[:3].sum())  # in M: AA's last 3 frames in the blend's reach
    speech = np.ones(100, bool)
    speech[:30] = False
    assert vowel_length(phones, 100, speech)[17] == 0.0  # no voice there: no vowel
    read = words_read(phones, 100)
    assert WORDS_READ == (*PHONES, LENGTH) and read.shape == (100, len(WORDS_READ))
    assert np.array_equal(read[:, :-1], presence(phones, 100)) and np.array_equal(read[:, -1], length)
    assert np.array_equal(words_read(phones, 100, names=PHONES), presence(phones, 100))


def _model_of_aa() -> MouthModel:
    """Opens as wide as AA is present, the spectrum ignored."""
    weights = np.zeros(MEL_BANDS + len(PHONES))
    weights[MEL_BANDS + PHONES.index("AA")] = 1.0
    return MouthModel((0,), np.zeros_like(weights), weights, 0.0, {}, PHONES)


def test_the_opening_is_the_models_and_shuts_only_after_a_pause_with_neither_words_nor_voice():
    frames = 100
    units = np.zeros((frames, BANDS + MEL_BANDS))
    units[:, 0] = GATE / 2  # a room's tone throughout
    heard = presence([Phone("AA", 0.40, 0.60)], frames)
    model = _model_of_aa()
    assert np.allclose(model.opening(units[:, BANDS:], heard), heard[:, PHONES.index("AA")])
    got = words_opening(units, heard, model)
    assert np.allclose(got[35:65], heard[35:65, PHONES.index("AA")])  # the word: as the model says
    loud = units.copy()
    loud[:, 0] = 0.9  # a voice throughout: never shut
    always = MouthModel((0,), model.mean, np.zeros_like(model.weights), 0.5, {}, PHONES)
    assert np.allclose(words_opening(loud, heard, always), 0.5)
    quiet = words_opening(units, heard, always)  # 200 ms either side of the word held, shut beyond
    assert np.allclose(quiet[25:75], 0.5) and np.allclose(quiet[:14], 0.0) and np.allclose(quiet[86:], 0.0)
    with pytest.raises(ValueError, match="values of the words"):
        model.opening(units[:, BANDS:])


def test_the_shapes_follow_the_phones_and_the_opening():
    frames, rate = 150, 16000
    t = np.arange(frames * 160) / rate
    sound = (0.3 * np.sin(2 * np.pi * 150 * t) * ((t > 0.2) & (t < 1.0))).astype(np.float32)
    phones = [Phone("AA", 0.20, 0.45), Phone("F", 0.45, 0.60), Phone("UW", 0.60, 1.00)]
    weights, cues = words_mouth(sound, frames, phones, _model_of_aa())
    assert weights.shape == (frames, len(VISEMES)) and np.allclose(weights.sum(axis=1), 1.0)
    named = "".join(VISEMES[k] for k in cues)
    assert named[:10] == "X" * 10 and named[-10:] == "X" * 10  # rest in silence
    assert set(named[30:40]) == {"D"} and set(named[48:56]) == {"G"}  # AA wide open, F teeth on lip
    assert not set(named[70:95]) & set("BCD")  # UW rounds the lips: the round ladder (A F E D)
    assert openness(blend(weights))[30:40].min() > 0.8


def test_the_shipped_words_model_reads_every_phone_and_the_vowels_length_and_says_how_it_was_made():
    model = shipped_words_model()
    assert model.magnitude  # the spectra and their magnitudes, then the words
    assert model.phones == WORDS_READ and len(model.weights) == 2 * len(model.offsets) * MEL_BANDS + len(WORDS_READ)
    assert model.notes["command"] == "python -m bench.lipsync_train" and model.notes["phone_scale"] > 0
    assert set(model.notes["final_speakers"]) <= set(model.notes["trained_on"])
    again = model_from_dict(model.to_dict())
    assert again.phones == WORDS_READ and again.weights.tolist() == model.weights.tolist() and again.magnitude
    doc = model.to_dict()
    with pytest.raises(InputError, match="must read silence"):  # words_opening shuts on it
        model_from_dict({**doc, "phones": [p if p != "SIL" else "QUIET" for p in doc["phones"]]})


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
@pytest.mark.realdata
def test_lipsync_hears_the_words_of_a_grid_clip(realdata, tmp_path, capsys):
    """GRID's bbaf2n: the words recognised (whatever they are) shape a mouth that rests at the
    ends, shuts at least once and says how it listened."""
    clip = realdata / "video" / "grid" / "bbaf2n.mpg"
    if not clip.is_file():
        pytest.skip(f"{clip} is absent")
    out = tmp_path / "c.tsv"
    assert main(["lipsync", str(clip), "--listen", "words", "-o", str(out)]) == 0
    shapes = [line.split("\t")[1] for line in out.read_text().splitlines()]
    assert shapes[0] == "X" and shapes[-1] == "X" and {"C", "D"} & set(shapes) and "A" in shapes
    assert "words heard (English)" in capsys.readouterr().out


@pytest.mark.parametrize("seconds", [0.01, 0.05, 1.0])
def test_digital_silence_is_rest_however_short_in_every_way_of_listening(seconds):
    """The recogniser heard three words in a second of digital silence (the mouth opened to C),
    and a sound too short to hear anything in raised a TypeError: now rest (X), shut, throughout."""
    from capture.voice_take import LISTEN_MODES, mouth_of

    silence = np.zeros(int(seconds * 16000), np.float32)
    for listen in LISTEN_MODES:
        _, shapes, weights = mouth_of(silence, None, listen)
        assert {VISEMES[k] for k in shapes} == {"X"}, listen
        assert weights is None or np.allclose(openness(weights), 0.0)
