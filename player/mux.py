"""A rendered video with the sound of the take it came from: the performer's own audio, muxed in.

The picture's packets are copied as they are; the sound is decoded, resampled and encoded as AAC
(what every browser plays in an MP4; Opus in a WebM), from ``start`` seconds of the source's clock and for the
picture's duration, so that the two stay in step and end together.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path
from typing import cast

import av
from av.audio.stream import AudioStream

from common import InputError, atomic_path
from common.sound import has_audio

__all__ = ["SOUND_CONTAINERS", "has_audio", "mux_audio"]

#: The picture files that can carry sound: their container and its audio codec and rate (None:
#: the sound's own).
SOUND_CONTAINERS: dict[str, tuple[str, str, int | None]] = {
    ".mp4": ("mp4", "aac", None), ".mov": ("mov", "aac", None), ".webm": ("webm", "libopus", 48000)}


def mux_audio(picture: str | os.PathLike, sound: str | os.PathLike, output: str | os.PathLike,
              start: float = 0.0) -> Path:
    """Write ``output`` (an MP4, a QuickTime .mov or a WebM: :data:`SOUND_CONTAINERS`): the video
    stream of ``picture`` and the audio of ``sound`` from ``start`` seconds (its container's
    clock) for as long as the picture lasts. Appears only when complete.

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
        container, codec, fixed_rate = SOUND_CONTAINERS[output.suffix.lower()]
        rate = fixed_rate or audio.codec_context.sample_rate or 48000
        with atomic_path(output) as tmp, av.open(str(tmp), mode="w", format=container) as out:
            out_video = out.add_stream_from_template(video, options={"movflags": "+faststart"}
                                                     if container != "webm" else {})
            out_audio = cast(AudioStream, out.add_stream(codec, rate=rate))
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
                if frame.time is not None and frame.time + frame.samples / (frame.sample_rate or rate) <= start:
                    continue
                for piece in resampler.resample(frame):
                    if limit is not None and written >= limit:
                        break
                    piece.pts, piece.time_base = written, Fraction(1, rate)
                    written += piece.samples
                    out.mux(out_audio.encode(piece))
            out.mux(out_audio.encode(None))
    return output
