"""Sounds the studio's tests write."""

import wave
from pathlib import Path

import numpy as np


def write_tone(path: Path, seconds: float = 1.0, rate: int = 22_050, amplitude: float = 0.5) -> Path:
    """A 440 Hz tone as a 16-bit mono WAV, then one second of silence."""
    t = np.arange(int(seconds * rate)) / rate
    return write_wav(path, np.concatenate([amplitude * np.sin(2 * np.pi * 440 * t), np.zeros(rate)]), rate)


def write_wav(path: Path, samples: np.ndarray, rate: int) -> Path:
    """``samples`` (-1..1, clipped) as a 16-bit mono WAV at ``rate``."""
    with wave.open(str(path), "wb") as file:
        file.setnchannels(1)
        file.setsampwidth(2)
        file.setframerate(rate)
        file.writeframes((np.clip(samples, -1.0, 1.0) * 32767).astype("<i2").tobytes())
    return path


def cut_clip(source: Path, path: Path, start: float) -> Path:
    """``source`` (a video with sound) from ``start`` seconds on, re-encoded as an MP4 (H.264 and
    AAC) whose clock starts at 0: a clip cut where its speaker is about to speak."""
    from fractions import Fraction

    import av

    with av.open(str(source)) as inp, av.open(str(path), "w", format="mp4") as out:
        video_in, audio_in = inp.streams.video[0], inp.streams.audio[0]
        rate = int(round(float(video_in.average_rate or 25)))
        video = out.add_stream("libx264", rate=rate)
        video.width, video.height, video.pix_fmt = video_in.width, video_in.height, "yuv420p"
        audio_rate = audio_in.codec_context.sample_rate
        audio = out.add_stream("aac", rate=audio_rate)
        resampler = av.AudioResampler(format="fltp", layout="mono", rate=audio_rate)
        index = written = 0
        for frame in inp.decode(video_in):
            if frame.time is not None and frame.time + 1e-6 >= start:
                image = av.VideoFrame.from_ndarray(frame.to_ndarray(format="rgb24"), format="rgb24")
                image.pts, image.time_base = index, Fraction(1, rate)
                index += 1
                out.mux(video.encode(image))
        out.mux(video.encode(None))
        with av.open(str(source)) as again:
            for frame in again.decode(again.streams.audio[0]):
                if frame.time is None or frame.time + frame.samples / audio_rate <= start:
                    continue
                for piece in resampler.resample(frame):
                    piece.pts, piece.time_base = written, Fraction(1, audio_rate)
                    written += piece.samples
                    out.mux(audio.encode(piece))
        out.mux(audio.encode(None))
    return path
