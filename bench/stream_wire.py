"""``stream.wire_both_*``: what the motor stream costs on the wire, both ways, at 30 fps.

Everything a stream puts on the network is counted: each datagram's bytes and IPv4/UDP's 28
bytes a datagram, forward (the sender's packets) and back (the receiver's acknowledgements and
keyframe requests), over 30 s (10 with ``--quick``) of motors sent at 30 frames a second, 2 a
packet, through a simulated network with a virtual clock (seeded), the receiver answering as
:class:`stream.receiver.StreamReceiver` does.

``stream.wire_both_kbps``
    Loss-free (1 ms each way): forward plus back, kbit/s, the largest over the contents (goal 6:
    fewer, larger packets while nothing is lost, and acknowledgements only as often as loss
    recovery needs). The detail has each content's forward, back, payload and packets, the same
    stream sealed with a key, and the jitter buffer's median delay (goal of the issue: at most 40 ms
    added by packing, here 2 frames a packet: 33 ms).
``stream.wire_both_lossy_kbps``
    The same under 10 % random loss, 50 ms bursts and 5 ms of jitter both ways (goal 12).

The contents are the synthetic performer mapped live at 30 Hz (three seeds) and, where the shared
real data is present, two real facial takes (AnimFace, mapped live at their 60 Hz, every other
frame sent): data the coding was not fitted on.
"""

from __future__ import annotations

import heapq

import numpy as np

from bench.core import REALDATA, Figure
from capture import load_take
from capture.sources import synthetic_source, take_source
from stream.framing import UDP_IP_HEADER
from stream.packets import StreamWriter, is_key_request, key_request, read_ack
from stream.playout import Playout
from stream.reader import StreamReader
from stream.relay import FaultPlan, NetworkFaults
from toon import standard_neutral
from toonface.send import build_mapper

RATE = 30.0
CLEAN = NetworkFaults(delay=0.001)
LOSSY = NetworkFaults(loss=0.10, burst_seconds=0.05, bursts_per_second=0.5, jitter=0.005, delay=0.001)
KEY = b"a bench key of sixteen bytes or more"
REQUEST_INTERVAL = 0.05  # as StreamReceiver's


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``stream.wire_both_*`` figures."""
    seconds = 10.0 if quick else 30.0
    contents = {f"synthetic_seed{seed}": _synthetic(seconds, seed) for seed in (0, 1, 2)}
    contents.update(_real(seconds))
    clean = {name: _exchange(values, CLEAN) for name, values in contents.items()}
    lossy = {name: _exchange(values, LOSSY) for name, values in contents.items()}
    sealed = _exchange(contents["synthetic_seed0"], CLEAN, KEY)
    detail = {"rate_hz": RATE, "frames_per_packet": 2, "seconds": seconds, "udp_ip_bytes_per_datagram": UDP_IP_HEADER,
              "each": clean, "sealed_synthetic_seed0": sealed}
    return [Figure("stream.wire_both_kbps", max(r["both_kbps"] for r in clean.values()), "kbit/s", 6.0, False, detail),
            Figure("stream.wire_both_lossy_kbps", max(r["both_kbps"] for r in lossy.values()), "kbit/s", 12.0, False,
                   {"faults": {"loss": 0.1, "burst_ms": 50, "jitter_ms": 5}, "each": lossy})]


def _synthetic(seconds: float, seed: int) -> np.ndarray:
    source = synthetic_source(seconds=seconds, rate=RATE, seed=seed)
    mapper = build_mapper(source)
    return np.array([mapper.step(frame.positions, frame.t)[0] for frame in source.frames])


def _real(seconds: float) -> dict[str, np.ndarray]:
    folder = REALDATA / "facial" / "animface"
    out: dict[str, np.ndarray] = {}
    if not folder.is_dir():
        return out
    for name in ("JawMoCap", "EyebrowsMoCap"):
        take = load_take(folder / f"{name}.csv", units="cm")
        mapper = build_mapper(take_source(take))
        step = max(1, int(round(take.rate / RATE)))
        motors = np.array([mapper.step(row, i / take.rate)[0] for i, row in enumerate(take.positions)])
        out[name] = motors[::step][:int(seconds * RATE)]
    return out


def _exchange(values: np.ndarray, faults: NetworkFaults, key: bytes | None = None, seed: int = 1) -> dict:
    """Send ``values`` at :data:`RATE` through ``faults`` both ways; what crossed the wire."""
    writer, reader = StreamWriter(RATE, first_sequence=0, key=key), StreamReader(key)
    playout = Playout(standard_neutral())
    forward, backward = FaultPlan(faults, seed), FaultPlan(faults, seed + 1)
    queue: list[tuple[float, int, bool, bytes]] = []  # (arrival, order, to the sender, datagram)
    sent = {"forward_bytes": 0, "forward_datagrams": 0, "back_bytes": 0, "back_datagrams": 0, "key_requests": 0}
    order, last_request, delays = 0, -np.inf, []

    def put(datagram: bytes, now: float, to_sender: bool) -> None:
        nonlocal order
        side = "back" if to_sender else "forward"
        sent[f"{side}_bytes"] += len(datagram) + UDP_IP_HEADER
        sent[f"{side}_datagrams"] += 1
        for when, data in (backward if to_sender else forward).decide(datagram, now):
            heapq.heappush(queue, (when, order, to_sender, data))
            order += 1

    for index, row in enumerate(values):
        now = index / RATE
        while queue and queue[0][0] <= now:
            when, _, to_sender, data = heapq.heappop(queue)
            if to_sender:
                acked = read_ack(data, key, writer.frame)
                if acked is not None:
                    writer.acknowledge(*acked)
                elif is_key_request(data, key):
                    writer.request_keyframe()
                continue
            for frames in reader.read(data, when):
                playout.add(frames)
            if (ack := reader.take_ack()) is not None:
                put(ack, when, True)
            if reader.want_keyframe and when - last_request >= REQUEST_INTERVAL:
                last_request = when
                sent["key_requests"] += 1
                put(key_request(sent["key_requests"], key, reader.stream), when, True)
        datagram = writer.push(row, now)
        if datagram is not None:
            put(datagram, now, False)
        playout.values_at(now)
        if playout.delay is not None:
            delays.append(playout.delay)
    seconds = len(values) / RATE

    def kbps(count: int) -> float:
        return round(count * 8 / seconds / 1000, 3)

    return {"both_kbps": kbps(sent["forward_bytes"] + sent["back_bytes"]), "forward_kbps": kbps(sent["forward_bytes"]),
            "back_kbps": kbps(sent["back_bytes"]), "payload_kbps": kbps(writer.payload_bytes),
            "forward_datagrams": sent["forward_datagrams"], "back_datagrams": sent["back_datagrams"],
            "key_requests": sent["key_requests"], "keyframes": writer.keyframes,
            "median_delay_ms": round(float(np.median(delays)) * 1000, 1) if delays else None}
