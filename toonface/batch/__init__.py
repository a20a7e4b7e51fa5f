"""Batch retargeting on Dask: a job file's takes x faces, resumable, failures isolated.

:func:`load_job` reads the job, :func:`plan` finds what is out of date, :func:`run_batch` makes it
on a cluster (:func:`connect` starts a local one or joins a scheduler), and
:func:`write_manifest` records the outcome.
"""

from toonface.batch.job import Job, load_job
from toonface.batch.pairs import Pair, plan
from toonface.batch.report import BatchReport, PairResult, write_manifest
from toonface.batch.runner import connect, default_workers, run_batch

__all__ = ["BatchReport", "Job", "Pair", "PairResult", "connect", "default_workers", "load_job", "plan",
           "run_batch", "write_manifest"]
