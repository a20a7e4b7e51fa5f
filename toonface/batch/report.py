"""What a batch run did: per-pair results, the summary table, and the JSON manifest."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from common import atomic_path
from toonface.batch.job import Job
from toonface.batch.pairs import Pair

MANIFEST_FORMAT = "toonface.batch-manifest/1"
STATUSES = ("done", "skipped", "failed", "cancelled")


@dataclass
class PairResult:
    """How one pair ended: ``status`` is one of :data:`STATUSES`; ``written`` maps output kinds
    made this run to their bytes; ``seconds`` is the compute time of its tasks on the workers;
    ``report`` is its mapped take's report (:mod:`mapping.report`; empty for a pair not mapped
    this run)."""

    pair: Pair
    status: str
    reason: str = ""
    frames: int = 0
    seconds: float = 0.0
    written: dict[str, int] = field(default_factory=dict)
    report: dict[str, Any] = field(default_factory=dict)


@dataclass
class BatchReport:
    """A whole run: its results in plan order, wall time, and the cluster it ran on."""

    job: Job
    results: list[PairResult]
    seconds: float
    workers: int
    scheduler: str

    def count(self, status: str) -> int:
        """Pairs that ended with ``status``."""
        return sum(r.status == status for r in self.results)

    @property
    def ok(self) -> bool:
        """True when no pair failed or was cancelled."""
        return all(r.status in ("done", "skipped") for r in self.results)

    def table(self) -> list[str]:
        """The summary: pairs, video frames and worker compute time per status, then the total."""
        lines = [f"{'':<10}{'pairs':>7}{'frames':>10}{'compute':>11}"]
        for status in STATUSES:
            rows = [r for r in self.results if r.status == status]
            if rows or status != "cancelled":
                frames = sum(r.frames for r in rows)
                compute = sum(r.seconds for r in rows)
                lines.append(f"{status:<10}{len(rows):>7}{frames:>10}{compute:>9.1f} s")
        made = sum(r.frames for r in self.results if r.status == "done")
        rate = f", {made / self.seconds:.1f} frames/s" if made and self.seconds > 0 else ""
        lines.append(f"{'total':<10}{len(self.results):>7}{sum(r.frames for r in self.results):>10}"
                     f"{self.seconds:>9.1f} s wall on {self.workers} worker thread{'s' * (self.workers != 1)}{rate}")
        return lines

    def warned(self) -> list[str]:
        """One line per pair whose take's report holds a warning: its name, how many, the first."""
        lines = []
        for result in self.results:
            warnings = result.report.get("warnings", [])
            if warnings:
                more = f" (and {len(warnings) - 1} more)" if len(warnings) > 1 else ""
                lines.append(f"{result.pair.name}: {warnings[0]}{more}")
        return lines

    def failures(self) -> list[str]:
        """One line per pair that did not finish: its name and why."""
        return [f"{r.pair.name}: {r.reason}" for r in self.results if r.status in ("failed", "cancelled")]


def write_manifest(report: BatchReport, path: str | os.PathLike) -> Path:
    """Write the JSON manifest: every pair, its input hashes, status and outputs (atomically)."""
    pairs = []
    for result in report.results:
        recorded = result.pair.recorded.get("outputs", {})
        outputs = []
        for output in result.pair.outputs:
            if output.kind in result.written:
                size = result.written[output.kind]
            elif output.kind not in result.pair.stale:  # up to date when planned
                size = recorded[output.kind]["bytes"]
            else:
                size = None
            outputs.append({"kind": output.kind, "path": str(output.path), "key": output.key, "bytes": size,
                            "written": output.kind in result.written, "up_to_date": size is not None})
        pairs.append({"name": result.pair.name, "take": str(result.pair.take), "face": result.pair.face,
                      "status": result.status, "reason": result.reason, "frames": result.frames,
                      "compute_seconds": round(result.seconds, 3), "inputs": result.pair.inputs, "outputs": outputs,
                      "report": result.report})
    doc = {"format": MANIFEST_FORMAT, "job": str(report.job.path), "scheduler": report.scheduler,
           "workers": report.workers, "wall_seconds": round(report.seconds, 3),
           "totals": {status: report.count(status) for status in STATUSES}, "pairs": pairs}
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(doc, indent=1) + "\n", encoding="utf-8")
    return path
