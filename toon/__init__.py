"""toon: ToonFace faces and motors, turned into drawable geometry without any GL.

Knows faces, CharToon components and the 21 motors, nothing of markers or OpenGL.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
