"""A voice's pitch, each 10 ms: the fundamental frequency by YIN (de Cheveigné and Kawahara 2002,
"YIN, a fundamental frequency estimator for speech and music", JASA 111:1917): the difference
function of a 32 ms window against itself shifted by each lag, normalised by its running mean,
and the first lag whose dip falls below a threshold (the voice is periodic there), refined by a
parabola through its neighbours. Unvoiced frames (a dip nowhere below the threshold, or a frame
too quiet to be speech) give 0.

The life layer (:mod:`mapping.life`) reads it as the take's ``voice_pitch`` channel, in semitones
above 55 Hz (0: unvoiced), for the brow raises that fall on pitch accents.
"""

from __future__ import annotations

import numpy as np

#: The lowest and highest pitch looked for (Hz): men's low speech to children's and raised voices.
FMIN, FMAX = 65.0, 450.0
#: YIN's absolute threshold on the normalised difference: 0.25 where the paper has 0.1, since real
#: recordings are noisier than its (on three shared clips it finds 27-60 % of speech voiced, 0-7 % of silence).
THRESHOLD = 0.25
#: The window (samples at 16 kHz: 32 ms) and the frames' hop (10 ms).
WINDOW, HOP, RATE = 512, 160, 16000
#: Semitones are counted above this (Hz): every voiced frame's value is then above 0.
BASE_HZ = 55.0


def pitch_hz(samples: np.ndarray, frames: int, quiet_db: float = -45.0) -> np.ndarray:
    """The pitch of each of ``frames`` 10 ms frames of ``samples`` (16 kHz mono), Hz, 0 where
    unvoiced or quieter than ``quiet_db`` below the loudest frame; shape ``(frames,)``."""
    longest = int(RATE / FMIN) + 2
    shortest = int(RATE / FMAX)
    span = WINDOW + longest
    x = np.pad(np.asarray(samples, np.float64), (0, frames * HOP + span))
    windows = np.lib.stride_tricks.sliding_window_view(x, span)[::HOP][:frames]  # (frames, span)
    size = 1 << int(np.ceil(np.log2(2 * span)))
    spectrum = np.fft.rfft(windows, size, axis=1)
    head = np.fft.rfft(windows[:, :WINDOW], size, axis=1)
    r = np.fft.irfft(spectrum * np.conj(head), size, axis=1)[:, :longest]  # sum x[j] x[j + tau], j < WINDOW
    energy = np.concatenate([np.zeros((frames, 1)), np.cumsum(windows ** 2, axis=1)], axis=1)
    lags = np.arange(longest)
    e0 = energy[:, WINDOW][:, None]
    e_tau = energy[:, lags + WINDOW] - energy[:, lags]
    d = np.maximum(e0 + e_tau - 2 * r, 0.0)
    d[:, 0] = 0.0
    running = np.cumsum(d[:, 1:], axis=1) / np.arange(1, longest)
    normal = np.ones_like(d)
    normal[:, 1:] = d[:, 1:] / np.maximum(running, 1e-12)
    out = np.zeros(frames)
    level = 10 * np.log10(e0[:, 0] / WINDOW + 1e-12)
    loud = float(level.max()) if frames else 0.0
    for k in np.flatnonzero(level > loud + quiet_db):
        row = normal[k]
        below = np.flatnonzero(row[shortest:longest - 1] < THRESHOLD)
        if not len(below):
            continue
        tau = int(below[0]) + shortest
        while tau + 1 < longest - 1 and row[tau + 1] < row[tau]:  # down to the dip's bottom
            tau += 1
        a, b, c = row[tau - 1], row[tau], row[tau + 1]
        shift = 0.5 * (a - c) / (a - 2 * b + c) if abs(a - 2 * b + c) > 1e-12 else 0.0
        out[k] = RATE / (tau + float(np.clip(shift, -0.5, 0.5)))
    return out


def semitones(hz: np.ndarray) -> np.ndarray:
    """Pitch in Hz as semitones above :data:`BASE_HZ` (0 stays 0: unvoiced)."""
    hz = np.asarray(hz, dtype=float)
    return np.where(hz > 0, 12.0 * np.log2(np.maximum(hz, 1e-9) / BASE_HZ), 0.0)
