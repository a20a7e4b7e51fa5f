"""Mapping fidelity on two synthetic performers, ours beside a plain peer, in one run.

Each performer's take is calibrated the documented way (neutral from its first second, range
from its range-of-motion sweep), mapped by the toon32 preset onto a face whose rest is the
performer's own (the pipeline maps a performer's rest onto the face's: measured on a face with
another rest, the convention itself would count as error), and scored after the sweep against
the true motors:

``fidelity.motor_rmse_pct`` / ``fidelity.second_rmse_pct``
    RMSE, % of the motors' 0..1 (goal 2.5; 2 on the project's own performer, as before).
``fidelity.motor_fitted_pct`` / ``fidelity.second_fitted_pct``
    The same with each motor's gain and offset fitted away (goal 2).
``fidelity.motor_min_r`` / ``fidelity.second_min_r``
    The lowest correlation of a motor with its truth (goal 0.95).
``fidelity.motor_vs_peer_ratio`` / ``fidelity.second_vs_peer_ratio``
    Our RMSE over the plain peer's (:mod:`bench.peer`; goal below 1), the peer's own scores in
    the detail.
``fidelity.second_head_range_error``
    How far HV's travel is from its truth's, as a share of it (the second performer's pitch
    range is ±20°, its HV's 0..1; goal 0.05).

The project's own performer is :mod:`capture.synthetic` with 0.3 mm jitter, 10 % dropout, 0.5 s
gaps, spikes and ±20° turns; the second is :mod:`bench.second_performer`, designed apart.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bench.core import Figure
from bench.peer import plain_pipeline, scores
from bench.second_performer import REST_SECONDS, SWEEP_END, perform
from capture import Take, synthesize
from capture.faults import Faults, apply_faults
from capture.performance import CALIBRATION_GROUPS, default_performance
from mapping import calibrate, choose_mapping, map_stabilised, prepare
from toon import MOTOR_CODES, standard_neutral
from toonface import truth_track

OWN_SWEEP_END = 1.0 + 1.2 * len(CALIBRATION_GROUPS)  # the own performer's calibration segment


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the figures of both performers."""
    seconds = 6.0 if quick else 20.0
    return [*_figures("motor", *_own(seconds), raw_goal=2.0), *_figures("second", *_second(seconds))]


def _own(seconds: float) -> tuple[Take, np.ndarray, np.ndarray, float, dict[str, Any]]:
    syn = synthesize(rate=60.0, noise_mm=0.3, seed=1,
                     performance=default_performance(seconds, calibration=True, max_turn_deg=20))
    take, _ = apply_faults(syn.take, Faults(gap_rate=0.1, gap_seconds=0.5, spike_rate=0.01), seed=1)
    positions = take.positions.copy()
    positions[np.random.default_rng(1).random(positions.shape[:2]) < 0.10] = np.nan  # 10 % dropout
    take = Take(positions, take.labels, take.rate, times=take.times, meta=take.meta)
    return take, truth_track(syn).values, standard_neutral(), OWN_SWEEP_END, {
        "performer": "capture.synthetic: 0.3 mm jitter, 10 % dropout, 0.5 s gaps, 1 % spikes, +-20 deg turns"}


def _second(seconds: float) -> tuple[Take, np.ndarray, np.ndarray, float, dict[str, Any]]:
    second = perform(seconds=seconds)
    return second.take, second.motors, second.rest, SWEEP_END, {
        "performer": "bench.second_performer: curved, coupled paths, its own face, rest and head pivot"}


def _figures(prefix: str, take: Take, truth: np.ndarray, rest: np.ndarray, sweep_end: float,
             about: dict[str, Any], raw_goal: float = 2.5) -> list[Figure]:
    mapping, markerset = choose_mapping(take)
    prepared = prepare(take, markerset)
    profile = calibrate(mapping, prepared, (0.0, REST_SECONDS), range_window=(REST_SECONDS, sweep_end))
    ours = map_stabilised(prepared.stable, prepared.columns, take.times, take.rate, mapping, profile, rest,
                          filled=prepared.stable.filled).values
    peer = plain_pipeline(take, mapping, markerset, (0.0, REST_SECONDS), (REST_SECONDS, sweep_end))
    after = take.times >= sweep_end
    mine, theirs = scores(ours[after], truth[after]), scores(peer[after], truth[after])
    detail = {**about, "seconds_after_sweep": round(float(take.times[-1] - sweep_end), 2),
              "per_motor_pct": mine["per_motor_pct"], "r": mine["r"]}
    peer_detail = {"peer_rmse_pct": round(theirs["raw_pct"], 3), "peer_fitted_pct": round(theirs["fitted_pct"], 3),
                   "peer_min_r": min(theirs["r"].values()), "peer_per_motor_pct": theirs["per_motor_pct"]}
    figures = [Figure(f"fidelity.{prefix}_rmse_pct", mine["raw_pct"], "%", raw_goal, False, detail),
               Figure(f"fidelity.{prefix}_fitted_pct", mine["fitted_pct"], "%", 2.0, False, {}),
               Figure(f"fidelity.{prefix}_min_r", min(mine["r"].values()), "r", 0.95, True,
                      {"motor": min(mine["r"], key=lambda k: mine["r"][k])}),
               Figure(f"fidelity.{prefix}_vs_peer_ratio", mine["raw_pct"] / theirs["raw_pct"], "ratio", 1.0, False,
                      peer_detail)]
    if prefix == "second":
        hv = MOTOR_CODES.index("HV")
        ratio = float(np.ptp(ours[after, hv]) / np.ptp(truth[after, hv]))
        figures.append(Figure("fidelity.second_head_range_error", abs(ratio - 1.0), "share", 0.05, False,
                              {"travel_ratio": round(ratio, 4), "truth": "HV 0..1 is +-20 deg of pitch"}))
    return figures
