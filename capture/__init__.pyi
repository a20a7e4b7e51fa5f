"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .markerset import MarkerSet, load_markerset
from .synthetic import SyntheticTake, synthesize
from .take import Take
from .takefile import load_take, save_take

__all__ = [
    "MarkerSet",
    "SyntheticTake",
    "Take",
    "load_markerset",
    "load_take",
    "save_take",
    "synthesize",
]
