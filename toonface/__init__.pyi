"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .pipeline import DemoResult, map_onto_face, render, run_demo, truth_track

__version__: str

__all__ = [
    "DemoResult",
    "__version__",
    "map_onto_face",
    "render",
    "run_demo",
    "truth_track",
]
