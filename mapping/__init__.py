"""mapping: turn a :class:`capture.Take` into a :class:`toon.MotorTrack`.

Clean (spikes, gaps, smoothing) with head motion removed, calibrate a performer profile, map
per channel by a mapping file. Imports ``capture`` (for takes) and ``toon`` (for motor codes
and tracks), nothing else.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
