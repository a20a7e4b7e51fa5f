"""capture: marker takes from files, a synthetic performer and (later) video.

Knows markers and nothing of faces: its output is a :class:`Take`.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
