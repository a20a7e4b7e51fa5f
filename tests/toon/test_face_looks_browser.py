"""Issue 70, item 7, in a real browser: the faces as a viewer's page draws them (the SVG of
:mod:`toon.svg`, which the page that draws itself reproduces line for line: ``test_web_rig``),
drawn by Chromium. The round face's white never shows below its lower lid, and no expression or
pose opens a hole through the face (the "background at the mouth corner" the issue saw) where the
CPU renderer paints the same geometry."""

from __future__ import annotations

import io
from dataclasses import replace

import numpy as np
import pytest
from browser import chromium
from PIL import Image
from scipy import ndimage

from player.backends import open_renderer
from toon import FaceRig, Geometry, builtin_faces, load_expressions, load_face, motor_index
from toon.svg import geometry_svg

SIZE = 400
RANDOM_POSES = 12
MAGENTA, GREEN = (1.0, 0.0, 1.0, 1.0), (0.0, 0.8, 0.0, 1.0)


@pytest.fixture(scope="module")
def page():
    with chromium(SIZE, SIZE + 200) as driver:
        driver.get("about:blank")
        driver.execute_script("document.body.style.margin = '0'")
        yield driver


def _drawn(page, geometry: Geometry) -> np.ndarray:
    """Chromium's pixels ``(SIZE, SIZE, 3)`` of the geometry's SVG."""
    page.execute_script("document.body.innerHTML = arguments[0]", geometry_svg(geometry, (SIZE, SIZE)))
    return np.asarray(Image.open(io.BytesIO(page.get_screenshot_as_png())).convert("RGB"))[:SIZE, :SIZE].astype(int)


@pytest.mark.slow
def test_the_round_faces_white_stays_inside_its_lower_lid_in_the_browser(page):
    """The white painted magenta and the lower lids green: in every column of an eye the lowest
    white pixel is at most a pixel below the lid's lowest (the old open-spline lid left a sliver
    of white below it at a wide-eyed pose, and the iris crossed it)."""
    face = load_face("round")
    rig = FaceRig(face)
    wide = face.neutral().copy()
    wide[[motor_index(c) for c in ("ERU", "ELU", "ERL", "ELL")]] = (1.0, 1.0, 0.0, 0.0)
    poses = {"wide": wide, **{name: e.pose(face.neutral()) for name, e in load_expressions().items()}}
    for name, pose in poses.items():
        geometry = rig.geometry(pose)
        items = tuple(replace(it, fill=MAGENTA if it.fill is not None else None, stroke=None) if it.name == "white"
                      else replace(it, fill=None, stroke=GREEN) if it.name == "lower_lid" else None
                      for it in geometry.items)
        shown = replace(geometry, items=tuple(it for it in items if it is not None), background=(1.0, 1.0, 1.0, 1.0))
        image = _drawn(page, shown)
        white = (image[..., 0] > 200) & (image[..., 1] < 60) & (image[..., 2] > 200)
        lid = (image[..., 1] > 150) & (image[..., 0] < 80) & (image[..., 2] < 80)
        assert white.sum() > 100 or name != "wide", name  # the eyes are open: there is white to see
        rows = np.arange(SIZE)[:, None]
        for x in np.flatnonzero(white.any(axis=0) & lid.any(axis=0)):
            lowest_white = rows[white[:, x], 0].max()
            lowest_lid = rows[lid[:, x], 0].max()
            assert lowest_white <= lowest_lid + 1, (name, int(x), int(lowest_white), int(lowest_lid))


@pytest.mark.slow
@pytest.mark.parametrize("name", builtin_faces())
def test_no_pose_opens_a_hole_through_the_face_in_the_browser(page, name):
    """Every expression and seeded random poses of every column (motors and the face's own
    parameters): no pixel Chromium shows as the background lies inside what the CPU renderer
    paints as the face (two pixels in from its edges)."""
    face = load_face(name)
    rig = FaceRig(face)
    rng = np.random.default_rng(70)
    poses = [(e.pose(face.neutral()), {}) for e in load_expressions().values()]
    poses += [(rng.uniform(0.0, 1.0, 21), {c: float(rng.uniform(0.0, 1.0)) for c in face.extra_codes})
              for _ in range(RANDOM_POSES)]
    with open_renderer((SIZE, SIZE), 4, "cairo") as cpu:
        for number, (values, extra) in enumerate(poses):
            geometry = rig.geometry(values, extra)
            image, oracle = _drawn(page, geometry), cpu.render(geometry)[..., :3].astype(int)
            background = np.round(np.asarray(geometry.background[:3]) * 255).astype(int)
            assert np.abs(image[2, 2] - background).sum() <= 3  # the corner is the background
            solid = np.abs(oracle - background).sum(axis=2) > 200  # painted, not an antialiased edge or gap
            face_inside = ndimage.binary_erosion(solid, iterations=2)
            holes = face_inside & (np.abs(image - background).sum(axis=2) < 12)
            if any(item.fill is not None for item in geometry.items):  # the lines face is lines alone
                assert face_inside.sum() > 1000  # something to look through
            assert not holes.any(), (name, number, np.argwhere(holes)[:5].tolist())
