"""A server that stops on SIGTERM within a bound, even while it is busy.

The ``toonface`` command raises SIGTERM in the main thread as
:class:`~common.errors.Terminated` (as Ctrl-C raises KeyboardInterrupt), which ends a server's
event loop. Work the loop handed to a worker thread (a render, a take opened and mapped, a voice
recognised, a performer page's mapper) is not ended by it, and Python waits for those threads
before the process may exit: a studio rendering a long movie went on for as long as the render
took. :func:`stop_within` gives such work a flag to look at (a render's progress does, between
frames), and ends the process outright once the bound has passed.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from common.errors import Terminated

#: Seconds a server has to end its work after SIGTERM before the process is ended outright.
STOP_SECONDS = 1.5


@contextmanager
def stop_within(seconds: float = STOP_SECONDS) -> Iterator[threading.Event]:
    """Within the block (in the main thread), SIGTERM sets the yielded event, raises
    :class:`~common.errors.Terminated` in the main thread, and ends the process with status 143
    ``seconds`` later if it has not ended by then. Outside the main thread, a plain event."""
    stop = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield stop
        return

    def terminate(signum: int, frame: object) -> None:
        if stop.is_set():  # a second SIGTERM while stopping: the watchdog is already armed
            return
        stop.set()
        watchdog = threading.Timer(seconds, _end_now)
        watchdog.daemon = True
        watchdog.start()
        raise Terminated()

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield stop
    finally:
        signal.signal(signal.SIGTERM, previous)


def _end_now() -> None:
    os.write(2, b"toonface: stopped (SIGTERM) with work left unfinished\n")
    os._exit(143)


def check_stop(stop: threading.Event | None) -> None:
    """Raise :class:`~common.errors.Terminated` where ``stop`` is set (for work in a worker thread
    to call between steps)."""
    if stop is not None and stop.is_set():
        raise Terminated()
