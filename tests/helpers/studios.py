"""The folder a test's studio works in."""

import tempfile
from pathlib import Path

from toonface.studio.guard import Folder


def temp_folder() -> Folder:
    """Where pytest makes every ``tmp_path``: a test's studio reads and writes its files there
    (a studio reads and writes only inside its folder)."""
    return Folder(Path(tempfile.gettempdir()).resolve())
