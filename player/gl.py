"""The one place an OpenGL context is created."""

from __future__ import annotations

import moderngl

from common import ToonfaceError


class RenderError(ToonfaceError):
    """OpenGL is unavailable or failed."""


def create_context() -> moderngl.Context:
    """A standalone offscreen OpenGL 3.3+ context through EGL (Mesa's llvmpipe without a GPU).

    The caller owns it and must ``release()`` it.
    """
    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=330)  # type: ignore[arg-type]  # stub says dict
    except Exception as exc:  # glcontext raises bare Exceptions for every EGL failure
        raise RenderError(f"cannot create an offscreen OpenGL context through EGL ({exc}); "
                          "install Mesa's EGL (run `make install`)") from None
    return ctx
