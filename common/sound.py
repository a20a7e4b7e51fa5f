"""A file's sound, decoded: whether it has any, its mono samples and its loudness over time.

Shared by everything that reads a voice: the tracker that notes where a video is silent
(:mod:`capture.video_tracking`), the muxer that puts it beside a cartoon and the score's
loudness stave (:mod:`player`), and the studio.
"""

from __future__ import annotations

import os

import av
import numpy as np

from common.errors import InputError, require_file
from common.limits import MAX_SOUND_SECONDS, check_sound


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
    require_file(path)
    try:
        with av.open(str(path)) as container:
            if not container.streams.audio:
                raise InputError("no audio stream", path)
            stream = container.streams.audio[0]
            own = stream.codec_context.sample_rate or 0
            check_sound(own, _stated_seconds(container, stream), path)
            offset = _start(stream)
            if container.streams.video:
                offset -= _start(container.streams.video[0])
            rate = rate or own
            most = int(MAX_SOUND_SECONDS * rate) + rate  # a header may understate the length: count as it comes
            resampler = av.AudioResampler(format="flt", layout="mono", rate=rate)
            pieces: list[np.ndarray] = []
            count = 0
            for frame in (*container.decode(stream), None):  # None: what the resampler holds back
                for piece in resampler.resample(frame):
                    pieces.append(piece.to_ndarray().reshape(-1))
                    count += len(pieces[-1])
                    if count > most:
                        check_sound(rate, count / rate, path)
    except av.error.FFmpegError as exc:
        raise InputError(f"cannot decode its sound ({exc})", path) from None
    samples = np.concatenate(pieces or [np.zeros(0, np.float32)])
    if not np.isfinite(samples).all():
        raise InputError("its sound holds samples that are not numbers (NaN or infinity)", path)
    return samples, rate, offset


def _stated_seconds(container: av.container.InputContainer, stream: av.stream.Stream) -> float:
    """The sound's length as its headers state it (0 where they do not)."""
    if stream.duration is not None and stream.time_base:
        return float(stream.duration * stream.time_base)
    return container.duration / av.time_base if container.duration is not None else 0.0


def _start(stream: av.stream.Stream) -> float:
    return float(stream.start_time * stream.time_base) if stream.start_time is not None and stream.time_base else 0.0
