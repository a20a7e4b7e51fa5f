"""``batch``: a job of takes x faces on local Dask clusters of one and two worker processes.

``batch.fps_1w`` / ``batch.fps_2w``: video frames a second of wall time for the whole job
(every output: motor track, video, score plot, contact sheet; 512x512, 4x MSAA), each cluster
already started and warmed by one run; the runs alternate between the two clusters.
``batch.speedup_2w``: the median of the repeats' ratios (goal 1.8, issue 65). ``batch.split_speedup_2w``:
one long take's video on two workers, rendered in parts of 5 s against in one piece.
``batch.frame_cost_ms``: worker compute time per video frame on one worker, all outputs, with
each task kind's share in the detail; the batch tutorial's plan for 100 machines uses it.
"""

from __future__ import annotations

import statistics
import tempfile
import time
from contextlib import ExitStack
from pathlib import Path

from dask.utils import key_split
from distributed import get_task_stream

from bench.core import Figure
from capture import save_take, synthesize
from toonface.batch import connect, load_job, plan, run_batch
from toonface.batch.runner import compute_seconds

GOAL_SPEEDUP = 1.8  # issue 65


def run(quick: bool = False) -> list[Figure]:
    """Time the job on both clusters, then the split long take on the two-worker one."""
    takes, seconds, repeats, long_seconds = (2, 2.0, 1, 10.0) if quick else (6, 4.0, 3, 40.0)
    with tempfile.TemporaryDirectory(prefix="toonface-bench-batch-") as folder, ExitStack() as stack:
        root = Path(folder)
        job = _job(root / "many", {f"take{i}": seconds for i in range(takes)}, ["classic", "round"])
        clusters = {n: stack.enter_context(connect(None, workers=n)) for n in (1, 2)}
        for client in clusters.values():
            _timed(job, client)  # warm: imports and shader compiles in each worker
        runs: dict[int, list[float]] = {1: [], 2: []}
        stages: dict[str, float] = {}
        for _ in range(repeats):
            for workers, client in clusters.items():
                frames, wall, compute = _timed(job, client)
                runs[workers].append(frames / wall)
                if workers == 1:
                    for stage, secs in compute.items():
                        stages[stage] = stages.get(stage, 0.0) + secs / frames / repeats
        ratios = [b / a for a, b in zip(runs[1], runs[2], strict=True)]
        split, whole = _split_runs(root / "long", long_seconds, clusters[2], repeats)
    detail = {"takes": takes, "faces": 2, "seconds_per_take": seconds, "size": 512, "samples": 4,
              "repeats": repeats}
    split_ratios = [w / s for s, w in zip(split, whole, strict=True)]
    cost = {stage: round(secs * 1000, 3) for stage, secs in sorted(stages.items())}
    return [
        Figure("batch.fps_1w", statistics.median(runs[1]), "frames/s", None, True, {**detail, "runs": runs[1]}),
        Figure("batch.fps_2w", statistics.median(runs[2]), "frames/s", None, True, {**detail, "runs": runs[2]}),
        Figure("batch.speedup_2w", statistics.median(ratios), "x", GOAL_SPEEDUP, True, {**detail, "ratios": ratios}),
        Figure("batch.split_speedup_2w", statistics.median(split_ratios), "x", GOAL_SPEEDUP, True,
               {"take_seconds": long_seconds, "part_seconds": 5.0, "split_s": split, "whole_s": whole}),
        Figure("batch.frame_cost_ms", sum(cost.values()), "ms/frame", None, False, {"by_task": cost, **detail}),
    ]


def _job(folder: Path, takes: dict[str, float], faces: list[str], extra: str = "") -> Path:
    """Synthetic takes (30 Hz, seeded) and a job file writing every output of each pair."""
    (folder / "takes").mkdir(parents=True, exist_ok=True)
    for seed, (name, seconds) in enumerate(takes.items()):
        save_take(synthesize(seconds=seconds, rate=30.0, seed=seed).take, folder / "takes" / f"{name}.npz")
    path = folder / "job.toml"
    face_list = ", ".join(f'"{f}"' for f in faces)
    path.write_text(f'format = "toonface.batch/1"\ntakes = ["takes/*.npz"]\nfaces = [{face_list}]\n'
                    f'output = "out"\n{extra}')
    return path


def _timed(path: Path, client) -> tuple[int, float, dict[str, float]]:
    """Run the whole job again; returns video frames, wall seconds and compute seconds per task kind."""
    job = load_job(path)
    start = time.perf_counter()
    with get_task_stream(client) as stream:
        report = run_batch(job, plan(job, force=True), client)
    wall = time.perf_counter() - start
    if not report.ok:
        raise RuntimeError(f"the benchmark job failed: {report.failures()}")
    compute: dict[str, float] = {}
    for key, seconds in compute_seconds(stream.data).items():
        compute[key_split(key)] = compute.get(key_split(key), 0.0) + seconds
    return sum(r.frames for r in report.results), wall, compute


def _split_runs(folder: Path, seconds: float, client, repeats: int) -> tuple[list[float], list[float]]:
    """Wall seconds of one long take's video in parts of 5 s and in one piece, alternating."""
    only_video = "[write]\nmotors = false\nscore = false\nsheet = false\n"
    split = _job(folder / "split", {"long": seconds}, ["classic"], only_video + "[render]\npart_seconds = 5.0\n")
    whole = _job(folder / "whole", {"long": seconds}, ["classic"], only_video + "[render]\npart_seconds = 3600.0\n")
    times: tuple[list[float], list[float]] = ([], [])
    for _ in range(repeats):
        for path, into in ((split, times[0]), (whole, times[1])):
            into.append(_timed(path, client)[1])
    return times
