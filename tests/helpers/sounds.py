"""Sounds the studio's tests write."""

import wave
from pathlib import Path

import numpy as np


def write_tone(path: Path, seconds: float = 1.0, rate: int = 22_050, amplitude: float = 0.5) -> Path:
    """A 440 Hz tone as a 16-bit mono WAV, then one second of silence."""
    t = np.arange(int(seconds * rate)) / rate
    samples = np.concatenate([amplitude * np.sin(2 * np.pi * 440 * t), np.zeros(rate)])
    with wave.open(str(path), "wb") as file:
        file.setnchannels(1)
        file.setsampwidth(2)
        file.setframerate(rate)
        file.writeframes((samples * 32767).astype("<i2").tobytes())
    return path
