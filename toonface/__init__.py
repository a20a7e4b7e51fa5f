"""toonface: the application: the ``toonface`` command and the one-call pipeline.

Wires ``capture``, ``mapping``, ``toon`` and ``player`` together; nothing below imports it.
"""

from toonface.pipeline import DemoResult, map_take, render, run_demo, truth_track

__version__ = "0.1.0"
__all__ = ["DemoResult", "__version__", "map_take", "render", "run_demo", "truth_track"]
