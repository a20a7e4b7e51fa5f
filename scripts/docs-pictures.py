"""Make every picture of the documentation site, from the project's own commands (``make pictures``).

Writes into ``docs/images/``:

- ``faces.png``: each built-in face (a row) in five expressions;
- ``face-NAME.png``: each face's own contact sheet, as ``toonface face NAME --sheet`` draws it;
- ``staves.png``: the shared jaw take's motors as staves (``toonface map``, then ``score``);
- ``batch-sheet.png``: the contact sheet ``toonface batch`` makes of that take on the cat;
- ``before-after.png``: three frames of a GRID clip beside the cartoon ``toonface retarget
  --side-by-side`` makes of it (the README's and the home page's picture);
- ``studio.png``: the studio with the jaw take open, in headless Chromium at 1366x768;
- ``own-layout-raw.png``, ``own-layout-check.png``: ``scripts/own-layout-pictures.py``.

The shared recordings are read from ``../shared/realdata/`` beside the checkout; the studio's
picture needs Chromium and chromedriver (``make test`` installs them). Each step says what it
wrote; a step that cannot run (a file or the browser missing) stops the script with the reason.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import av
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
IMAGES = ROOT / "docs" / "images"
REALDATA = ROOT.parent / "shared" / "realdata"
TAKE = REALDATA / "facial" / "animface" / "JawMoCap.csv"
CLIP = REALDATA / "video" / "grid" / "bbaf2n.mpg"
EXPRESSIONS = ("neutral", "happiness", "surprise", "anger", "blink")


def toonface(*argv: str, cwd: Path) -> None:
    """Run one ``toonface`` command as a user would; stop the script if it fails."""
    done = subprocess.run([sys.executable, "-m", "toonface", *argv], cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"toonface {' '.join(argv)} failed: {done.stderr.strip()}")


def save_png(picture: np.ndarray, path: Path) -> None:
    """An RGB picture ``(height, width, 3)`` as a PNG, compressed hardest."""
    import cv2

    cv2.imwrite(str(path), cv2.cvtColor(picture, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_PNG_COMPRESSION, 9])
    print(f"wrote {path.relative_to(ROOT)}")


def faces_overview(work: Path) -> None:
    """``faces.png``: a row per built-in face, five expressions each; and each face's own sheet."""
    from player.sheet import labelled_grid
    from toon import FaceRig, builtin_faces, load_expressions, load_face

    repertoire = load_expressions("expressions")
    rows = []
    for name in builtin_faces():
        face = load_face(name)
        neutral, declared = face.neutral(), face.extra_neutral()
        poses = [(name if e == "neutral" else e, repertoire[e].pose(neutral), repertoire[e].extra_pose(declared))
                 for e in EXPRESSIONS]
        rows.append(labelled_grid(FaceRig(face), poses, (176, 176), len(poses), 4))
        toonface("face", name, "--sheet", str(IMAGES / f"face-{name}.png"), "--size", "160", cwd=work)
        print(f"wrote docs/images/face-{name}.png")
    save_png(np.concatenate(rows), IMAGES / "faces.png")


def staves(work: Path) -> None:
    """``staves.png``: the jaw take mapped, then scored."""
    shutil.copy(TAKE, work)
    toonface("map", TAKE.name, "--units", "cm", "-o", "jaw.csv", cwd=work)
    toonface("score", "jaw.csv", "-o", str(IMAGES / "staves.png"), "--width", "1000", cwd=work)
    print("wrote docs/images/staves.png")


def batch_sheet(work: Path) -> None:
    """``batch-sheet.png``: the contact sheet a batch job makes of the jaw take on the cat."""
    (work / "takes").mkdir()
    shutil.copy(TAKE, work / "takes")
    (work / "sheet.toml").write_text('format = "toonface.batch/1"\ntakes = ["takes/*.csv"]\nfaces = ["cat"]\n'
                                     'output = "out"\n[write]\nvideo = false\nmotors = false\nscore = false\n'
                                     '[render]\nsize = "192"\n[csv]\nunits = "cm"\n')
    toonface("batch", "sheet.toml", "--workers", "1", cwd=work)
    shutil.copyfile(work / "out" / "JawMoCap" / "cat.sheet.png", IMAGES / "batch-sheet.png")
    print("wrote docs/images/batch-sheet.png")


def before_after(work: Path) -> None:
    """``before-after.png``: frames at 0.6, 1.5 and 2.3 s of the side-by-side retarget, stacked."""
    toonface("retarget", str(CLIP), "-o", "both.mp4", "--face", "round", "--side-by-side", "--size", "288", cwd=work)
    wanted, frames = [0.6, 1.5, 2.3], []
    with av.open(str(work / "both.mp4")) as movie:
        for frame in movie.decode(video=0):
            if wanted and frame.time is not None and frame.time >= wanted[0]:
                frames.append(frame.to_ndarray(format="rgb24"))
                wanted.pop(0)
    gap = np.full((frames[0].shape[0], 8, 3), 255, np.uint8)
    save_png(np.concatenate([frames[0], gap, frames[1], gap, frames[2]], axis=1), IMAGES / "before-after.png")


def studio(work: Path) -> None:
    """``studio.png``: ``toonface studio jaw.csv`` in headless Chromium, the jaw open at 6.5 s."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    browser, driver_path = shutil.which("chromium") or shutil.which("chromium-browser"), shutil.which("chromedriver")
    if browser is None or driver_path is None:
        raise SystemExit("studio.png needs Chromium and chromedriver (make test installs them)")
    server = subprocess.Popen([sys.executable, "-m", "toonface", "studio", "jaw.csv", "--face", "classic", "--listen",
                               "127.0.0.1:0"], cwd=work, stdout=subprocess.PIPE, text=True)
    try:
        assert server.stdout is not None
        address = server.stdout.readline().split()[2]  # "studio at http://127.0.0.1:PORT/ (Ctrl-C stops)"
        options = webdriver.ChromeOptions()
        options.binary_location = browser
        for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--window-size=1366,768",
                     "--force-device-scale-factor=1"):
            options.add_argument(flag)
        driver = webdriver.Chrome(options=options, service=Service(executable_path=driver_path))
        try:
            driver.get(address)
            deadline = time.monotonic() + 60
            while not driver.execute_script("return !!(window.studio && window.studio.last && window.studio.last.svg"
                                            " && window.editor && window.editor.state && window.editor.state.knots)"):
                if time.monotonic() > deadline:
                    raise SystemExit("the studio page did not show the take within a minute")
                time.sleep(0.2)
            driver.execute_script("window.studio.send({op: 'cursor', t: 6.5})")
            time.sleep(1.0)  # the face redraws at the new cursor (a script, not a test: waiting is fine)
            driver.save_screenshot(str(IMAGES / "studio.png"))
            print("wrote docs/images/studio.png")
        finally:
            driver.quit()
    finally:
        server.terminate()
        server.wait(10)


def main() -> None:
    for needed in (TAKE, CLIP):
        if not needed.is_file():
            raise SystemExit(f"{needed} is absent: the pictures are made from the shared recordings")
    IMAGES.mkdir(parents=True, exist_ok=True)
    os.environ.setdefault("TOONFACE_RENDERER", "auto")
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        faces_overview(work)
        staves(work)
        batch_sheet(work)
        before_after(work)
        studio(work)
    done = subprocess.run([sys.executable, str(ROOT / "scripts" / "own-layout-pictures.py")], cwd=ROOT,
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"scripts/own-layout-pictures.py failed: {done.stderr.strip()[-500:]}")
    print("wrote docs/images/own-layout-raw.png, docs/images/own-layout-check.png")


if __name__ == "__main__":
    main()
