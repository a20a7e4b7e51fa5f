"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .backends import FrameRenderer, open_renderer
from .gl import RenderError, create_context
from .layout import triangulate
from .offline import render_track, resample
from .renderer import Renderer
from .sink_choice import open_sink
from .sinks import Mp4Sink, PngSink

__all__ = [
    "FrameRenderer",
    "Mp4Sink",
    "PngSink",
    "RenderError",
    "Renderer",
    "create_context",
    "open_renderer",
    "open_sink",
    "render_track",
    "resample",
    "triangulate",
]
