"""The golden test of the web rig (issue 63): a page that draws a face itself, from motor values,
through ``rig.js`` and ``physics.js`` and the face's web rig (:mod:`toon.web_rig`), draws what
the Python renderer draws. For every built-in face and a face with imported artwork (an SVG
drawing and a PNG picture, both attached to the mouth), 200 seeded random poses over every column
(the 21 motors, HT and the face's own parameters) and a physics swing: the page's SVG has the
Python SVG's lines (same elements, coordinates within their last decimal), and the two, both
drawn by Chromium, differ by at most 1/255 on average; a few poses are held to the offscreen
renderer's raster as the studio's page is."""

from __future__ import annotations

import base64
import io
import json
from importlib import resources

import numpy as np
import pytest
from browser import chromium
from pictures import png_bytes
from PIL import Image

from player.backends import open_renderer
from player.motion import SecondaryMotion
from toon import FaceRig, load_face
from toon.face import face_from_dict
from toon.svg import geometry_svg
from toon.web_rig import web_rig
from toonface.studio import component_edits as parts

SIZE = (256, 256)
POSES = 200
DRAWING = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">
  <path id="lip" d="M60 140 Q100 170 140 140 Q100 155 60 140 Z" fill="#b0303a" stroke="#000" stroke-width="2"/>
  <polyline id="lash" points="10,10 20,5 30,10" fill="none" stroke="rgba(0,0,0,0.5)" stroke-width="4"/>
  <circle id="blush" cx="50" cy="100" r="10" fill="#ff0000" opacity="0.5"/>
</svg>"""

#: The page's side: draw both SVGs of each pose into canvases, compare the text and the pixels.
COMPARE = """
const [rows, svgs, size, done] = [arguments[0], arguments[1], arguments[2], arguments[arguments.length - 1]];
const number = /-?\\d+(\\.\\d+)?/g;
function pixels(svg) {
  return new Promise((resolve, reject) => {
    const image = new Image(), url = URL.createObjectURL(new Blob([svg], {type: "image/svg+xml"}));
    image.onload = () => {
      const canvas = document.createElement("canvas");
      canvas.width = size[0]; canvas.height = size[1];
      const g = canvas.getContext("2d");
      g.drawImage(image, 0, 0);
      URL.revokeObjectURL(url);
      resolve([g.getImageData(0, 0, size[0], size[1]).data, canvas]);
    };
    image.onerror = () => reject(new Error("an SVG did not draw"));
    image.src = url;
  });
}
(async () => {
  const out = {mad: [], lines: 0, shape: 0, worst: 0, page: []};
  for (let k = 0; k < rows.length; k++) {
    const mine = window.rig.svg(window.motion ? window.motion.frame(rows[k][0], rows[k][1]) : rows[k], size);
    const a = mine.split("\\n"), b = svgs[k].split("\\n");
    if (a.length !== b.length) out.lines++;
    else a.forEach((line, i) => {
      if (line === b[i]) return;
      const x = line.match(number) || [], y = b[i].match(number) || [];
      if (line.replace(number, "#") !== b[i].replace(number, "#") || x.length !== y.length) { out.shape++; return; }
      x.forEach((v, j) => { out.worst = Math.max(out.worst, Math.abs(Number(v) - Number(y[j]))); });
    });
    const [[p, canvas], [q]] = await Promise.all([pixels(mine), pixels(svgs[k])]);
    out.page.push(k < 3 ? canvas.toDataURL("image/png") : "");
    let sum = 0;
    for (let i = 0; i < p.length; i++) if (i % 4 !== 3) sum += Math.abs(p[i] - q[i]);
    out.mad.push(sum / (p.length / 4 * 3));
  }
  done(out);
})().catch((e) => done({error: String(e)}));
"""


def artwork_face():
    """The classic face with an imported drawing and picture attached to the mouth."""
    doc = load_face("classic").to_dict()
    made = parts.import_svg(doc, DRAWING)
    parts.attach(doc, made[0], "mouth")
    quad = np.zeros((32, 32, 4), np.uint8)
    quad[:16, :, 0] = quad[16:, :, 2] = 255
    quad[..., 3] = 255
    quad[:8, :8, 3] = 128
    picture = parts.import_picture(doc, png_bytes(quad), "patch.png")
    spec = doc["components"][picture]
    spec["points"] = [[-60, -150], [60, -150], [-60, -220]]
    parts.attach(doc, picture, "mouth")
    return face_from_dict(doc)


FACES = {"classic": lambda: load_face("classic"), "round": lambda: load_face("round"),
         "lines": lambda: load_face("lines"), "cat": lambda: load_face("cat"), "wizard": lambda: load_face("wizard"),
         "artwork": artwork_face}


def _page(driver, rig: FaceRig, physics: bool = False) -> None:
    driver.get("about:blank")
    static = resources.files("toonface.studio").joinpath("static")
    for name in ("rig.js", "physics.js"):
        driver.execute_script("const s = document.createElement('script'); s.text = arguments[0];"
                              "document.head.append(s)", static.joinpath(name).read_text(encoding="utf-8"))
    driver.execute_script("const data = JSON.parse(arguments[0]); window.rig = new toonRig.Rig(data);"
                          "window.motion = arguments[1] ? new toonPhysics.Motion(data.physics) : null",
                          json.dumps(web_rig(rig)), physics)


def _compare(driver, rows: list, svgs: list[str]) -> dict:
    driver.set_script_timeout(120)
    found: dict = {"mad": [], "lines": 0, "shape": 0, "worst": 0.0, "page": []}
    for start in range(0, len(rows), 25):  # a few megabytes a call at most
        out = driver.execute_async_script(COMPARE, rows[start:start + 25], svgs[start:start + 25], list(SIZE))
        assert "error" not in out, out.get("error")
        found["mad"] += out["mad"]
        found["page"] += out["page"]
        found["lines"] += out["lines"]
        found["shape"] += out["shape"]
        found["worst"] = max(found["worst"], out["worst"])
    return found


@pytest.mark.slow
@pytest.mark.parametrize("name", list(FACES))
def test_the_page_draws_every_pose_as_the_python_renderer_does(name):
    face = FACES[name]()
    rig = FaceRig(face)
    rng = np.random.default_rng(63)
    rows = rng.uniform(0.0, 1.0, (POSES, len(rig.codes)))
    assert "HT" in rig.codes and len(rig.codes) > 22  # the tilt and the face's own parameters are in every pose
    geometries = [rig.geometry(row[:21], dict(zip(rig.codes[21:], row[21:], strict=True))) for row in rows]
    svgs = [geometry_svg(g, SIZE) for g in geometries]
    with chromium() as driver:
        _page(driver, rig)
        found = _compare(driver, rows.tolist(), svgs)
    assert found["lines"] == 0 and found["shape"] == 0  # the same elements, line for line
    assert found["worst"] <= 0.0011  # coordinates within their last decimal (rounding)
    assert len(found["mad"]) == POSES and max(found["mad"]) <= 1.0  # mean absolute difference, of 255
    with open_renderer(SIZE) as renderer:  # and the Python raster, at the studio page's tolerance
        for k in range(3):
            drawn = renderer.render(geometries[k]).astype(int)
            png = _png(found["page"][k])
            assert np.abs(png - drawn).mean() < 1.5


def _png(url: str) -> np.ndarray:
    """A canvas's ``data:image/png`` address as RGB ``(H, W, 3)``."""
    data = base64.b64decode(url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(int)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["classic", "cat"])
def test_the_page_swings_what_the_physics_moves_as_the_python_does(name):
    """Live frames at 60 a second, the head turning and the jaw working, a pause of half a second,
    then on: the page's physics gives the parameters the Python's does (to 1e-9) and the same
    pictures."""
    face = FACES[name]()
    rig = FaceRig(face)
    motion = SecondaryMotion(face)
    neutral = np.concatenate([face.neutral(), [face.extra_neutral()[c] for c in face.extra_codes]])
    frames, svgs, drawn = [], [], []
    times = [k / 60 for k in range(60)] + [1.5 + k / 60 for k in range(30)]
    for t in times:
        row = neutral.copy()
        row[rig.codes.index("HH")] = 0.5 + 0.45 * np.sin(4 * t)
        row[rig.codes.index("MB")] = 0.4 + 0.3 * np.sin(9 * t)
        row[rig.codes.index("HT")] = 0.5 + 0.3 * np.sin(2 * t)
        extra = dict(zip(rig.codes[21:], row[21:], strict=True))
        moved = motion.extra_at(t, row[:21], extra)
        drawn.append(rig.full_values(row[:21], moved))
        svgs.append(geometry_svg(rig.geometry(row[:21], moved), SIZE))
        frames.append([t, row.tolist()])
    assert np.ptp(np.array(drawn)[:, 22:], axis=0).max() > 0.05  # something swings
    with chromium() as driver:
        _page(driver, rig, physics=True)
        found = _compare(driver, frames, svgs)
        driver.execute_script("window.motion = new toonPhysics.Motion(window.rig.data.physics)")
        values = driver.execute_script("return arguments[0].map(([t, row]) => window.motion.frame(t, row))", frames)
    np.testing.assert_allclose(np.array(values), np.array(drawn), atol=1e-9)
    assert found["lines"] == 0 and found["shape"] == 0 and found["worst"] <= 0.0011
    assert max(found["mad"]) <= 1.0
