"""The score's sound stave: a file's loudness beside the motor staves, on the track's clock."""

import av
import numpy as np

from common.sound import sound_envelope
from player.score import STAVE_PX, score_image
from toon import MotorTrack
from toonface.cli import main


def _tone(path, loud_from: float, loud_to: float, seconds: float = 2.0, rate: int = 16000) -> None:
    """A quiet hum with a loud stretch, as AAC in an .m4a."""
    t = np.arange(int(seconds * rate)) / rate
    wave = 0.01 * np.sin(2 * np.pi * 220 * t)
    wave[(t >= loud_from) & (t < loud_to)] *= 50
    with av.open(str(path), "w") as container:
        stream = container.add_stream("aac", rate=rate)
        stream.layout = "mono"
        for start in range(0, len(wave), 1024):
            frame = av.AudioFrame.from_ndarray(wave[None, start:start + 1024].astype(np.float32), format="fltp",
                                               layout="mono")
            frame.sample_rate, frame.pts = rate, start
            container.mux(stream.encode(frame))
        container.mux(stream.encode(None))


def test_the_envelope_is_loud_where_the_sound_is_and_scaled_to_one(tmp_path):
    _tone(tmp_path / "voice.m4a", 0.8, 1.2)
    times, loud = sound_envelope(tmp_path / "voice.m4a")
    assert loud.max() == 1.0 and 1.9 < times[-1] < 2.1
    inside = (times > 0.85) & (times < 1.15)
    outside = (times < 0.7) | (times > 1.3)
    assert loud[inside].min() > 0.7 and loud[outside].max() < 0.1  # 50 times quieter outside


def test_the_sound_stave_is_drawn_under_the_motors(tmp_path):
    _tone(tmp_path / "voice.m4a", 0.8, 1.2)
    track = MotorTrack(np.full((50, 21), 0.5), 25.0)
    plain = score_image(track, codes=("MB",), width=600)
    with_sound = score_image(track, codes=("MB",), width=600, sound=sound_envelope(tmp_path / "voice.m4a"))
    assert with_sound.shape[0] == plain.shape[0] + STAVE_PX
    stave = with_sound[STAVE_PX:2 * STAVE_PX]
    tall = (np.abs(stave.astype(int) - 150).max(axis=2) < 30).sum(axis=0) > STAVE_PX // 2  # filled high
    columns = np.flatnonzero(tall)
    x0, plot = 70, 600 - 70 - 90  # the score's margins: the loud stretch, 0.8-1.2 s of 2 s
    assert len(columns) and columns.min() > x0 + 0.35 * plot and columns.max() < x0 + 0.65 * plot
    track_file = tmp_path / "m.csv"
    from toon import save_track

    save_track(track, track_file)
    assert main(["score", str(track_file), "-o", str(tmp_path / "s.png"), "--sound", str(tmp_path / "voice.m4a"),
                 "--motors", "MB"]) == 0
    assert (tmp_path / "s.png").stat().st_size > 0
