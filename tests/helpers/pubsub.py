"""A NATS server on loopback for the tests of rooms shared between server processes."""

from __future__ import annotations

import shutil
import socket
import subprocess
import time
from collections.abc import Iterator
from contextlib import contextmanager

import pytest


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


#: The token the tests' NATS servers ask of their clients.
NATS_TOKEN = "test-nats-token-0123456789"


@contextmanager
def nats_server(auth: bool = True) -> Iterator[str]:
    """Debian's ``nats-server`` on a free loopback port (make test installs it; skips where it is
    missing), asking its clients for :data:`NATS_TOKEN` unless ``auth`` is False; yields its
    ``nats://`` address (with the token) once it accepts connections."""
    binary = shutil.which("nats-server") or shutil.which("nats-server", path="/usr/sbin:/usr/local/sbin")
    if binary is None:
        pytest.skip("nats-server is missing (make test installs Debian's nats-server)")
    port = free_port()
    process = subprocess.Popen([binary, "-a", "127.0.0.1", "-p", str(port), *(["--auth", NATS_TOKEN] if auth else [])],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 10
        while True:  # (a process starting: its port answers when it is ready)
            try:
                socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
                break
            except OSError:
                if process.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError("nats-server did not start") from None
                try:
                    process.wait(0.02)  # (it may have ended: then the next round says so)
                except subprocess.TimeoutExpired:
                    pass
        yield f"nats://{NATS_TOKEN}@127.0.0.1:{port}" if auth else f"nats://127.0.0.1:{port}"
    finally:
        process.terminate()
        process.wait(10)
