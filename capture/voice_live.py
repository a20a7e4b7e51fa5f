"""A voice as it is heard: a microphone, or a sound file played in real time in its place.

``voice:mic`` (the system's default input through PulseAudio, or ALSA's), ``voice:mic:DEVICE``
(an ALSA device such as ``hw:1``), ``voice:FILE`` or just ``FILE.wav`` (any sound file; its sound
is fed 10 ms at a time, each piece when its time comes, as a sound card gives it). Each frame of
mouth shapes leaves :class:`capture.voice_sound.Listener` 112.5 ms after its sound (its fixed
look-ahead) with the channels a voice take has (``viseme_A`` ... ``viseme_X``, ``sound_level``,
``voice_pitch``),
so ``play --source`` and ``send`` map it with the same voice mapping as ``map voice.wav``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from capture.sources import Frame, Source
from capture.voice import FRAME_RATE, LOOKAHEAD, SAMPLE_RATE, VISEMES, decode_voice
from capture.voice_pitch import pitch_hz, semitones
from capture.voice_sound import HOP, WINDOW, Listener
from common import InputError

#: Each frame's channels, as :func:`capture.voice_take.read_voice` names them.
CHANNELS = (*(f"viseme_{v}" for v in VISEMES), "sound_level", "voice_pitch")
#: A frame this far below the loudest heard so far has no pitch (dB), as :func:`capture.voice_pitch.pitch_hz` gates.
QUIET_DB = -45.0
#: How much sound a file played in real time hands over at once (s): a sound card's period.
CHUNK_S = 0.01


def voice_frames(chunks: Iterator[np.ndarray], listener: Listener | None = None) -> Iterator[Frame]:
    """Frames of mouth shapes from ``chunks`` of sound (16 kHz mono float32) as they come: frame
    ``k`` at ``t = k / 100`` s, its channels :data:`CHANNELS` (the level scaled by the loudest
    10 ms heard so far; the pitch by YIN, as a voice file's, 0 where unvoiced or quieter than
    :data:`QUIET_DB` below that loudest)."""
    listener = Listener() if listener is None else listener
    pending = np.zeros(0, np.float32)  # sound from frame `index` on (frame k: samples k*HOP to (k+1)*HOP)
    loudest, index, heard = 1e-9, 0, 0
    ended = np.zeros((2 * LOOKAHEAD + 1) * HOP + WINDOW, np.float32)  # silence after the end places the last frames
    for chunk, last in _then_silence(chunks, ended):
        heard += 0 if last else len(chunk)
        pending = np.concatenate([pending, np.asarray(chunk, np.float32)])
        placed = listener.hear(chunk)
        if last:
            placed = placed[:max(0, heard // HOP - index)]
        pitches = semitones(pitch_hz(pending, len(placed), quiet_db=-np.inf)) if len(placed) else np.zeros(0)
        for k, weights in enumerate(placed):
            piece = pending[k * HOP:(k + 1) * HOP].astype(np.float64)
            level = float(np.sqrt(np.mean(piece ** 2))) if len(piece) else 0.0
            loudest = max(loudest, level)
            pitch = pitches[k] if level > loudest * 10 ** (QUIET_DB / 20) else 0.0
            yield Frame((index + k) / FRAME_RATE, np.zeros((0, 3)), np.append(weights, [level / loudest, pitch]))
        index += len(placed)
        pending = pending[len(placed) * HOP:]


def _then_silence(chunks: Iterator[np.ndarray], silence: np.ndarray) -> Iterator[tuple[np.ndarray, bool]]:
    for chunk in chunks:
        yield chunk, False
    yield silence, True


def played(samples: np.ndarray, clock: Callable[[], float] = time.perf_counter,
           sleep: Callable[[float], None] = time.sleep) -> Iterator[np.ndarray]:
    """``samples`` (16 kHz) in pieces of :data:`CHUNK_S`, each when the clock reaches its end, as
    a microphone hands over what it has just heard."""
    step = int(CHUNK_S * SAMPLE_RATE)
    start = clock()
    for k in range(0, len(samples), step):
        wait = start + (k + step) / SAMPLE_RATE - clock()
        if wait > 0:
            sleep(wait)
        yield samples[k:k + step]


def microphone(device: str = "") -> tuple[Iterator[np.ndarray], Callable[[], None]]:
    """Sound from a microphone (PyAV: PulseAudio's default input, else ALSA's ``default``, or the
    ALSA ``device`` named), opened now: 16 kHz mono float32 pieces as the device delivers them,
    and what closes it.

    Raises
    ------
    InputError
        When no such input can be opened.
    """
    import av

    tries = [(device, "alsa")] if device else [("default", "pulse"), ("default", "alsa")]
    container, errors = None, []
    for name, driver in tries:
        try:
            container = av.open(name, format=driver)
            break
        except (OSError, ValueError, av.error.FFmpegError) as exc:
            errors.append(f"{driver} {name}: {exc}")
    if container is None:
        raise InputError(f"no microphone could be opened ({'; '.join(errors)})", f"voice:mic:{device}".rstrip(":"))
    opened = container

    def pieces() -> Iterator[np.ndarray]:
        resampler = av.AudioResampler(format="flt", layout="mono", rate=SAMPLE_RATE)
        for frame in opened.decode(audio=0):
            for piece in resampler.resample(frame):
                yield piece.to_ndarray().reshape(-1).astype(np.float32)
    return pieces(), opened.close


def voice_source(target: str, clock: Callable[[], float] = time.perf_counter,
                 sleep: Callable[[float], None] = time.sleep, **_: Any) -> Source:
    """A live voice (see the module docstring): ``target`` is ``mic``, ``mic:DEVICE`` or a sound file."""
    release = None
    if target == "mic" or target.startswith("mic:"):
        (chunks, release), name = microphone(target[4:]), "microphone"
    else:
        path = Path(target)
        if not path.is_file():
            raise InputError("no such sound file (a voice source is mic, mic:DEVICE or a sound file)", target)
        chunks, name = played(decode_voice(path), clock, sleep), path.name
    wait_ms = 1000 * (2 * LOOKAHEAD * HOP + WINDOW / 2 + CHUNK_S * SAMPLE_RATE) / SAMPLE_RATE
    meta = {"source": "voice", "file": name, "listen": "sound", "rest_seconds": 0.0, "lookahead_ms": wait_ms}
    return Source((), FRAME_RATE, voice_frames(chunks), name, live=True, meta=meta, channel_names=CHANNELS,
                  release=release)
