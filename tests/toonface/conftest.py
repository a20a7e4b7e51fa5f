"""Fixtures the command-line tests share."""

import pytest

from capture import save_take, synthesize
from toonface.cli import main


@pytest.fixture(scope="module")
def small_take(tmp_path_factory):
    """A 2 s synthetic take at 30 Hz and its mapped motors."""
    root = tmp_path_factory.mktemp("small")
    save_take(synthesize(seconds=2.0, rate=30.0).take, root / "t.npz")
    assert main(["map", str(root / "t.npz"), "-o", str(root / "m.csv")]) == 0
    return root
