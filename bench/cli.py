"""``cli``: how long ``toonface --help`` and every ``toonface SUB --help`` take to start.

Each command runs in a fresh interpreter (``python -m toonface``), as a user's shell runs it;
a bare ``python -c pass`` is timed in the same run and taken off, so the figure is what
toonface itself adds. Goal: every command within 300 ms of the bare interpreter.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

from bench.core import Figure

GOAL_MS = 300.0


def _median_ms(argv: list[str], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append((time.perf_counter() - start) * 1000)
    return statistics.median(times)


def run(quick: bool = False) -> list[Figure]:
    """Measure and return ``cli.startup_ms``: the slowest command's median less the bare interpreter's."""
    from toonface.cli import cli

    repeats = 3 if quick else 10
    names = ["map", "batch"] if quick else sorted(cli.commands)
    bare = _median_ms([sys.executable, "-c", "pass"], repeats)
    commands = {"--help": [], **{f"{name} --help": [name] for name in names}}
    medians = {label: _median_ms([sys.executable, "-m", "toonface", *args, "--help"], repeats)
               for label, args in commands.items()}
    slowest = max(medians, key=lambda label: medians[label])
    return [Figure("cli.startup_ms", medians[slowest] - bare, "ms", GOAL_MS, False,
                   {"bare_python_ms": round(bare, 1), "slowest": slowest, "repeats": repeats,
                    "medians_ms": {label: round(ms, 1) for label, ms in medians.items()}})]
