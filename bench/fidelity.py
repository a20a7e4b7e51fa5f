"""``fidelity``: how faithfully cleaning and mapping follow the performer.

``fidelity.step_lag_frames``: the live One Euro filter (min_cutoff 1 Hz, beta 0.5, mm at 60 Hz)
on three moving markers of the synthetic performer with 0.3 mm jitter; the delay, in whole
frames, that best aligns its output with the clean motion (goal 1).
``fidelity.still_jitter_reduction_x``: the same filter on a still marker: raw jitter over
filtered jitter (no goal; reported beside the lag).
``fidelity.gapfill_*``: gaps cut from real facial and body takes, ours against a spline and
against Gløersen & Federolf's R2 (:mod:`bench.gapfill`).
``fidelity.motor_*`` and ``fidelity.second_*``: mapping fidelity on the project's own synthetic
performer and on a second one designed apart, beside a plain peer (:mod:`bench.generators`).
``fidelity.clean_map_fps``: clean + map of a 120 Hz toon32 take, frames per second on one core
(goal 100 000, issue 65), in a process whose allocator keeps freed memory as the ``toonface`` command's does
(:mod:`common.memory`); beside it, ``default_allocator_fps``: the same with glibc's defaults.
That take has no gaps; ``fidelity.gapfill_fps`` is gap filling alone (:class:`mapping.gaps.GapFiller`)
on the second performer's 60 Hz take with 10 % of its samples in 0.5 s gaps, frames per second
on one core (the median of three runs; goal 2000, issue 65: an hour of 120 Hz cleaned in under 4
minutes; ``real_time_x`` in the detail says how it compares with the take's own rate).
"""

from __future__ import annotations

import numpy as np

from bench import gapfill, generators
from bench.core import Figure, median_rate, one_core
from bench.pipeline import pinned_rate
from bench.second_performer import perform
from capture import synthesize
from capture.performance import default_performance
from mapping.filters import OneEuro
from mapping.gaps import GapFiller
from mapping.reference_bridge import fade_frames
from mapping.stepwise import LIVE_BETA, LIVE_MIN_CUTOFF

LIVE = {"min_cutoff": LIVE_MIN_CUTOFF, "beta": LIVE_BETA}  # the live sender's marker filter


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``fidelity.*`` figures."""
    return [*_live_filter(), *gapfill.run(quick), *generators.run(quick), _throughput(quick), _fill_rate(quick),
            _solve_rate(quick)]


def _solve_rate(quick: bool) -> Figure:
    """``fidelity.solve_fps``: frames per second of the sweep-taught solver alone (every motor of
    every frame at once, :meth:`mapping.solver.Solver.solve`) on a 120 Hz toon32 take."""
    from mapping import calibrate, choose_mapping, prepare
    from mapping.mapper import marker_quality

    syn = synthesize(rate=120.0, noise_mm=0.3, seed=3,
                     performance=default_performance(6.0 if quick else 20.0, calibration=True, seed=3))
    mapping, markerset = choose_mapping(syn.take)
    prepared = prepare(syn.take, markerset)
    profile = calibrate(mapping, prepared, (0.0, 1.0), range_window=(1.0, generators.OWN_SWEEP_END), solve=True)
    solver, stable = profile.solver, prepared.stable
    assert solver is not None, "the sweep taught no solver"
    quality = marker_quality(stable.local, stable.filled)
    trust, fade = (quality > 0).astype(float), fade_frames(syn.take.rate)
    with one_core() as pinned:
        fps, runs = median_rate(lambda: len(solver.solve(stable.local, prepared.columns, trust, quality, fade)[0]),
                                1 if quick else 5, warmup=1)
    return Figure("fidelity.solve_fps", fps, "frames/s", 20_000.0, True,
                  {"frames": len(stable.local), "rate_hz": 120.0, "motors": len(solver.codes),
                   "markers": len(solver.markers), "one_core": pinned, "runs": [round(r, 1) for r in runs]})


def _fill_rate(quick: bool) -> Figure:
    """``fidelity.gapfill_fps``: frames per second of gap filling alone on the second performer."""
    take = perform(seconds=6.0 if quick else 20.0, seed=7).take
    filled = np.mean(np.isnan(take.positions).any(axis=2))
    with one_core() as pinned:
        fps, runs = median_rate(lambda: len(GapFiller().apply(take.positions, take.times).positions),
                                1 if quick else 3, warmup=0)
    return Figure("fidelity.gapfill_fps", fps, "frames/s", 2000.0, True,
                  {"frames": take.frames, "rate_hz": take.rate, "real_time_x": round(fps / take.rate, 1),
                   "one_core": pinned,
                   "runs": [round(r, 1) for r in runs], "missing_share": round(float(filled), 3),
                   "take": "bench.second_performer seed 7"})


def _live_filter() -> list[Figure]:
    syn = synthesize(rate=60.0, noise_mm=0.0, performance=default_performance(20, max_turn_deg=0))
    labels = syn.take.labels
    cols = [labels.index(m) for m in ("LIP_LOW", "BROW_R_CEN", "LID_R_UP")]
    clean = syn.take.positions[:, cols, 1]
    rng = np.random.default_rng(0)
    noisy = clean + rng.normal(0.0, 0.3, clean.shape)
    out = OneEuro(**LIVE, rate=60.0).apply(noisy, syn.take.times)
    lags = [min(range(10), key=lambda k: float(np.mean((out[60 + k:, i] - clean[60:len(clean) - k, i]) ** 2)))
            for i in range(clean.shape[1])]
    still = 5.0 + rng.normal(0.0, 0.3, (1200, 1))
    calm = OneEuro(**LIVE, rate=60.0).apply(still, np.arange(1200) / 60.0)
    detail = {"filter": "one-euro", **LIVE, "rate": 60, "jitter_mm": 0.3,
              "markers": ["LIP_LOW", "BROW_R_CEN", "LID_R_UP"], "lags": lags}
    return [Figure("fidelity.step_lag_frames", float(max(lags)), "frames", 1.0, False, detail),
            Figure("fidelity.still_jitter_reduction_x", float(still[60:].std() / calm[60:].std()), "x", None, True,
                   detail)]


def _throughput(quick: bool) -> Figure:
    seconds, repeats = (10.0 if quick else 30.0), (3 if quick else 5)
    measured = pinned_rate(seconds, repeats, 120.0)
    plain = pinned_rate(seconds, repeats, 120.0, keep_freed=False)
    return Figure("fidelity.clean_map_fps", measured["fps"], "frames/s", 100_000.0, True,
                  {"frames": measured["frames"], "rate_hz": 120.0, "markerset": "toon32", "runs": measured["runs"],
                   "one_core": measured["one_core"], "kept_freed_memory": measured["kept_freed_memory"],
                   "default_allocator_fps": round(plain["fps"], 1)})
