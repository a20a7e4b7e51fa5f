"""Batch jobs for the tests: synthetic takes and a job file naming them, and a job run on a
cluster with its manifest written."""

from __future__ import annotations

import textwrap
from pathlib import Path

from capture import save_take, synthesize
from toonface.batch import load_job, plan, run_batch, write_manifest

SIZE = 64


def write_job(root: Path, takes: dict[str, float], faces: list[str], extra: str = "") -> Path:
    """Synthetic takes (name -> seconds, 30 Hz, seeded) under root/takes and a job file naming them."""
    (root / "takes").mkdir(exist_ok=True)
    for seed, (name, seconds) in enumerate(takes.items()):
        save_take(synthesize(seconds=seconds, rate=30.0, seed=seed).take, root / "takes" / f"{name}.npz")
    face_list = ", ".join(f'"{f}"' for f in faces)
    text = f"""\
        format = "toonface.batch/1"
        takes = ["takes/*.npz", "takes/*.c3d"]
        faces = [{face_list}]
        output = "out"
        [render]
        size = "{SIZE}"
        samples = 0
        part_seconds = 0.5
        """
    path = root / "job.toml"
    path.write_text(textwrap.dedent(text) + textwrap.dedent(extra))
    return path


def run(path: Path, client, force: bool = False, progress=None):
    job = load_job(path)
    report = run_batch(job, plan(job, force), client, progress)
    write_manifest(report, job.output / "manifest.json")
    return report
