"""Pictures in a face: CharToon's scanned backgrounds and hand-painted parts as image components.

A face's ``image`` component (:mod:`toon.components`) shows a PNG picture stretched over the
parallelogram of its three points (top-left, top-right, bottom-left corner), on its layer, moved,
scaled, turned and shown by its motors and parameters as any component is. The picture is read
once, when the face is: from a PNG file beside the face (``"src": "scan.png"``) or from the face
file itself (``"src": "data:image/png;base64,..."``, what the studio writes, so a face and its
pictures travel as one file).
"""

from __future__ import annotations

import base64
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common.errors import InputError
from common.limits import MAX_PICTURE_BYTES, MAX_PICTURE_PIXELS, MAX_PICTURE_SIDE, read_regular

#: How a picture embedded in a face file starts.
DATA_PNG = "data:image/png;base64,"


@dataclass(frozen=True, eq=False)
class Picture:
    """A picture as drawn: ``pixels`` straight RGBA ``uint8`` ``(height, width, 4)``, row 0 at the
    top; ``href``, the same picture as a PNG data URI (for SVG, the studio and files)."""

    pixels: np.ndarray
    href: str

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` in pixels."""
        return int(self.pixels.shape[1]), int(self.pixels.shape[0])


def decode_png(data: bytes, where: str) -> Picture:
    """A PNG's bytes as a :class:`Picture`; a ValueError naming ``where`` for anything else."""
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(io.BytesIO(data)) as image:
            if image.format != "PNG":
                raise ValueError(f"{where}: expected a PNG picture, got {image.format or 'something else'}")
            width, height = image.size
            if max(width, height) > MAX_PICTURE_SIDE or width * height > MAX_PICTURE_PIXELS:
                raise ValueError(f"{where}: the picture is {width}x{height} pixels; at most {MAX_PICTURE_SIDE} a "
                                 f"side and {MAX_PICTURE_PIXELS} in all")
            pixels = np.ascontiguousarray(np.asarray(image.convert("RGBA"), dtype=np.uint8))
    except (UnidentifiedImageError, OSError, Image.DecompressionBombError) as exc:
        raise ValueError(f"{where}: not a readable PNG picture ({exc})") from None
    if pixels.size == 0:
        raise ValueError(f"{where}: the picture has no pixels")
    return Picture(pixels, DATA_PNG + base64.b64encode(data).decode("ascii"))


def load_picture(src: str, base_dir: Path | None) -> Picture:
    """The picture ``src`` names: a PNG data URI, or a PNG file (relative to ``base_dir``, the
    face file's folder). A ValueError saying what is wrong."""
    if src.startswith("data:"):
        if not src.startswith(DATA_PNG):
            raise ValueError(f"a picture in the face file is a PNG data URI ({DATA_PNG}...)")
        if len(src) - len(DATA_PNG) > MAX_PICTURE_BYTES * 4 // 3 + 4:
            raise ValueError(f"the picture in the face file is larger than the {MAX_PICTURE_BYTES} bytes a picture "
                             "may have")
        try:
            data = base64.b64decode(src[len(DATA_PNG):], validate=True)
        except ValueError:
            raise ValueError("the PNG data URI is not valid base64") from None
        return decode_png(data, "the picture in the face file")
    path = Path(src)
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    if path.suffix.lower() != ".png":
        raise ValueError(f"{src}: a picture is a .png file (or a PNG data URI)")
    try:
        data = read_regular(path, MAX_PICTURE_BYTES, "picture")
    except InputError as exc:
        raise ValueError(f"{src}: {exc.message}") from None
    return decode_png(data, src)


def corners(points: np.ndarray) -> np.ndarray:
    """The four corners ``(4, 2)`` (top-left, top-right, bottom-right, bottom-left) of the
    parallelogram of three points ``(3, 2)``: top-left, top-right, bottom-left."""
    tl, tr, bl = points
    return np.array([tl, tr, tr + bl - tl, bl])


#: The outline operator of an image: its three points to its four corners (:func:`corners`).
CORNERS = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 1.0], [0.0, 0.0, 1.0]])


def pixel_affine(quad: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """The 2x3 affine that takes a picture's pixel coordinates ``(x, y)`` (``size`` ``(width,
    height)``, row 0 on top) to where its corners ``quad`` ``(4, 2)`` (top-left, top-right,
    bottom-right, bottom-left) lie: ``[[a, c, e], [b, d, f]]`` with ``x' = a x + c y + e``."""
    width, height = size
    tl, tr, _, bl = quad
    across, down = (tr - tl) / width, (bl - tl) / height
    return np.array([[across[0], down[0], tl[0]], [across[1], down[1], tl[1]]])
