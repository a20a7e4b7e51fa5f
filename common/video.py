"""Decoded video frames the way they are meant to be seen: a phone's portrait video is stored on
its side with a display matrix saying how to turn it, which players (and OpenCV) obey."""

from __future__ import annotations

from typing import Any

import numpy as np


def upright(frame: Any, format: str = "rgb24") -> np.ndarray:
    """A decoded PyAV ``VideoFrame`` as an image ``(H, W, 3)`` turned by its display matrix.

    ``frame.rotation`` is the counter-clockwise angle (degrees, a multiple of 90 in practice)
    the container asks for; the image is turned by it to the nearest quarter turn, as OpenCV's
    own decoding does. Contiguous, since some consumers (MediaPipe) ignore strides.

    >>> class Frame:
    ...     rotation = 90
    ...     def to_ndarray(self, format):
    ...         return np.array([[[1], [2], [3]]])  # one row, three columns
    >>> upright(Frame())[:, :, 0].tolist()  # a quarter turn counter-clockwise: the last column on top
    [[3], [2], [1]]
    """
    image = frame.to_ndarray(format=format)
    turns = int(round(float(getattr(frame, "rotation", 0) or 0) / 90.0)) % 4
    return np.ascontiguousarray(np.rot90(image, turns)) if turns else image
