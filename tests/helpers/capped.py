"""Hostile inputs under a memory cap: a regression fails fast instead of swapping the machine.

:func:`run_capped` runs a ``toonface`` command in a process whose address space is capped
(``resource.setrlimit``) and reports how long it took and the most memory it held;
:func:`capped_memory` caps this process for the length of a block.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

#: Address space a capped command may reserve (numpy's and OpenBLAS's threads reserve much that
#: they never touch; resident memory is what :attr:`Run.peak_mb` holds to 500 MB).
ADDRESS_SPACE = 4 << 30
#: The most a hostile input may cost: within 5 s and under 500 MB (resident).
SECONDS, MEGABYTES = 5.0, 500.0


@dataclass
class Run:
    """What a capped command did: its exit status, its output, its wall time and peak memory."""

    returncode: int
    stdout: str
    stderr: str
    seconds: float
    peak_mb: float

    def refused_in_one_line(self) -> bool:
        """Exit 2 with one line on stderr that is not an internal error or a traceback."""
        lines = self.stderr.strip().splitlines()
        return (self.returncode == 2 and len(lines) == 1 and "internal error" not in lines[0]
                and "Traceback" not in self.stderr)

    def within_bounds(self) -> bool:
        return self.seconds <= SECONDS and self.peak_mb <= MEGABYTES


def _cap() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))


def run_capped(args: list[str], cwd: Path, timeout: float = 30.0) -> Run:
    """``toonface ARGS`` in ``cwd`` with its address space capped; killed after ``timeout``."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    started = time.perf_counter()
    with open(cwd / ".out", "w+") as out, open(cwd / ".err", "w+") as err:
        process = subprocess.Popen([sys.executable, "-m", "toonface", *args], cwd=cwd, stdout=out, stderr=err,
                                   stdin=subprocess.DEVNULL, preexec_fn=_cap, env=env)
        ended: dict = {}
        waiter = threading.Thread(target=lambda: ended.update(result=os.wait4(process.pid, 0)))
        waiter.start()  # (wait4 reaps it and gives its own peak memory; it takes no time-out)
        waiter.join(timeout)
        if waiter.is_alive():
            process.kill()
            waiter.join()
        _, status, usage = ended["result"]
        process.returncode = os.waitstatus_to_exitcode(status)
        seconds = time.perf_counter() - started
        out.seek(0)
        err.seek(0)
        return Run(process.returncode, out.read(), err.read(), seconds, usage.ru_maxrss / 1024)


@contextmanager
def capped_memory(extra_bytes: int = 2 << 30) -> Iterator[None]:
    """This process's address space capped at what it holds now plus ``extra_bytes`` within the
    block: an allocation beyond fails with MemoryError instead of swapping."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    with open("/proc/self/statm") as statm:
        now = int(statm.read().split()[0]) * resource.getpagesize()
    cap = now + extra_bytes if hard == resource.RLIM_INFINITY else min(now + extra_bytes, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
