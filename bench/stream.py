"""``stream``: the telepresence motor stream.

The content is the synthetic performer (default noise, 0.2 mm) mapped live by the toon32 preset
at 60 Hz, as ``toonface send synthetic`` sends it.

``stream.extras_payload_ratio``: the same stream carrying the mapping's parameters beyond the 21
(HT, UL, CP, JS, PERK) over the 21 alone, acknowledged (goal 1.1; unacknowledged in the detail).
``stream.payload_kbps``: coded motor frames (keyframes included; no headers, no tags) per
second of a loss-free stream, 2 frames a packet (goal 2.5); ``stream.payload_kbps_0.3mm``: the
same with 0.3 mm of marker noise (goal 2.5). The detail has the payload of two real facial takes
mapped live (AnimFace, 60 Hz; data the coding was not fitted on) and of the lossy run below,
where frames go one a packet and repeat. ``stream.wire_kbps``: the loss-free stream with the
21-byte headers, the 4-byte CRCs and IPv4/UDP's 28 bytes a packet (no goal).
``stream.quantisation_error_pct``: the largest difference between a sent and a decoded value,
% of range (goal 0.5).
``stream.latency_ms``: capture at the sender to showing at the receiver, median, over real UDP
sockets on loopback with the default jitter buffer (goal 45).

Under 10 % random loss, 50 ms bursts and 5 ms of jitter both ways (a simulated network with a
virtual clock, seeded; acknowledgements cross it too), 30 s of the stream is shown with each
concealment: ``stream.concealed_pct``, the share of shown frames concealed or recovering with
the best predicting concealment (goal 12); ``stream.concealment_vs_hold_ratio``, the RMS error
against the sent values of those frames, with the better of the predicting concealments (linear,
or pysindy's motion model) over the same with holding the last value (goal 0.8); each method's
error is in the detail. ``stream.out_of_range``: shown values outside [0, 1], all methods (goal
0). ``stream.lossy_latency_ms``: the jitter buffer's median delay there (goal 45).
``stream.jump_vs_own_speed``: the largest change of a motor between two shown frames while
concealing or recovering, over the larger of 0.05 and that motor's largest step in the values
sent (as quantised; goal 1: the face never moves faster than it does on its own).
``stream.sender_fps``: the sender's live cleaning, mapping and coding, frames per second on one
core (goal 60). ``stream.wire_both_kbps`` and ``stream.wire_both_lossy_kbps``: the stream's cost
on the wire both ways at 30 fps (:mod:`bench.stream_wire`).
"""

from __future__ import annotations

import heapq
import os
import threading
import time

import numpy as np

from bench import stream_wire
from bench.core import REALDATA, Figure, one_core
from capture import load_take
from capture.sources import synthetic_source, take_source
from mapping.predict import MotionModel, trailing_line
from stream.framing import UDP_IP_HEADER
from stream.packets import StreamWriter, read_ack
from stream.playout import Playout
from stream.reader import StreamReader
from stream.receiver import StreamReceiver
from stream.relay import FaultPlan, NetworkFaults
from stream.sender import StreamSender
from stream.wire import quantise
from toon import standard_neutral
from toonface.send import build_mapper, run_sender

RATE = 60.0
LOSSY = NetworkFaults(loss=0.10, burst_seconds=0.05, bursts_per_second=0.5, jitter=0.005, delay=0.001)


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``stream.*`` figures."""
    seconds = 30.0 if quick else 60.0
    values, fps, extras = _live_values(seconds)
    noisier, _, _ = _live_values(seconds, noise_mm=0.3)
    real = _real_motors()
    return [*_rates(values, noisier, real), _extras_ratio(values, *extras), _latency(4.0 if quick else 10.0),
            *_concealment(values, real, quick),
            Figure("stream.sender_fps", fps, "frames/s", 60.0, True, {"one_core": hasattr(os, "sched_setaffinity")}),
            *stream_wire.run(quick)]


def _live_values(seconds: float, noise_mm: float = 0.2) -> tuple[np.ndarray, float, tuple[np.ndarray, tuple]]:
    """The motors the sender sends, its frames per second (mapping and coding) on one core, and
    the parameters beyond the 21 the mapping drives beside them (values, codes)."""
    source = synthetic_source(seconds=seconds, rate=RATE, noise_mm=noise_mm)
    mapper = build_mapper(source)
    writer = StreamWriter(RATE)
    with one_core():
        out, beyond, start = [], [], time.perf_counter()
        for frame in source.frames:
            values, _ = mapper.step(frame.positions, frame.t)
            writer.push(values, frame.t)
            out.append(values)
            beyond.append(mapper.extra.copy())
        elapsed = time.perf_counter() - start
    return np.array(out), len(out) / elapsed, (np.array(beyond), mapper.extra_codes)


def _payload_kbps(values: np.ndarray) -> float:
    return _loss_free(values)[0].payload_bytes * 8 / (len(values) / RATE) / 1000


def _extras_ratio(values: np.ndarray, extra: np.ndarray, codes: tuple[str, ...]) -> Figure:
    """``stream.extras_payload_ratio``: the payload of the same stream carrying the mapping's
    parameters beyond the 21 (HT, UL, CP, JS, PERK) over the 21 alone's, acknowledged (goal 1.1);
    the detail has the same without acknowledgements (keyframes every half second)."""
    both = np.hstack([values, extra])
    acked = _loss_free(both, codes)[0].payload_bytes / _loss_free(values)[0].payload_bytes
    plain = [StreamWriter(RATE, first_sequence=0, codes=c) for c in ((), codes)]
    for index in range(len(values)):
        plain[0].push(values[index], index / RATE)
        plain[1].push(both[index], index / RATE)
    return Figure("stream.extras_payload_ratio", acked, "ratio", 1.1, False,
                  {"codes": list(codes), "unacknowledged_ratio": round(plain[1].payload_bytes / plain[0].payload_bytes,
                                                                       4)})


def _loss_free(values: np.ndarray, codes: tuple[str, ...] = ()) -> tuple[StreamWriter, list[np.ndarray]]:
    """A loss-free stream (``codes``: its parameters after the 21), each acknowledgement back
    before the next packet (a short round trip: with a long one the sender predicts from further
    back)."""
    writer, reader = StreamWriter(RATE, first_sequence=0, codes=codes), StreamReader()
    decoded = []
    for index, row in enumerate(values):
        datagram = writer.push(row, index / RATE)
        if datagram is not None:
            decoded += [f.values for f in reader.read(datagram, index / RATE)]
            ack = reader.take_ack()
            if ack is not None:
                writer.acknowledge(*(read_ack(ack, None, writer.frame) or (0, 0)))
    return writer, decoded


def _rates(values: np.ndarray, noisier: np.ndarray, real: dict[str, np.ndarray] | str) -> list[Figure]:
    writer, decoded = _loss_free(values)
    seconds = len(values) / RATE
    got = np.concatenate(decoded)
    error = float(np.abs(got - values[:len(got)]).max()) * 100
    payload = writer.payload_bytes * 8 / seconds / 1000
    wire = (writer.packet_bytes + UDP_IP_HEADER * writer.packets) * 8 / seconds / 1000
    detail = {"seconds": seconds, "motors": 21, "rate_hz": RATE, "frames_per_packet": 2, "steps": writer.steps,
              "bits_per_motor_frame": round(writer.payload_bytes * 8 / len(values) / 21, 3),
              "keyframes": writer.keyframes, "packets_kbps": round(writer.packet_bytes * 8 / seconds / 1000, 3),
              "payload_kbps_real_takes": real if isinstance(real, str) else {
                  name: round(_payload_kbps(motors), 3) for name, motors in real.items()}}
    return [Figure("stream.payload_kbps", payload, "kbit/s", 2.5, False, detail),
            Figure("stream.payload_kbps_0.3mm", _payload_kbps(noisier), "kbit/s", 2.5, False, {"noise_mm": 0.3}),
            Figure("stream.wire_kbps", wire, "kbit/s", None, False, {"udp_ip_bytes_per_packet": UDP_IP_HEADER}),
            Figure("stream.quantisation_error_pct", error, "% of range", 0.5, False, {"steps": writer.steps})]


def _real_motors() -> dict[str, np.ndarray] | str:
    """The AnimFace takes' motors as the sender maps them live ``(frames, 21)``, or why there
    are none."""
    folder = REALDATA / "facial" / "animface"
    if not folder.is_dir():
        return f"skipped: {folder} is absent"
    out = {}
    for name in ("JawMoCap", "EyebrowsMoCap"):
        take = load_take(folder / f"{name}.csv", units="cm")
        mapper = build_mapper(take_source(take))
        out[name] = np.array([mapper.step(row, i / take.rate)[0] for i, row in enumerate(take.positions)])
    return out


def _latency(seconds: float) -> Figure:
    """Real sockets on loopback: the sender in one thread, the face shown 60 times a second."""
    source = synthetic_source(seconds=seconds + 1.0, rate=RATE)
    mapper = build_mapper(source)
    stop = threading.Event()
    latencies: list[float] = []
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as receiver:
        def show() -> None:
            while not stop.wait(1 / RATE):
                receiver.values_at()
                latency = receiver.playout.latency()
                if latency is not None:
                    latencies.append(latency)
        viewer = threading.Thread(target=show, daemon=True)
        viewer.start()
        sender = StreamSender(receiver.address, StreamWriter(RATE))
        run_sender(source, mapper, [sender], seconds)
        sender.close()
        stop.set()
        viewer.join()
    ms = np.array(latencies[int(RATE):]) * 1000  # after the first second
    return Figure("stream.latency_ms", float(np.median(ms)), "ms", 45.0, False,
                  {"p95_ms": round(float(np.percentile(ms, 95)), 2), "frames_per_packet": 2,
                   "packetisation_ms": round(1000 / RATE, 2), "seconds": seconds})


def _concealment(values: np.ndarray, real: dict[str, np.ndarray] | str, quick: bool) -> list[Figure]:
    split = int(0.5 * len(values))
    times = np.arange(len(values)) / RATE
    model = MotionModel().fit(values[:split], times[:split])

    def sindy(history: np.ndarray, stamps: np.ndarray, ahead: float) -> np.ndarray:
        level, slope = trailing_line(history, stamps)
        return np.clip(model.advance(level[-1:], slope[-1:], ahead)[0], 0.0, 1.0)

    test = values[split:] if not quick else values[split:split + int(10 * RATE)]
    runs = {method: _simulate(test, method, sindy if method == "sindy" else None)
            for method in ("hold", "linear", "sindy")}
    hold = runs["hold"]["rms"]
    best = min(("linear", "sindy"), key=lambda m: runs[m]["rms"])
    states = runs[best]["states"]
    shown = sum(states.values()) - states.get("waiting", 0)
    lossy = runs[best]
    detail = {"faults": {"loss": LOSSY.loss, "burst_ms": LOSSY.burst_seconds * 1000, "jitter_ms": LOSSY.jitter * 1000},
              "seconds": round(len(test) / RATE, 1), "rms": {m: round(r["rms"], 5) for m, r in runs.items()},
              "best_predictor": best, "linear_vs_hold_ratio": round(runs["linear"]["rms"] / hold, 4),
              "sindy_vs_hold_ratio": round(runs["sindy"]["rms"] / hold, 4),
              "packets_lost": lossy["lost"], "packets_sent": lossy["packets"],
              "linear_vs_hold_ratio_real_takes": real if isinstance(real, str) else {
                  name: round(_simulate(motors, "linear", None)["rms"] / _simulate(motors, "hold", None)["rms"], 4)
                  for name, motors in real.items()},
              "longest_concealment_frames": lossy["longest"]}
    share = {"frames": states, "lost_frames_pct": round(100 * lossy["lost_frames"] / len(test), 2),
             "repeated_frames": lossy["repeated"], "payload_kbps_lossy": lossy["payload_kbps"],
             "by_method": {m: round(100 * (r["states"].get("concealed", 0) + r["states"].get("recovering", 0))
                                    / shown, 2) for m, r in runs.items()}}
    jump = round(max(r["jump"] for r in runs.values()), 4)
    outside = sum(r["outside"] for r in runs.values())
    return [Figure("stream.concealed_pct", 100 * (states.get("concealed", 0) + states.get("recovering", 0)) / shown,
                   "% of frames", 12.0, False, share),
            Figure("stream.concealment_vs_hold_ratio", runs[best]["rms"] / hold, "ratio", 0.8, False, detail),
            Figure("stream.out_of_range", float(outside), "values", 0.0, False,
                   {"shown_values": 21 * sum(sum(r["states"].values()) for r in runs.values())}),
            Figure("stream.lossy_latency_ms", lossy["latency_ms"], "ms", 45.0, False,
                   {"of": "the jitter buffer's delay, median over the lossy run"}),
            Figure("stream.jump_vs_own_speed", jump, "ratio", 1.0, False,
                   {"while": "concealing or recovering", "methods": list(runs),
                    "largest_jump": round(max(r["largest_jump"] for r in runs.values()), 4)})]


def _simulate(values: np.ndarray, method: str, forecaster) -> dict:
    """Send ``values`` through a simulated lossy network (virtual clock) and show them."""
    writer, reader = StreamWriter(RATE, first_sequence=0), StreamReader()
    forward, backward = FaultPlan(LOSSY, seed=1), FaultPlan(LOSSY, seed=2)
    playout = Playout(standard_neutral(), method, forecaster)
    arrivals: list[tuple[float, int, bytes]] = []
    requests: list[float] = []
    acks: list[tuple[float, tuple[int, int, bool] | tuple[int, int]]] = []
    states: dict[str, int] = {}
    received: set[int] = set()  # frames that arrived (in time or not)
    order, errors, jumps, longest, run, outside, delays = 0, [], [0.0], 0, 0, 0, []
    sent = quantise(values) / 100  # as the receiver gets them
    own, largest = np.maximum(np.abs(np.diff(sent, axis=0)).max(axis=0), 0.05), 0.0  # each motor's fastest step
    shown_before, state_before = None, "waiting"
    for index, row in enumerate(values):
        now = index / RATE
        while arrivals and arrivals[0][0] <= now:
            when, _, data = heapq.heappop(arrivals)
            for frames in reader.read(data, when):
                playout.add(frames)
                received.update(range(frames.first, frames.first + len(frames.values)))
            ack = reader.take_ack()
            if ack is not None:
                acks += [(back_when, read_ack(ack, None, writer.frame) or (0, 0))
                         for back_when, _ in backward.decide(ack, when)]
            if reader.want_keyframe and not requests and backward.decide(b"k", when):
                requests.append(when + LOSSY.delay)
        for back_when, frame in sorted(acks):
            if back_when <= now:
                writer.acknowledge(*frame)
        acks = [a for a in acks if a[0] > now]
        if requests and requests[0] <= now:
            writer.request_keyframe()
            requests.clear()
        datagram = writer.push(row, now)
        if datagram is not None:
            for when, data in forward.decide(datagram, now):
                heapq.heappush(arrivals, (when, order, data))
                order += 1
        shown, state = playout.values_at(now)
        states[state] = states.get(state, 0) + 1
        outside += int(np.count_nonzero((shown < 0.0) | (shown > 1.0)))
        if playout.delay is not None:
            delays.append(playout.delay)
        behind = ("concealed", "recovering")
        if shown_before is not None and (state in behind or state_before in behind):  # and the first frame back
            step = np.abs(shown - shown_before)
            jumps.append(float((step / own).max()))
            largest = max(largest, float(step.max()))
        if state in behind:
            truth = np.array([np.interp(playout.position, np.arange(len(values)), values[:, c]) for c in range(21)])
            errors.append(shown - truth)
            run += 1
            longest = max(longest, run)
        else:
            run = 0
        shown_before, state_before = shown, state
    rms = float(np.sqrt(np.mean(np.square(errors)))) if errors else 0.0
    seconds = len(values) / RATE
    lost_frames = len(values) - len(received)
    return {"rms": rms, "jump": max(jumps), "largest_jump": largest, "states": states, "lost": forward.counts["lost"],
            "longest": longest, "outside": outside, "packets": writer.packets, "repeated": writer.repeated_frames,
            "payload_kbps": round(writer.payload_bytes * 8 / seconds / 1000, 3), "lost_frames": lost_frames,
            "latency_ms": round(float(np.median(delays)) * 1000, 2)}
