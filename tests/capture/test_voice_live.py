"""A live voice (issue 40): a sound file played as a microphone gives it, its frames' times and
delay on an injected clock, the channels a voice take has, and `send` driven by it."""

import numpy as np
import pytest

from capture.sources import open_source
from capture.voice import SAMPLE_RATE, VISEMES
from capture.voice_live import CHANNELS, played, voice_frames
from capture.voice_take import read_voice
from tests.capture.test_voice_sound import _speech
from toonface.cli import main


class FakeClock:
    """A clock that moves only when slept on."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.now += seconds


def _wav(path, sound: np.ndarray) -> None:
    import av

    with av.open(str(path), "w") as out:
        stream = out.add_stream("pcm_s16le", rate=SAMPLE_RATE, layout="mono")
        frame = av.AudioFrame.from_ndarray((sound * 32767).astype(np.int16)[None], format="s16", layout="mono")
        frame.sample_rate = SAMPLE_RATE
        for packet in (*stream.encode(frame), *stream.encode(None)):
            out.mux(packet)


@pytest.fixture
def line(tmp_path):
    path = tmp_path / "line.wav"
    _wav(path, _speech([("-", 0.5), ("a", 0.4), ("-", 0.1), ("i", 0.3), ("u", 0.3), ("-", 0.6)]))
    return path


def test_a_sound_file_plays_as_a_live_voice_each_frame_within_its_lookahead(line):
    clock = FakeClock()
    source = open_source(str(line), clock=clock, sleep=clock.sleep)
    assert source.live and source.channel_names == CHANNELS and source.labels == ()
    frames = []
    for frame in source.frames:
        frames.append(frame)
        assert clock.now - frame.t <= 0.1226  # sound to shapes: 122.5 ms at most (two blends, half a window, a chunk)
    take = read_voice(line)
    assert len(frames) == take.frames  # the last frames are placed when the sound ends
    assert [f.t for f in frames] == pytest.approx(np.arange(take.frames) / 100)
    live = np.array([f.channels for f in frames])
    np.testing.assert_allclose(live[:, :-2].sum(axis=1), 1.0, atol=1e-9)  # shapes' weights sum to 1
    x = VISEMES.index("X")
    assert (live[:40, x] > 0.99).all()  # silence before the voice: rest, also live
    opening_live = live[:, VISEMES.index("C")] + live[:, VISEMES.index("D")]
    opening_file = take.channels[:, VISEMES.index("C")] + take.channels[:, VISEMES.index("D")]
    assert np.corrcoef(opening_live, opening_file)[0, 1] > 0.9  # its own scale, learned as it goes
    pitch_file, pitch_live = take.channel("voice_pitch"), live[:, -1]
    voiced = pitch_file > 0
    assert voiced.sum() > 50  # the vowels
    assert np.mean(np.abs(pitch_live[voiced] - pitch_file[voiced]) < 0.3) > 0.9  # the file's pitch, as it comes
    assert np.mean(pitch_live[~voiced] > 0) < 0.05


def test_the_live_level_is_the_files_once_the_loudest_has_been_heard(line):
    sound = np.asarray(read_voice(line).channel("sound_level"))
    clock = FakeClock()
    chunks = played(np.asarray(_speech([("-", 0.5), ("a", 0.4), ("-", 0.1), ("i", 0.3), ("u", 0.3), ("-", 0.6)])),
                    clock=clock, sleep=clock.sleep)
    level = np.array([f.channels[-2] for f in voice_frames(chunks)])
    loudest = int(np.argmax(sound))
    np.testing.assert_allclose(level[loudest:], sound[loudest:len(level)], atol=2e-4)


def test_a_missing_sound_file_or_microphone_is_a_one_line_error(tmp_path, capsys):
    assert main(["send", f"voice:{tmp_path / 'none.wav'}", "--to", "127.0.0.1:9"]) == 2
    assert "no such sound file" in capsys.readouterr().err


@pytest.mark.slow
def test_send_streams_a_voice_live_and_records_the_mouth(line, tmp_path, capsys):
    from toon import MOTOR_CODES, load_track

    assert main(["send", str(line), "--to", "127.0.0.1:9", "--record", str(tmp_path / "sent.csv")]) == 0
    said = capsys.readouterr()
    assert "its rest is silence" in said.out + said.err
    sent = load_track(tmp_path / "sent.csv")
    mb = sent.values[:, MOTOR_CODES.index("MB")]
    assert sent.frames == read_voice(line).frames
    assert np.ptp(mb[:40]) < 0.01 and mb[55:85].max() > mb[:40].mean() + 0.2  # shut, then the "a" opens it
    assert "the life layer moves what the mapping does not drive" in said.out + said.err  # on for a voice, as offline
    for code in ("PRH", "HV", "HH"):  # gaze, breathing and sway: alive while it speaks
        assert np.ptp(sent.values[:, MOTOR_CODES.index(code)]) > 0.003, code
    assert main(["send", str(line), "--to", "127.0.0.1:9", "--record", str(tmp_path / "still.csv"), "--no-life"]) == 0
    still = load_track(tmp_path / "still.csv")
    assert np.ptp(still.values[:, MOTOR_CODES.index("PRH")]) == 0.0
