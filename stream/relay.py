"""A fault-injecting UDP relay for testing a stream on one machine.

It listens on one address and forwards what it gets to a target, and forwards the target's
replies back to the sender of the stream they answer (by the stream id in the packets; the last
sender for a datagram without one), so several performers can share one relay. Each datagram
(both ways) meets the faults in :class:`Faults`: random loss, loss in bursts, duplication,
corruption (one bit flipped), delay with jitter (which reorders), and explicit reordering (a
datagram held back behind the next). The decisions come from a seeded generator
(:class:`FaultPlan`), so a test can check them without sockets.
"""

from __future__ import annotations

import heapq
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from stream.framing import UDP_IP_HEADER, peek_stream

#: Senders a relay remembers by stream id.
MAX_CLIENTS = 256

@dataclass(frozen=True)
class NetworkFaults:
    """What the relay does to each datagram (the network's faults; a take's are
    :class:`capture.faults.Faults`).

    Attributes
    ----------
    loss : float
        Probability of dropping a datagram.
    burst_seconds : float
        Length of a loss burst (0: none); bursts start at ``bursts_per_second`` on average.
    duplicate, corrupt, reorder : float
        Probabilities of sending twice, of flipping one byte, of holding back by ``reorder_seconds``.
    delay, jitter : float
        Seconds: every datagram waits ``delay`` plus a uniform 0..``jitter``.
    """

    loss: float = 0.0
    burst_seconds: float = 0.0
    bursts_per_second: float = 0.5
    duplicate: float = 0.0
    corrupt: float = 0.0
    reorder: float = 0.0
    reorder_seconds: float = 0.03
    delay: float = 0.0
    jitter: float = 0.0


class FaultPlan:
    """The relay's decisions: for a datagram arriving at ``now``, what to send and when."""

    def __init__(self, faults: NetworkFaults, seed: int = 0) -> None:
        self.faults, self.rng = faults, np.random.default_rng(seed)
        self._burst_until = -np.inf
        self._last: float | None = None
        self._first: float | None = None
        self.counts = {"in": 0, "lost": 0, "duplicated": 0, "corrupted": 0, "reordered": 0, "bytes_in": 0,
                       "wire_bytes_in": 0}

    def flowing_kbps(self) -> float:
        """The wire's kbit/s while datagrams came: from the first to the last, one interval more
        (the last one's own), not over the relay's whole life, idle before and after included."""
        count = self.counts["in"]
        if count < 2 or self._first is None or self._last is None or self._last <= self._first:
            return 0.0
        span = (self._last - self._first) * count / (count - 1)
        return self.counts["wire_bytes_in"] * 8 / span / 1000

    def decide(self, datagram: bytes, now: float) -> list[tuple[float, bytes]]:
        """``(send time, datagram)`` pairs (none if lost). The counts keep the datagrams' bytes
        that came (``bytes_in``) and what they cost on the wire with IPv4/UDP's 28 bytes each
        (``wire_bytes_in``)."""
        f, rng = self.faults, self.rng
        self.counts["in"] += 1
        self._first = now if self._first is None else self._first
        self.counts["bytes_in"] += len(datagram)
        self.counts["wire_bytes_in"] += len(datagram) + UDP_IP_HEADER
        if f.burst_seconds > 0 and self._last is not None:
            if rng.random() < 1 - np.exp(-f.bursts_per_second * max(now - self._last, 0.0)):
                self._burst_until = now + f.burst_seconds
        self._last = now
        if now < self._burst_until or rng.random() < f.loss:
            self.counts["lost"] += 1
            return []
        data = datagram
        if rng.random() < f.corrupt and data:
            flipped = bytearray(data)
            flipped[int(rng.integers(len(data)))] ^= 1 << int(rng.integers(8))
            data = bytes(flipped)
            self.counts["corrupted"] += 1
        when = now + f.delay + rng.uniform(0.0, f.jitter)
        if rng.random() < f.reorder:
            when += f.reorder_seconds
            self.counts["reordered"] += 1
        out = [(when, data)]
        if rng.random() < f.duplicate:
            out.append((when + rng.uniform(0.0, f.jitter + 0.001), data))
            self.counts["duplicated"] += 1
        return out


class Relay:
    """Forward UDP from ``listen`` to ``target`` (and replies back) through a :class:`FaultPlan`.

    Runs in two daemon threads; :meth:`close` stops them. ``address`` is where senders send.
    """

    def __init__(self, listen: tuple[str, int], target: tuple[str, int], faults: NetworkFaults, seed: int = 0,
                 clock: Callable[[], float] = time.perf_counter, max_queue: int = 4096) -> None:
        self.target, self.clock, self.max_queue = target, clock, max_queue
        self.forward, self.backward = FaultPlan(faults, seed), FaultPlan(faults, seed + 1)
        self.front = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.back = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            self.front.bind(listen)
            self.back.bind((listen[0], 0))
        except OSError:
            self.front.close()
            self.back.close()
            raise
        for s in (self.front, self.back):
            s.settimeout(0.1)  # only to notice close()
        self._queue: list[tuple[float, int, bytes, bool]] = []  # (when, order, data, forward)
        self._order = 0
        self._client: tuple[str, int] | None = None  # the last sender
        self._clients: dict[int, tuple[str, int]] = {}  # each stream's sender, by stream id
        self._due = threading.Condition()  # guards the queue and the client; signalled on each arrival
        self._stop = threading.Event()
        self._threads = [threading.Thread(target=self._receive, args=(s, fwd), daemon=True)
                         for s, fwd in ((self.front, True), (self.back, False))]
        self._threads.append(threading.Thread(target=self._send, daemon=True))

    @property
    def address(self) -> tuple[str, int]:
        return self.front.getsockname()

    def start(self) -> Relay:
        for thread in self._threads:
            thread.start()
        return self

    def close(self) -> None:
        self._stop.set()
        with self._due:
            self._due.notify_all()
        for thread in self._threads:
            if thread.is_alive():
                thread.join(timeout=2.0)
        self.front.close()
        self.back.close()

    def __enter__(self) -> Relay:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _receive(self, sock: socket.socket, forward: bool) -> None:
        plan = self.forward if forward else self.backward
        while not self._stop.is_set():
            try:
                data, sender = sock.recvfrom(65536)
            except (TimeoutError, OSError):
                continue
            now = self.clock()
            with self._due:
                if forward:
                    self._client = sender
                    stream = peek_stream(data)
                    if stream is not None and (stream in self._clients or len(self._clients) < MAX_CLIENTS):
                        self._clients[stream] = sender
                for when, out in plan.decide(data, now):
                    if len(self._queue) < self.max_queue:
                        heapq.heappush(self._queue, (when, self._order, out, forward))
                        self._order += 1
                self._due.notify()

    def _send(self) -> None:
        """Send each datagram at its time, sleeping until the next is due or one arrives."""
        while not self._stop.is_set():
            with self._due:
                now = self.clock()
                due = []
                while self._queue and self._queue[0][0] <= now:
                    due.append(heapq.heappop(self._queue))
                client, clients = self._client, dict(self._clients)
                if not due:
                    self._due.wait(self._queue[0][0] - now if self._queue else None)
                    continue
            for _, _, data, forward in due:
                try:
                    if forward:
                        self.back.sendto(data, self.target)
                    elif (to := clients.get(peek_stream(data) or 0, client)) is not None:
                        self.front.sendto(data, to)
                except OSError:
                    pass
