"""Make the "A rig from another lab" pictures (docs/howto/own-layout.md): the third synthetic performer (seed 4)
on bench/foreign_rig.py's layout, taken through the chapter's commands.

Run from the project's root: ``.venv/bin/python scripts/own-layout-pictures.py``; it writes
docs/images/own-layout-raw.png and docs/images/own-layout-check.png.
"""

import shutil
import tempfile
from pathlib import Path

from bench import third_performer
from bench.foreign_rig import foreign_take
from toonface.cli import main

ROOT = Path(__file__).resolve().parents[1]


def run() -> None:
    rig = foreign_take(third_performer.perform(seconds=20.0, rate=120.0, seed=4, faults=False).take, 4)
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        rig.write_csv(work / "lab.csv")
        reading = ["--rate", "120", "--units", "m"]
        steps = [["info", str(work / "lab.csv"), *reading, "--plot", str(work / "raw.png"), "--plot-motion"],
                 ["markerset", "draft", str(work / "lab.csv"), *reading, "-o", str(work / "lab.toml")],
                 ["markerset", "mapping", str(work / "lab.toml"), "-o", str(work / "lab-mapping.toml")],
                 ["info", str(work / "lab.csv"), "--mapping", str(work / "lab-mapping.toml"), "--plot",
                  str(work / "check.png"), "--plot-motion"]]
        for step in steps:
            if main(step) != 0:
                raise SystemExit(f"failed: toonface {' '.join(step)}")
        for name, target in (("raw.png", "own-layout-raw.png"), ("check.png", "own-layout-check.png")):
            shutil.copyfile(work / name, ROOT / "docs" / "images" / target)


if __name__ == "__main__":
    run()
