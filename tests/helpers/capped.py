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


#: Runs ``ARGS`` under an address-space cap and writes its peak memory: a small process between
#: the test and the command, as a child's peak (``ru_maxrss``) counts what its parent held when it
#: forked (a pytest process of 500 MB made every command look that big). SIGTERM is passed on.
WRAPPER = """
import os, resource, signal, sys
resource.setrlimit(resource.RLIMIT_AS, (int(sys.argv[1]), int(sys.argv[1])))
pid = os.fork()
if pid == 0:
    os.execv(sys.executable, [sys.executable, *sys.argv[3:]])
signal.signal(signal.SIGTERM, lambda number, frame: os.kill(pid, number))
_, status, usage = os.wait4(pid, 0)
with open(sys.argv[2], "w") as out:
    out.write(str(usage.ru_maxrss))
code = os.waitstatus_to_exitcode(status)
sys.exit(code if code >= 0 else 128 - code)
"""


def capped_command(args: list[str], peak_file: Path) -> list[str]:
    """The command line that runs ``python ARGS`` capped, its peak memory (kB) written to ``peak_file``."""
    return [sys.executable, "-c", WRAPPER, str(ADDRESS_SPACE), str(peak_file), *args]


def peak_mb(peak_file: Path) -> float:
    """The peak memory :func:`capped_command` wrote, MB."""
    return int(peak_file.read_text()) / 1024


def run_capped(args: list[str], cwd: Path, timeout: float = 30.0) -> Run:
    """``toonface ARGS`` in ``cwd`` with its address space capped; killed after ``timeout``."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    started = time.perf_counter()
    peak = cwd / ".peak"
    with open(cwd / ".out", "w+") as out, open(cwd / ".err", "w+") as err:
        process = subprocess.Popen(capped_command(["-m", "toonface", *args], peak), cwd=cwd, stdout=out, stderr=err,
                                   stdin=subprocess.DEVNULL, env=env)
        try:
            process.wait(timeout)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        seconds = time.perf_counter() - started
        out.seek(0)
        err.seek(0)
        peak_memory = peak_mb(peak) if peak.exists() else float("inf")
        return Run(process.returncode, out.read(), err.read(), seconds, peak_memory)


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
