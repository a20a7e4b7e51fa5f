"""Motor streams the stream tests share: smooth motion and the datagrams a writer makes of it."""

import numpy as np

from stream.packets import StreamWriter

RATE = 60.0


def smooth_motion(frames: int, seed: int = 0) -> np.ndarray:
    """Smooth random motor curves ``(frames, 21)`` in [0, 1]."""
    rng = np.random.default_rng(seed)
    t = np.arange(frames)[:, None] / RATE
    return np.clip(0.5 + 0.3 * np.sin(2 * np.pi * rng.uniform(0.2, 2, 21) * t + rng.uniform(0, 6, 21))
                   + rng.normal(0, 0.003, (frames, 21)), 0, 1)


def packets(values: np.ndarray, **options) -> tuple[StreamWriter, list[bytes]]:
    """``values`` ``(n, 21)`` at :data:`RATE` through a fresh writer (sequence from 0, no
    acknowledgements), flushed: the writer and its datagrams."""
    writer = StreamWriter(RATE, first_sequence=0, **options)
    out = [d for i, row in enumerate(values) if (d := writer.push(row, i / RATE)) is not None]
    last = writer.flush()
    return writer, out + ([last] if last else [])
