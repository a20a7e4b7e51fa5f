"""capture: marker takes from files, a synthetic performer and (later) video.

Knows markers and nothing of faces: its output is a :class:`Take`.
"""

from capture.markerset import MarkerSet, load_markerset
from capture.synthetic import SyntheticTake, synthesize
from capture.take import Take
from capture.takefile import load_take, save_take

__all__ = ["MarkerSet", "SyntheticTake", "Take", "load_markerset", "load_take", "save_take", "synthesize"]
