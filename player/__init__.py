"""player: motor values over time into pictures (offscreen OpenGL through moderngl).

Imports ``toon``, never ``capture`` or ``mapping``.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
