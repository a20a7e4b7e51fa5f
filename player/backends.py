"""Which renderer draws offline frames: OpenGL where there is a GPU, Cairo on the CPU where not.

Both draw the same geometry into the same picture (:mod:`player.cairo_renderer` says how close).
A software OpenGL (Mesa's llvmpipe) takes about three times as long as Cairo for a 512x512 face,
so ``auto`` takes Cairo where the machine shows no GPU device, where the context OpenGL gives is
a software one, and where no OpenGL context can be made at all; OpenGL where the system has no
libcairo. The live player keeps OpenGL: it shares its context with the preview and the window.
``TOONFACE_RENDERER`` (``gl``, ``cairo`` or ``auto``) overrides the choice for every command.
"""

from __future__ import annotations

import glob
import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Protocol

import moderngl
import numpy as np

from player.gl import RenderError, create_context
from player.renderer import Renderer
from toon import Geometry

if TYPE_CHECKING:
    from player.cairo_renderer import CairoRenderer

BACKENDS = ("auto", "gl", "cairo")
#: Substrings of GL_RENDERER that name a rasteriser running on the CPU.
SOFTWARE_GL = ("llvmpipe", "softpipe", "swrast", "software")


class FrameRenderer(Protocol):
    """What the offline paths need of a renderer."""

    size: tuple[int, int]

    def render(self, geometry: Geometry, alpha: bool = False) -> np.ndarray:
        """One frame, RGB ``uint8`` ``(height, width, 3)``, row 0 at the top; straight RGBA
        ``(height, width, 4)`` with ``alpha``."""
        ...


def chosen_backend(backend: str | None = None) -> str:
    """``backend``, else ``TOONFACE_RENDERER``, else ``auto``; checked against :data:`BACKENDS`."""
    name = (backend or os.environ.get("TOONFACE_RENDERER") or "auto").strip().lower()
    if name not in BACKENDS:
        raise RenderError(f"unknown renderer {name!r} in TOONFACE_RENDERER: "
                          f"expected one of {', '.join(BACKENDS)}")
    return name


@contextmanager
def open_renderer(size: tuple[int, int], samples: int = 4, backend: str | None = None,
                  ctx: moderngl.Context | None = None) -> Iterator[FrameRenderer]:
    """A renderer for offline frames, released on exit (with the GL context it made, if any).

    Parameters
    ----------
    size : (width, height)
    samples : int
        Antialiasing (see :class:`~player.renderer.Renderer` and
        :class:`~player.cairo_renderer.CairoRenderer`).
    backend : str, optional
        ``gl``, ``cairo`` or ``auto`` (the default; see the module docstring).
    ctx : moderngl.Context, optional
        The caller's context, to draw with (and judge by) instead of making one: making a
        context makes it current, so one made and dropped here would leave the caller's idle.
    """
    name = chosen_backend(backend)
    cpu = None
    if name == "cairo" or (name == "auto" and ctx is None and not _gpu_device()):
        cpu = _cairo(size, samples, required=name == "cairo")
    own = None
    if cpu is None and ctx is None:
        try:
            ctx = own = create_context()
        except RenderError:
            cpu = None if name == "gl" else _cairo(size, samples, required=False)
            if cpu is None:
                raise
    if cpu is None and name == "auto" and ctx is not None and _software(ctx):
        cpu = _cairo(size, samples, required=False)
    if cpu is not None:
        if own is not None:
            own.release()
        with cpu:
            yield cpu
        return
    assert ctx is not None
    try:
        with Renderer(ctx, size, samples) as gl_renderer:
            yield gl_renderer
    finally:
        if own is not None:
            own.release()


def _cairo(size: tuple[int, int], samples: int, required: bool) -> CairoRenderer | None:
    """The Cairo renderer, or None where libcairo cannot be loaded (an error if ``required``)."""
    from player.cairo_renderer import CairoRenderer

    try:
        return CairoRenderer(size, samples)
    except (OSError, ImportError) as exc:
        if required:
            raise RenderError(f"cannot draw with Cairo ({exc}); install libcairo2") from None
        return None


def _gpu_device() -> bool:
    """Whether the machine shows a GPU to draw on (a DRM render node or an NVIDIA device): where
    none is, OpenGL can only be Mesa's software rasteriser, and no context is made to ask."""
    return bool(glob.glob("/dev/dri/renderD*") or glob.glob("/dev/nvidia[0-9]*"))


def _software(ctx: moderngl.Context) -> bool:
    """Whether the context draws on the CPU."""
    return any(word in str(ctx.info.get("GL_RENDERER", "")).lower() for word in SOFTWARE_GL)
