"""Shared benchmark helpers: the figure record, median timing and running on one core."""

from __future__ import annotations

import json
import os
import statistics
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path

#: The real files recorded by others (``../shared/realdata`` beside the project's root).
REALDATA = Path(__file__).resolve().parents[1].parent / "shared" / "realdata"


@dataclass(frozen=True)
class Figure:
    """One benchmark figure, printed as one JSON line."""

    name: str
    value: float
    unit: str
    goal: float | None
    higher_is_better: bool
    detail: dict = field(default_factory=dict)

    @property
    def met(self) -> bool | None:
        """Whether the goal is reached (None without a goal)."""
        if self.goal is None:
            return None
        return self.value >= self.goal if self.higher_is_better else self.value <= self.goal

    def to_json(self) -> str:
        """The figure as a JSON line (with ``met`` added to ``detail``)."""
        record = asdict(self)
        record["value"] = round(self.value, 4)
        record["detail"] = {**self.detail, "goal_met": self.met}
        return json.dumps(record)


@contextmanager
def one_core() -> Iterator[bool]:
    """Run the body on one CPU (the lowest this thread may use) with one BLAS thread, as the speed
    goals are set, and give both back after; yields whether it could pin (not every platform
    does). Pinning moves only this thread: the BLAS libraries' own threads stayed where they
    were, so a figure on "one core" used a second one, until a fork in the process (any child
    the bench starts) made the libraries start them again on the pinned CPU, where two spun on
    one core: gap filling then read 68 frames/s where it does 350 (the same on one BLAS thread)."""
    from threadpoolctl import threadpool_limits

    cpus = os.sched_getaffinity(0) if hasattr(os, "sched_setaffinity") else None
    with threadpool_limits(limits=1, user_api="blas"):
        if cpus is None:
            yield False
            return
        os.sched_setaffinity(0, {min(cpus)})
        try:
            yield True
        finally:
            os.sched_setaffinity(0, cpus)


def median_rate(run: Callable[[], int], repeats: int, warmup: int = 1) -> tuple[float, list[float]]:
    """Median items per second of ``run`` (which returns how many items it processed).

    Returns the median and every repeat's rate.
    """
    for _ in range(warmup):
        run()
    rates = []
    for _ in range(repeats):
        start = time.perf_counter()
        items = run()
        rates.append(items / (time.perf_counter() - start))
    return statistics.median(rates), rates
