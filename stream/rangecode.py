"""Arithmetic coding of small integer symbols with static models, byte-aligned per message.

The coder keeps its interval exactly, as Python integers (``[low, low + width)`` over ``scale``),
so there is no renormalisation and no carry to propagate; a message of a few hundred symbols
costs a few kilobits of integer arithmetic. The output is the shortest bit string whose interval
lies inside the final one, padded with zeros to whole bytes: a message costs its information
content plus at most 9 bits. (Coders with word-sized output, such as ANS or range coders that
emit 32-bit words, waste up to 31 bits per message, more than a whole frame of motors here.)

Models are static frequency tables (:class:`Model`); the caller picks one per symbol, and may
pick it from the symbols decoded so far (context modelling), since decoding is symbol by symbol.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Sequence

import numpy as np


class Model:
    """A static distribution over the symbols ``0 .. len(frequencies) - 1``.

    Parameters
    ----------
    frequencies : sequence of int
        Positive counts; a symbol's probability is its count over their total.
    """

    def __init__(self, frequencies: Sequence[int]) -> None:
        freq = [int(f) for f in frequencies]
        if not freq or min(freq) < 1:
            raise ValueError("every symbol needs a positive frequency")
        self.freq = freq
        self.cum = [0, *np.cumsum(freq).tolist()]
        self.total = self.cum[-1]

    @classmethod
    def laplace(cls, size: int, centre: int, decay: float, precision: int = 1 << 16) -> Model:
        """A two-sided geometric distribution: P(s) ∝ ``decay ** |s - centre|``, every symbol at
        least 1 of about ``precision`` counts (so an unlikely symbol still codes)."""
        s = np.arange(size)
        p = decay ** np.abs(s - centre)
        return cls(1 + np.floor(p / p.sum() * (precision - size)).astype(np.int64))

    def bits(self, symbol: int) -> float:
        """The symbol's information content, bits."""
        return float(np.log2(self.total / self.freq[symbol]))


class Encoder:
    """Code symbols one by one, then :meth:`finish` into bytes."""

    def __init__(self) -> None:
        self._low, self._width, self._scale = 0, 1, 1

    def encode(self, symbol: int, model: Model) -> None:
        """Narrow the interval to ``symbol``'s share under ``model``."""
        if not 0 <= symbol < len(model.freq):
            raise ValueError(f"symbol {symbol} is outside the model's 0..{len(model.freq) - 1}")
        self._low = self._low * model.total + model.cum[symbol] * self._width
        self._width *= model.freq[symbol]
        self._scale *= model.total

    def finish(self) -> bytes:
        """The shortest byte string that decodes to the symbols encoded."""
        low, width, scale = self._low, self._width, self._scale
        n = max(0, (scale // width).bit_length() - 1)
        while True:
            value = -((-low << n) // scale)  # the first n-bit fraction at or above low
            if (value + 1) * scale <= (low + width) << n:
                break
            n += 1
        size = (n + 7) // 8
        return (value << (8 * size - n)).to_bytes(size, "big")


class Decoder:
    """Read back what an :class:`Encoder` wrote, symbol by symbol, with the same models."""

    def __init__(self, data: bytes) -> None:
        self._value = int.from_bytes(data, "big")
        self._bits = 8 * len(data)
        self._low, self._width, self._scale = 0, 1, 1

    def decode(self, model: Model) -> int:
        """The next symbol under ``model``."""
        total = model.total
        # the symbol whose share holds value / 2**bits, in the interval's own units
        rest = self._value * self._scale * total - ((self._low * total) << self._bits)
        symbol = min(max(bisect_right(model.cum, rest // (self._width << self._bits)) - 1, 0), len(model.freq) - 1)
        self._low = self._low * total + model.cum[symbol] * self._width
        self._width *= model.freq[symbol]
        self._scale *= total
        return symbol
