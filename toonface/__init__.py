"""toonface: the application: the ``toonface`` command and the one-call pipeline.

Wires ``capture``, ``mapping``, ``toon`` and ``player`` together; nothing below imports it.
"""

import lazy_loader

__version__ = "0.1.0"
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
