"""Run a planned batch on a Dask cluster: one small task graph per (take, face) pair.

Per take: ``ready`` (load, clean, calibrate), once for all its faces. Per pair: ``map`` (the
ready take onto the face) feeds ``count`` (video frames), ``motors``, ``score`` and ``sheet``;
once the frame count is known, the video is rendered as ``part`` tasks of at most
``part_seconds`` each and joined by a ``join`` task. Follow-up tasks have a higher priority than
new pairs' maps, and at most four pairs per worker thread are in flight, so pairs finish in order
and the cluster holds few motor tracks at a time. A task that raises fails its own pair only (its
dependants fail with it); a worker that dies has its tasks re-run elsewhere by the scheduler.
"""

from __future__ import annotations

import contextlib
import logging
import math
import time
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import replace
from pathlib import Path
from uuid import uuid4

from distributed import Client, Future, KilledWorker, LocalCluster, as_completed, get_task_stream
from distributed.diagnostics.plugin import WorkerPlugin

from common import InputError, ToonfaceError
from common.cores import usable_cores
from common.memory import keep_freed_memory
from player.parts import frame_ranges
from toonface.batch import tasks
from toonface.batch.job import Job
from toonface.batch.pairs import Pair, write_stamp
from toonface.batch.report import BatchReport, PairResult

log = logging.getLogger("toonface")

PAIRS_PER_THREAD = 4
# Each worker process renders on one core: llvmpipe and x264 threads would only compete with the
# other workers' processes (set the same on the machines of a cluster).
WORKER_ENV = {"LP_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def default_workers() -> int:
    """One worker per core this process may use."""
    return usable_cores()


@contextlib.contextmanager
def connect(scheduler: str | None = None, workers: int | None = None, wait_seconds: float = 60.0
            ) -> Iterator[Client]:
    """A client of the Dask scheduler at ``scheduler``, or of a local cluster of ``workers`` processes
    (one thread each; default :func:`default_workers`), closed on exit. Its workers keep freed
    memory for reuse (:class:`KeepFreedMemory`).

    With a scheduler, ``workers`` is how many workers to wait for (up to ``wait_seconds``).
    """
    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"cannot reach the Dask scheduler ({exc})", scheduler) from None
        with client:
            client.register_plugin(KeepFreedMemory())
            if workers:
                try:
                    client.wait_for_workers(workers, timeout=wait_seconds)
                except TimeoutError:
                    have = len(client.scheduler_info()["workers"])
                    raise InputError(f"only {have} of {workers} workers joined in {wait_seconds:g} s",
                                     scheduler) from None
            yield client
        return
    count = workers or default_workers()
    # No dashboard; the scheduler's small HTTP server (health, metrics) on any free port, not 8787.
    with LocalCluster(n_workers=count, threads_per_worker=1, processes=True, dashboard_address=None,
                      scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, silence_logs=logging.CRITICAL,
                      env=WORKER_ENV) as cluster, Client(cluster) as client:
        client.register_plugin(KeepFreedMemory())
        yield client


def quiet_dask() -> None:
    """Silence Dask's and asyncio's loggers for the rest of the process: on Ctrl-C, cancelling the
    tasks in flight made the scheduler log 35 lines of its own tracebacks ("Exception while
    handling op register-client", "Task exception was never retrieved") before "aborted"."""
    names = [name for name in logging.root.manager.loggerDict if name.split(".")[0] in ("distributed", "asyncio")]
    for name in {"distributed", "asyncio", *names}:
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)


class KeepFreedMemory(WorkerPlugin):
    """Each worker's allocator keeps freed memory for the next take's arrays, as the ``toonface``
    command's does (:func:`common.memory.keep_freed_memory`)."""

    name = "toonface-keep-freed-memory"

    def setup(self, worker: object) -> None:
        keep_freed_memory()


def run_batch(job: Job, pairs: list[Pair], client: Client | None,
              progress: Callable[[int, int], None] | None = None,
              clock: Callable[[], float] = time.perf_counter) -> BatchReport:
    """Make every stale output of ``pairs`` on ``client``'s cluster; returns the report.

    ``client`` may be None when no pair has anything to make. ``progress(finished_tasks,
    submitted_tasks)`` is called after every task. On an interrupt the pairs not finished are
    reported as cancelled (and their tasks cancelled) before it propagates.
    """
    start = clock()
    run = _Run(job, client, progress, clock)
    if client is None:
        if any(p.stale and not p.error for p in pairs):
            raise ValueError("pairs to make, but no cluster to make them on")
        run.execute(pairs)
        return BatchReport(job, [run.results[p.name] for p in pairs], clock() - start, 0, "")
    stream = get_task_stream(client)
    try:
        with stream:
            try:
                run.execute(pairs)
            except KeyboardInterrupt:
                quiet_dask()  # cancelling mid-flight makes Dask log its own races: not the user's to read
                raise
            finally:
                run.cancel_unfinished()
    finally:
        run.add_compute_times(stream.data)  # the stream's records arrive when its block ends
    threads = sum(client.nthreads().values())
    return BatchReport(job, [run.results[p.name] for p in pairs], clock() - start, threads, client.scheduler.address)


class _PairWork:
    """The futures of one pair in flight, and what its finished tasks reported."""

    def __init__(self, pair: Pair) -> None:
        self.pair = pair
        self.track: Future | None = None
        self.keys: list[str] = []
        self.pending = 0
        self.frames = 0
        self.written: dict[str, int] = {}
        self.reason = ""
        self.report: dict = {}


class _Run:
    """The client-side loop: submits each pair's tasks and reacts as they finish."""

    def __init__(self, job: Job, client: Client | None, progress: Callable[[int, int], None] | None,
                 clock: Callable[[], float]) -> None:
        self.job, self.client, self.progress, self.clock = job, client, progress, clock
        self.map_job = replace(job, takes=(), empty_globs=(), passed_over=())  # what map tasks need, no paths
        self.capacity, self.capacity_time = 0, -float("inf")
        # Futures as they finish; without a cluster there is nothing to wait for (as_completed()
        # would look for a default client, and a rerun with nothing to make has none).
        self.queue = as_completed(loop=client.loop) if client is not None else None
        self.owner: dict[Future, tuple[_PairWork, str]] = {}
        self.active: dict[str, _PairWork] = {}
        self.results: dict[str, PairResult] = {}
        self.keys: dict[str, list[str]] = {}  # each started pair's task keys
        self.ready: dict[Path, Future] = {}  # each take's ready task, while pairs of it remain
        self.remaining: dict[Path, int] = {}  # pairs of each take not yet finished
        self.finished = self.submitted = 0

    def execute(self, pairs: list[Pair]) -> None:
        """Report the pairs with nothing to make; make the others, a bounded number at a time."""
        waiting: deque[Pair] = deque()
        for pair in pairs:
            if pair.error:
                self.results[pair.name] = PairResult(pair, "failed", pair.error)
            elif not pair.stale:
                self.results[pair.name] = PairResult(pair, "skipped", frames=pair.recorded.get("frames", 0),
                                                     report=_recorded_report(pair))
            else:
                waiting.append(pair)
                self.remaining[pair.take] = self.remaining.get(pair.take, 0) + 1
        self._start_more(waiting)
        requeued: dict[str, int] = {}
        for future in self.queue or ():
            if (self.queue is not None and future.status not in ("finished", "error", "cancelled")
                    and requeued.get(future.key, 0) < REQUEUES):
                # its worker died after it finished, taking the result: the scheduler runs it again
                requeued[future.key] = requeued.get(future.key, 0) + 1
                self.queue.add(future)
                continue
            work, stage = self.owner.pop(future)
            work.pending -= 1
            self._settle(work, stage, future)
            self.finished += 1
            if work.pending == 0:
                self._finish(work)
                self._start_more(waiting)
            if self.progress:
                self.progress(self.finished, self.submitted)

    @property
    def cluster(self) -> Client:
        """The client, when there is work to submit."""
        if self.client is None or self.queue is None:
            raise ValueError("pairs to make, but no cluster to make them on")
        return self.client

    def _start_more(self, waiting: deque) -> None:
        """Start waiting pairs up to four per worker thread (re-counted at most once a second, as
        workers join or leave)."""
        if not waiting:
            return
        if self.clock() - self.capacity_time >= 1.0:
            self.capacity = PAIRS_PER_THREAD * max(sum(self.cluster.nthreads().values()), 1)
            self.capacity_time = self.clock()
        while waiting and len(self.active) < self.capacity:
            self._start(waiting.popleft())

    def _submit(self, work: _PairWork, stage: str, fn: Callable, *args, priority: int = 1) -> Future:
        key = f"{stage}-{uuid4().hex}"
        future = self.cluster.submit(fn, *args, key=key, pure=False, priority=priority)
        self.owner[future] = (work, stage)
        work.keys.append(key)
        work.pending += 1
        self.submitted += 1
        assert self.queue is not None  # self.cluster checked it
        self.queue.add(future)
        return future

    def _start(self, pair: Pair) -> None:
        work = _PairWork(pair)
        self.active[pair.name] = work
        self.keys[pair.name] = work.keys
        if pair.take not in self.ready:  # the first pair of its take (its compute time counts here)
            key = f"ready-{uuid4().hex}"
            self.ready[pair.take] = self.cluster.submit(tasks.ready_pair_take, pair.take, self.map_job, key=key,
                                                        pure=False, priority=0)
            work.keys.append(key)
        work.track = self._submit(work, "map", tasks.map_pair, self.ready[pair.take], pair.face, priority=0)
        self._submit(work, "count", tasks.count_frames, work.track, self.job.render.fps)
        self._submit(work, "report", tasks.report_pair, work.track)
        for kind in pair.stale:
            path = pair.output(kind).path
            if kind == "motors":
                self._submit(work, kind, tasks.write_motors, work.track, path)
            elif kind == "score":
                self._submit(work, kind, tasks.write_score, work.track, path)
            elif kind == "sheet":
                self._submit(work, kind, tasks.write_sheet, work.track, pair.face, path, self.job.render.samples)

    def _settle(self, work: _PairWork, stage: str, future: Future) -> None:
        if future.status != "finished":
            if not work.reason:
                work.reason = _reason(stage, future)
            return
        if stage == "count":
            work.frames, fps = future.result()
            if "video" in work.pair.stale:
                self._submit_video(work, work.frames, fps)
        elif stage == "join":
            work.frames, work.written["video"] = future.result()
        elif stage in ("motors", "score", "sheet"):
            work.written[stage] = future.result()
        elif stage == "report":
            work.report = future.result()

    def _submit_video(self, work: _PairWork, frames: int, fps: float) -> None:
        if frames < 1:
            work.reason = "the take has no frames to render"
            return
        render = self.job.render
        if self.job.write.video != "mp4" or render.background:  # other formats: one task draws the whole
            self._submit(work, "join", tasks.render_whole, work.track, work.pair.face, work.pair.output("video").path,
                         render.fps, render.size, render.samples, render.background, priority=2)
            return
        part_frames = max(1, math.floor(render.part_seconds * fps))
        parts = [self._submit(work, "part", tasks.render_video_part, work.track, work.pair.face, start, stop,
                              render.fps, render.size, render.samples, priority=2)
                 for start, stop in frame_ranges(frames, part_frames)]
        self._submit(work, "join", tasks.join_video, work.pair.output("video").path, *parts, priority=3)

    def _finish(self, work: _PairWork) -> None:
        del self.active[work.pair.name]
        work.track = None
        self.remaining[work.pair.take] -= 1
        if self.remaining[work.pair.take] == 0:  # the last pair of its take: the cleaned take may go
            self.ready.pop(work.pair.take, None)
        if work.written:
            write_stamp(work.pair, work.written, work.frames, work.report)
        status = "failed" if work.reason else "done"
        self.results[work.pair.name] = PairResult(work.pair, status, work.reason, work.frames, 0.0, work.written,
                                                  work.report)

    def cancel_unfinished(self) -> None:
        """Cancel the tasks of pairs still in flight and report those pairs as cancelled."""
        if self.ready:
            self.cluster.cancel(list(self.ready.values()))
            self.ready.clear()
        for work in list(self.active.values()):
            self.cluster.cancel([f for f, (w, _) in self.owner.items() if w is work])
            self.results[work.pair.name] = PairResult(work.pair, "cancelled", "interrupted before it finished",
                                                      work.frames, 0.0, work.written)
            if work.written:
                write_stamp(work.pair, work.written, work.frames, work.report)
        self.active.clear()

    def add_compute_times(self, records: list[dict]) -> None:
        """Sum each pair's task compute seconds from the scheduler's task stream."""
        seconds = compute_seconds(records)
        for name, keys in self.keys.items():
            self.results[name].seconds = sum(seconds.get(key, 0.0) for key in keys)


def compute_seconds(records: list[dict]) -> dict[str, float]:
    """Seconds each task key spent computing, from the records of :func:`distributed.get_task_stream`."""
    seconds: dict[str, float] = {}
    for record in records:
        for span in record.get("startstops", ()):
            if span.get("action") == "compute":
                seconds[record["key"]] = seconds.get(record["key"], 0.0) + span["stop"] - span["start"]
    return seconds


#: How often a finished task whose result was lost with its worker is waited for again.
REQUEUES = 3


def _reason(stage: str, future: Future) -> str:
    """One line saying why a task did not finish, for the pair's report."""
    if future.status == "cancelled":
        return f"its {stage} task was cancelled"
    if future.status not in ("finished", "error"):
        return f"its {stage} task's result was lost with its worker {REQUEUES} times"
    exc = future.exception()
    if isinstance(exc, KilledWorker):
        return f"the workers running its {stage} task died, each time it was tried ({exc})"
    if isinstance(exc, ToonfaceError):
        return str(exc)
    if isinstance(exc, OSError):
        return f"{exc.filename + ': ' if exc.filename else ''}{exc.strerror or exc}"
    return f"{stage}: {type(exc).__name__}: {exc}"


def _recorded_report(pair: Pair) -> dict:
    """The take's report a skipped pair's stamp kept (empty if none, or not a table)."""
    report = pair.recorded.get("report")
    return report if isinstance(report, dict) else {}
