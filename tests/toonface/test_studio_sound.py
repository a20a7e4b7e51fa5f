"""The studio's sound: decoding, the waveform, the WAV the page plays, Audacity's labels."""

import io
import wave

import pytest
from sounds import write_tone

from common import InputError
from toonface.studio.sound import PEAKS_PER_SECOND, RATE, load_labels, load_sound


def test_a_sound_is_decoded_drawn_and_served_as_wav(tmp_path):
    sound = load_sound(write_tone(tmp_path / "tone.wav"))
    assert sound.duration == pytest.approx(2.0, abs=0.01)
    low, high = sound.peaks()
    assert len(high) == pytest.approx(2.0 * PEAKS_PER_SECOND, abs=1)
    assert max(high[:90]) == pytest.approx(0.5, abs=0.02) and min(low[:90]) == pytest.approx(-0.5, abs=0.02)
    assert max(high[110:]) == pytest.approx(0.0, abs=0.01)  # the silence
    with wave.open(io.BytesIO(sound.wav())) as file:
        assert (file.getframerate(), file.getnchannels(), file.getsampwidth()) == (RATE, 1, 2)
        assert file.getnframes() == len(sound.samples)


def test_labels_are_audacitys(tmp_path):
    path = tmp_path / "labels.txt"
    path.write_text("0.5\t1.25\tbin blue\n\\\t120.0\t3000.0\n2\t2\tat\n0.1\t0.3\t\n", encoding="utf-8")
    labels = load_labels(path)
    assert [(lb.start, lb.end, lb.text) for lb in labels] == [(0.1, 0.3, ""), (0.5, 1.25, "bin blue"), (2.0, 2.0, "at")]
    path.write_text("0.5\t1.25\tok\nhello there\n", encoding="utf-8")
    with pytest.raises(InputError, match="line 2.*start<TAB>end"):
        load_labels(path)
    path.write_text("2\t1\tbackwards\n", encoding="utf-8")
    with pytest.raises(InputError, match="start <= end"):
        load_labels(path)


def test_files_without_sound_say_so(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        load_sound(tmp_path / "missing.wav")
    (tmp_path / "text.wav").write_text("not a sound")
    with pytest.raises(InputError, match="text.wav"):
        load_sound(tmp_path / "text.wav")


@pytest.mark.realdata
def test_a_grid_clips_voice_is_its_length(realdata):
    import av

    clips = sorted((realdata / "video" / "grid").glob("*.mpg"))
    if not clips:
        pytest.skip(f"no GRID clip in {realdata / 'video' / 'grid'}")

    with av.open(str(clips[0])) as container:
        stream = container.streams.audio[0]
        expected = float(stream.duration * stream.time_base)
    sound = load_sound(clips[0])
    assert sound.duration == pytest.approx(expected, abs=0.05)
    assert max(sound.peaks()[1]) > 0.05  # someone speaks
