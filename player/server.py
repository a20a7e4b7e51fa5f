"""The command socket: TCP (a reply per line) and UDP (fire-and-forget; replies sent back anyway).

Both bind 127.0.0.1 unless told otherwise and protect the player from what arrives:

- a line longer than :data:`MAX_LINE` bytes is refused (and the rest of it skipped);
- at most ``max_clients`` TCP connections at once (others are told so and closed);
- each client (TCP connection or UDP sender) may send ``rate`` commands per second, with bursts
  of ``burst``; lines over the limit are refused, not queued;
- a client that disconnects mid-line leaves the player running; its partial line is dropped.
"""

from __future__ import annotations

import socketserver
import threading
import time
from collections.abc import Callable

MAX_LINE = 4096


class RateLimit:
    """A token bucket: ``rate`` per second, up to ``burst`` at once (clock injectable)."""

    def __init__(self, rate: float, burst: int, clock: Callable[[], float] = time.monotonic) -> None:
        self.rate, self.burst, self.clock = rate, burst, clock
        self.tokens, self.last = float(burst), clock()

    def allow(self) -> bool:
        """Take one token if there is one."""
        now = self.clock()
        self.tokens = min(self.burst, self.tokens + (now - self.last) * self.rate)
        self.last = now
        if self.tokens >= 1:
            self.tokens -= 1
            return True
        return False


class _TCPHandler(socketserver.StreamRequestHandler):
    server: CommandServer

    def handle(self) -> None:
        if not self.server.admit():
            self.wfile.write(b"error: too many connections\n")
            return
        try:
            limit = RateLimit(self.server.rate, self.server.burst)
            while True:
                raw = self.rfile.readline(MAX_LINE + 1)
                if not raw:
                    return  # the client went away
                if len(raw) > MAX_LINE and not raw.endswith(b"\n"):
                    self._skip_rest()
                    self._reply(f"error: line longer than {MAX_LINE} bytes")
                    continue
                if not raw.endswith(b"\n"):
                    return  # disconnected mid-line: the partial command is dropped
                self._reply(self.server.answer(raw, limit))
        except (ConnectionError, OSError):
            return
        finally:
            self.server.leave()

    def _skip_rest(self) -> None:
        while True:
            chunk = self.rfile.readline(MAX_LINE + 1)
            if not chunk or chunk.endswith(b"\n"):
                return

    def _reply(self, text: str) -> None:
        self.wfile.write(text.encode() + b"\n")


class _UDPHandler(socketserver.BaseRequestHandler):
    server: CommandUDPServer

    def handle(self) -> None:
        data, sock = self.request
        limit = self.server.limit_for(self.client_address)
        lines = data.split(b"\n")
        if len(data) > MAX_LINE:
            replies = [f"error: datagram longer than {MAX_LINE} bytes"]
        else:
            replies = [self.server.answer(line + b"\n", limit) for line in lines if line.strip()]
        if replies:
            sock.sendto(("\n".join(replies) + "\n").encode(), self.client_address)


class _Answering:
    """What both servers share: decode a line, check the rate, ask the handler."""

    handler: Callable[[str], str]
    rate: float
    burst: int

    def answer(self, raw: bytes, limit: RateLimit) -> str:
        if not limit.allow():
            return f"error: more than {self.rate:g} commands a second; slow down"
        try:
            line = raw.decode("utf-8").rstrip("\r\n")
        except UnicodeDecodeError:
            return "error: not UTF-8 text"
        return self.handler(line)


class CommandServer(_Answering, socketserver.ThreadingTCPServer):
    """TCP command server; ``handler(line) -> reply`` runs in the connection's thread."""

    daemon_threads = True
    allow_reuse_address = True

    def __init__(self, address: tuple[str, int], handler: Callable[[str], str], max_clients: int = 8,
                 rate: float = 200.0, burst: int = 50) -> None:
        self.handler, self.rate, self.burst = handler, rate, burst
        self._slots = threading.BoundedSemaphore(max_clients)
        super().__init__(address, _TCPHandler)

    def admit(self) -> bool:
        return self._slots.acquire(blocking=False)

    def leave(self) -> None:
        self._slots.release()


class CommandUDPServer(_Answering, socketserver.ThreadingUDPServer):
    """UDP command server: each datagram holds one or more lines."""

    daemon_threads = True
    max_senders = 256

    def __init__(self, address: tuple[str, int], handler: Callable[[str], str], rate: float = 200.0,
                 burst: int = 50) -> None:
        self.handler, self.rate, self.burst = handler, rate, burst
        self._limits: dict[tuple, RateLimit] = {}
        self._lock = threading.Lock()
        super().__init__(address, _UDPHandler)

    def limit_for(self, sender: tuple) -> RateLimit:
        """The sender's token bucket (memory stays bounded: the oldest senders are forgotten)."""
        with self._lock:
            if sender not in self._limits:
                if len(self._limits) >= self.max_senders:
                    self._limits.pop(next(iter(self._limits)))
                self._limits[sender] = RateLimit(self.rate, self.burst)
            return self._limits[sender]


def start(server: socketserver.BaseServer) -> threading.Thread:
    """Serve in a daemon thread; stop with ``server.shutdown(); server.server_close()``."""
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True)
    thread.start()
    return thread


def local_port(server: socketserver.TCPServer | socketserver.UDPServer) -> int:
    """The port the server is bound to (useful after binding port 0)."""
    return server.socket.getsockname()[1]

