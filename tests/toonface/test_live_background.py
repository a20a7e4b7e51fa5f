"""play and receive take --background as render does (issue 44): none keeps the picture's alpha
for a compositor (OBS), a colour replaces the face's own; before, only editing the face file did."""

import numpy as np
import pytest
from PIL import Image

from toonface.cli import main

pytestmark = pytest.mark.gl


def first_frame(folder) -> np.ndarray:
    return np.asarray(Image.open(sorted(folder.glob("*.png"))[0]))


@pytest.mark.parametrize("command", [["play", "--listen", "off"],
                                     pytest.param(["receive", "--listen", "127.0.0.1:0"], marks=pytest.mark.slow)])
def test_live_pictures_take_a_background_none_or_a_colour(tmp_path, command):
    common = [*command, "--face", "round", "--size", "96x96", "--seconds", "0.3"]
    assert main([*common, "--background", "none", "-o", str(tmp_path / "clear")]) == 0
    clear = first_frame(tmp_path / "clear")
    assert clear.shape == (96, 96, 4) and clear[0, 0, 3] == 0 and clear[48, 48, 3] == 255  # the face alone is opaque
    assert main([*common, "--background", "#00ff00", "-o", str(tmp_path / "green")]) == 0
    green = first_frame(tmp_path / "green")
    assert tuple(green[0, 0, :3]) == (0, 255, 0)
    assert main([*common, "--background", "mauve"]) == 2
