"""player: motor values over time into pictures (offscreen OpenGL through moderngl).

Imports ``toon``, never ``capture`` or ``mapping``.
"""

from player.gl import RenderError, create_context
from player.offline import render_track, resample
from player.layout import triangulate
from player.renderer import Renderer
from player.sinks import Mp4Sink, PngSink, open_sink

__all__ = ["Mp4Sink", "PngSink", "RenderError", "Renderer", "create_context", "open_sink", "render_track",
           "resample", "triangulate"]
