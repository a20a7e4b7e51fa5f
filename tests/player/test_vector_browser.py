"""Vector outputs in a real browser (issue 41): the animated SVG of a take, paused at three
times in headless Chromium, against the offscreen renderer's frame at each time."""

import io

import numpy as np
import pytest
from browser import chromium
from PIL import Image

from capture import synthesize
from player.backends import open_renderer
from player.offline import resample
from toon import FaceRig, builtin_faces, load_face
from toon.svg_anim import save_track_svg
from toonface.pipeline import truth_track

pytestmark = pytest.mark.slow
TIMES = (2.0, 5.0, 9.0)  # seconds: expressions of the synthetic performer, away from frame edges


def test_the_animated_svg_shows_the_renderers_frames_at_three_times(tmp_path):
    values = resample(truth_track(synthesize(seconds=10.0, rate=30.0, seed=5)), 30.0)
    with chromium(700, 800) as driver, open_renderer((512, 512)) as renderer:
        for name in builtin_faces():
            rig = FaceRig(load_face(name))
            path = save_track_svg([rig.geometry(row) for row in values], 30.0, tmp_path / f"{name}.svg")
            driver.get(path.as_uri())
            for t in TIMES:
                driver.execute_script(f"const s = document.documentElement; s.pauseAnimations(); "
                                      f"s.setCurrentTime({t});")
                png = driver.get_screenshot_as_png()
                shown = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))[:512, :512].astype(int)
                drawn = renderer.render(rig.geometry(values[int(round(t * 30))])).astype(int)
                assert np.abs(shown - drawn).mean() <= 1.5, (name, t, np.abs(shown - drawn).mean())
