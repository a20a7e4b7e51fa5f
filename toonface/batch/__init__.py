"""Batch retargeting on Dask: a job file's takes x faces, resumable, failures isolated.

:func:`load_job` reads the job, :func:`plan` finds what is out of date, :func:`run_batch` makes it
on a cluster (:func:`connect` starts a local one or joins a scheduler), and
:func:`write_manifest` records the outcome.
"""

import lazy_loader

__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
