"""A rendered video with the sound of the take it came from: the performer's own audio, muxed in.

The picture's packets are copied as they are; the sound is decoded, resampled and encoded as AAC
(what every browser plays in an MP4), from ``start`` seconds of the source's clock and for the
picture's duration, so that the two stay in step and end together.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import av
import numpy as np

from common import InputError, atomic_path


def has_audio(path: str | os.PathLike) -> bool:
    """Whether the file has an audio stream PyAV can open."""
    try:
        with av.open(str(path)) as container:
            return bool(container.streams.audio)
    except av.error.FFmpegError:
        return False


def sound_envelope(path: str | os.PathLike, step: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    """The loudness of a file's sound: RMS over each ``step`` seconds, scaled to its loudest as 1;
    ``(times, envelope)``, each ``(n,)``, times from the file's first video frame where it has
    one (the clock a track mapped from that video keeps), else from the sound's start.

    Raises
    ------
    InputError
        When the file has no audio stream or cannot be decoded.
    """
    samples, rate, offset = decode_mono(path)
    size = max(1, int(round(step * rate)))
    count = len(samples) // size
    rms = np.sqrt(np.mean(samples[:count * size].reshape(count, size).astype(float) ** 2, axis=1))
    return offset + np.arange(count) * size / rate, rms / max(float(rms.max(initial=0.0)), 1e-12)


def decode_mono(path: str | os.PathLike, rate: int | None = None) -> tuple[np.ndarray, int, float]:
    """A file's sound (its first audio stream: a WAV, an MP3, a video's) as mono float samples
    ``(n,)`` at ``rate`` (its own by default), that rate, and where the sound starts on the
    clock of the file's first video frame (0 without video), seconds.

    Raises
    ------
    InputError
        When the file has no audio stream or cannot be decoded.
    """
    try:
        with av.open(str(path)) as container:
            if not container.streams.audio:
                raise InputError("no audio stream", path)
            stream = container.streams.audio[0]
            offset = _start(stream)
            if container.streams.video:
                offset -= _start(container.streams.video[0])
            rate = rate or stream.codec_context.sample_rate or 48000
            resampler = av.AudioResampler(format="flt", layout="mono", rate=rate)
            pieces = [piece.to_ndarray().reshape(-1) for frame in container.decode(stream)
                      for piece in resampler.resample(frame)]
            pieces += [piece.to_ndarray().reshape(-1) for piece in resampler.resample(None)]  # what it holds back
    except av.error.FFmpegError as exc:
        raise InputError(f"cannot decode its sound ({exc})", path) from None
    return np.concatenate(pieces or [np.zeros(0, np.float32)]), rate, offset


def _start(stream: av.stream.Stream) -> float:
    return float(stream.start_time * stream.time_base) if stream.start_time is not None and stream.time_base else 0.0


def mux_audio(picture: str | os.PathLike, sound: str | os.PathLike, output: str | os.PathLike,
              start: float = 0.0) -> Path:
    """Write ``output``: the video stream of ``picture`` and the audio of ``sound`` from ``start``
    seconds (its container's clock) for as long as the picture lasts. Appears only when complete.

    Raises
    ------
    InputError
        When ``sound`` has no audio stream.
    """
    output = Path(output)
    with av.open(str(picture)) as video_in, av.open(str(sound)) as sound_in:
        if not sound_in.streams.audio:
            raise InputError("no audio stream to take the sound from", sound)
        video = video_in.streams.video[0]
        duration = float(video.duration * video.time_base) if video.duration and video.time_base else None
        audio = sound_in.streams.audio[0]
        rate = audio.codec_context.sample_rate or 48000
        with atomic_path(output) as tmp, av.open(str(tmp), mode="w", format="mp4") as out:
            out_video = out.add_stream_from_template(video, options={"movflags": "+faststart"})
            out_audio = out.add_stream("aac", rate=rate)
            out_audio.layout = "stereo" if (audio.codec_context.channels or 1) > 1 else "mono"
            resampler = av.AudioResampler(format="fltp", layout=out_audio.layout, rate=rate)
            for packet in video_in.demux(video):
                if packet.dts is None:
                    continue
                packet.stream = out_video
                out.mux(packet)
            written = 0
            limit = None if duration is None else int(round(duration * rate))
            for frame in sound_in.decode(audio):
                if frame.time is not None and frame.time + frame.samples / rate <= start:
                    continue
                for piece in resampler.resample(frame):
                    if limit is not None and written >= limit:
                        break
                    piece.pts, piece.time_base = written, Fraction(1, rate)
                    written += piece.samples
                    out.mux(out_audio.encode(piece))
            out.mux(out_audio.encode(None))
    return output
