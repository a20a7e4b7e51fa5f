"""Run a documentation page's shell blocks as a reader would paste them into a terminal.

Each ```` ```sh ```` block runs in ``bash -e`` in a folder of the test's, with this environment's
commands (``toonface``, ``dask``) first on the PATH and Debian's ``/usr/sbin`` (``nats-server``)
after it. A block that holds a server runs in the background until the test is done with it, in
a session of its own, so everything it started ends with it.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def blocks(page: str | Path, language: str = "sh") -> list[str]:
    """The fenced blocks of ``language`` in a page of ``docs/`` (a path relative to it), in order."""
    text = (ROOT / "docs" / page).read_text()
    return re.findall(rf"```{language}\n(.*?)```", text, re.S)


def _environment() -> dict[str, str]:
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", ""), "/usr/sbin"])
    return {**os.environ, "PATH": path, "NO_COLOR": "1"}


def substitute(block: str, names: dict[str, str]) -> str:
    """``block`` with each placeholder of ``names`` (a token, a port) replaced by its value."""
    for name, value in names.items():
        block = block.replace(name, value)
    return block


def run(block: str, cwd: Path, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run ``block`` to its end, then stop what it left in the background (a block that starts a
    cluster and uses it); fails the test, with what it printed, where it fails."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        process = subprocess.Popen(["bash", "-e", "-c", block], cwd=cwd, env=_environment(), stdout=out, stderr=err,
                                   text=True, start_new_session=True)
        try:
            returncode = process.wait(timeout)
        finally:
            _stop(process)
        out.seek(0)
        err.seek(0)
        done = subprocess.CompletedProcess(block, returncode, out.read(), err.read())
    assert done.returncode == 0, f"{block}\n--- exit {done.returncode}\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}"
    return done


def _stop(process: subprocess.Popen) -> None:
    """End ``process`` and everything in its session."""
    try:
        os.killpg(process.pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        try:
            os.killpg(process.pid, 0)
        except ProcessLookupError:
            break
        try:
            process.wait(0.05)  # (the leader may be gone while its children still close)
        except subprocess.TimeoutExpired:
            pass
    else:
        os.killpg(process.pid, signal.SIGKILL)
    if process.returncode is None:
        process.wait(10)


class Background:
    """A block running in the background: ``log``, the file its output goes to."""

    def __init__(self, process: subprocess.Popen, log: Path) -> None:
        self.process, self.log = process, log

    def output(self) -> str:
        """What it printed so far."""
        return self.log.read_text()

    def finish(self, timeout: float) -> str:
        """Wait for it to end by itself (a command given ``--seconds``); fails the test unless it
        ends well in time. Returns what it printed."""
        returncode = self.process.wait(timeout)
        assert returncode == 0, f"exit {returncode}:\n{self.output()[-2000:]}"
        return self.output()


@contextmanager
def running(block: str, cwd: Path, ready: str, timeout: float = 60) -> Iterator[Background]:
    """Start ``block`` in the background and yield it once ``ready`` appears in its output; at
    the end, stop everything the block started."""
    log = cwd / f".block-{abs(hash(block))}.log"
    with open(log, "w") as out:
        process = subprocess.Popen(["bash", "-e", "-c", block], cwd=cwd, env=_environment(), stdout=out,
                                   stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + timeout
        while ready not in log.read_text():
            if process.poll() is not None and ready not in log.read_text():
                raise AssertionError(f"{block}\n--- ended ({process.returncode}) before {ready!r}:\n{log.read_text()}")
            assert time.monotonic() < deadline, f"{block}\n--- no {ready!r} in {timeout} s:\n{log.read_text()}"
            try:
                process.wait(0.05)  # (a server starting: it writes its banner when it is ready)
            except subprocess.TimeoutExpired:
                pass
        yield Background(process, log)
    finally:
        _stop(process)
