"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .job import Job, load_job
from .pairs import Pair, plan
from .report import BatchReport, PairResult, write_manifest
from .runner import connect, default_workers, run_batch

__all__ = [
    "BatchReport",
    "Job",
    "Pair",
    "PairResult",
    "connect",
    "default_workers",
    "load_job",
    "plan",
    "run_batch",
    "write_manifest",
]
