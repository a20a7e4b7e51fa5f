"""stream: motor values over a thin network link.

The wire format (quantised, predicted, range-coded frames with a CRC, or sealed with a key), the packet writer
and defensive reader, the receiver's jitter buffer and concealment, and a fault-injecting relay.
Imports ``toon`` and ``common`` only: what makes the values (mapping) and what shows them
(player) sit on either side of it.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
