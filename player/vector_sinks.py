"""Vector outputs: sinks that take each frame's geometry instead of its pixels.

- ``anim.svg``: one animated SVG of the whole track (:mod:`toon.svg_anim`: SMIL, no script),
  written when the track ends.
- a folder with ``--format svg``: ``frame_000000.svg`` ... one SVG per frame (:mod:`toon.svg`).
- ``anim.json``: a Lottie animation (:mod:`toon.lottie`), written when the track ends.

Both appear atomically like every picture output, and keep what was drawn under a partial name
when a run is interrupted. The render loop hands them :class:`toon.Geometry` (``vector = True``),
so nothing is rasterised.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from common import atomic_dir, atomic_path
from player.sinks import _AtomicSink
from toon.geometry import Geometry
from toon.lottie import track_lottie
from toon.svg import geometry_svg
from toon.svg_anim import track_svg


class AnimatedSvgSink(_AtomicSink):
    """The frames as one looping animated SVG at ``fps`` (see the module docstring); with
    ``lottie``, as a Lottie animation (JSON) instead."""

    vector = True
    alpha = True  # a face whose background is transparent stays so

    def __init__(self, path: str | os.PathLike, fps: float, size: tuple[int, int], lottie: bool = False) -> None:
        self.lottie = lottie
        super().__init__(atomic_path(path), path)
        self.fps, self.size = fps, size
        self._frames: list[Geometry] = []

    def write_geometry(self, geometry: Geometry) -> None:
        """Add one frame."""
        self._frames.append(geometry)
        self.frames += 1

    def write(self, frame: object) -> None:
        raise TypeError("an animated SVG takes geometry (write_geometry), not pixels")

    def skip(self, frames: int) -> None:
        """Slots without a frame: the last frame again."""
        if self._frames:
            self._frames.extend([self._frames[-1]] * max(0, frames))
            self.frames += max(0, frames)

    def _finish(self) -> None:
        if self._frames and self.lottie:
            document = track_lottie(self._frames, self.fps, self.size, name=self._target.stem)
            self._tmp.write_text(json.dumps(document, separators=(",", ":")), encoding="utf-8")
        elif self._frames:
            self._tmp.write_text(track_svg(self._frames, self.fps, self.size), encoding="utf-8")


class SvgFolderSink(_AtomicSink):
    """A folder of ``frame_000000.svg`` files, one per frame (replaced whole if it exists)."""

    vector = True
    alpha = True

    def __init__(self, directory: str | os.PathLike, size: tuple[int, int]) -> None:
        super().__init__(atomic_dir(directory), directory)
        self.size = size
        self._last: str | None = None

    def write_geometry(self, geometry: Geometry) -> None:
        """Write one frame as the next SVG."""
        self._last = geometry_svg(geometry, self.size)
        (self._tmp / f"frame_{self.frames:06d}.svg").write_text(self._last, encoding="utf-8")
        self.frames += 1

    def write(self, frame: object) -> None:
        raise TypeError("an SVG folder takes geometry (write_geometry), not pixels")

    def skip(self, frames: int) -> None:
        """Slots without a frame: the last SVG again."""
        for _ in range(max(0, frames) if self._last is not None else 0):
            (self._tmp / f"frame_{self.frames:06d}.svg").write_text(self._last or "", encoding="utf-8")
            self.frames += 1

    def _trim(self) -> None:
        for path in Path(self._tmp).glob("frame_*.svg"):
            if int(path.stem.split("_")[1]) >= self.frames:
                path.unlink()
