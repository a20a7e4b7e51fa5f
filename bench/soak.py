"""``soak``: the motor stream for ten minutes through a faulty relay on loopback (its own group,
so that the default bench run stays short: ``python -m bench soak``).

The synthetic performer is mapped live and sent at 60 Hz through :class:`stream.relay.Relay`
(5 % loss, 50 ms bursts, 2 % reordered, 2 % duplicated, 1 % corrupted, 1 ms delay and 5 ms of
jitter, both ways) to a receiver whose face is drawn 60 times a second, all in this process;
after the stream ends the receiver goes on drawing for 30 s.

``stream.soak_rss_mb_per_h``: the process's resident memory, sampled every 10 s, its least-
squares slope after a 2-minute warm-up, the 30 s after the stream included (goal 1 MB an hour).
``stream.soak_latency_ms``: the highest median latency of any 10 s window of the stream (goal
45, the stream's latency goal, throughout). ``stream.soak_sender_p99_ms``: the sender's live
mapping and coding per frame, 99th percentile over the run (goal one frame period, 16.7 ms);
the process has the machine's cores to itself, but shares them with the relay and the receiver.
"""

from __future__ import annotations

import os
import threading
import time

import numpy as np

from bench.core import Figure
from capture.sources import paced, synthetic_source
from stream.packets import StreamWriter
from stream.playout import Playout
from stream.receiver import StreamReceiver
from stream.relay import NetworkFaults, Relay
from stream.sender import StreamSender
from toon import standard_neutral
from toonface.send import build_mapper

RATE = 60.0
FAULTS = NetworkFaults(loss=0.05, burst_seconds=0.05, bursts_per_second=0.5, duplicate=0.02, corrupt=0.01,
                       reorder=0.02, delay=0.001, jitter=0.005)
SAMPLE_SECONDS = 10.0


def run(quick: bool = False) -> list[Figure]:
    """Soak for 10 minutes (1 with ``quick``) and return the ``stream.soak_*`` figures."""
    seconds, after, warm = (60.0, 10.0, 20.0) if quick else (600.0, 30.0, 120.0)
    source = synthetic_source(seconds=seconds + 1.0, rate=RATE)
    mapper = build_mapper(source)
    # all preallocated or a few values a window, so that the bench does not grow the memory it measures
    samples: list[tuple[float, float]] = []  # (seconds since start, resident MB)
    medians: list[float] = []  # ms, one a window
    window = np.full(int(SAMPLE_SECONDS * RATE * 2), np.nan)
    steps = np.full(int((seconds + 1) * RATE), np.nan)
    stop = threading.Event()
    start = time.perf_counter()
    with StreamReceiver(("127.0.0.1", 0), Playout(standard_neutral())) as receiver, \
            Relay(("127.0.0.1", 0), receiver.address, FAULTS, seed=3) as relay:
        def view() -> None:
            next_sample, filled = 0.0, 0
            while not stop.wait(1 / RATE):
                receiver.values_at()
                latency = receiver.playout.latency()
                if latency is not None and filled < len(window) and not stop.is_set():
                    window[filled] = latency
                    filled += 1
                elapsed = time.perf_counter() - start
                if elapsed >= next_sample:
                    samples.append((elapsed, _resident_mb()))
                    if filled > RATE and elapsed <= seconds:  # a whole window of stream
                        medians.append(float(np.median(window[:filled])) * 1000)
                    filled = 0
                    next_sample += SAMPLE_SECONDS

        viewer = threading.Thread(target=view, daemon=True)
        viewer.start()
        sender = StreamSender(relay.address, StreamWriter(RATE))
        frames = 0
        for frame in paced(source, time.perf_counter, time.sleep):
            if frame.t >= seconds:
                break
            began = time.perf_counter()
            values, _ = mapper.step(frame.positions, frame.t, frame.channels)
            sender.write(frames / RATE, values, began)
            steps[frames] = time.perf_counter() - began
            frames += 1
        rates = sender.rates(frames)
        sender.close()
        time.sleep(after)
        stop.set()
        viewer.join()
        summary = receiver.summary()
    t, mb = np.array(samples).T
    late = t >= warm
    slope = float(np.polyfit(t[late] / 3600, mb[late], 1)[0]) if late.sum() >= 3 else float("nan")
    steps = steps[:frames]
    detail = {"seconds": seconds, "after_seconds": after, "warm_up_seconds": warm, "faults": FAULTS.__dict__,
              "rss_mb": [round(float(x), 2) for x in mb], "sender": rates, "receiver": summary,
              "relay": {"forward": relay.forward.counts, "backward": relay.backward.counts}}
    return [Figure("stream.soak_rss_mb_per_h", slope, "MB/h", 1.0, False, detail),
            Figure("stream.soak_latency_ms", max(medians), "ms", 45.0, False,
                   {"window_medians_ms": [round(m, 1) for m in medians]}),
            Figure("stream.soak_sender_p99_ms", float(np.percentile(steps, 99)) * 1000, "ms", 1000 / RATE, False,
                   {"median_ms": round(float(np.median(steps)) * 1000, 3), "frames": frames,
                    "cores": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None})]


def _resident_mb() -> float:
    """This process's resident memory, MB (Linux; NaN elsewhere)."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6
    except OSError:
        return float("nan")
