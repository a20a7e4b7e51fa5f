"""``predict``: guessing motor values 50 and 100 ms ahead (what hides a lost packet).

For each motion and horizon, ``predict.<motion>_<ms>ms_sindy_vs_hold_ratio``: the RMS error of
pysindy's sparse motion model (:class:`mapping.predict.MotionModel`) over the RMS error of holding
the last value (goal 1: it earns its place only below 1); constant velocity's ratio is in the
detail. Motions: the synthetic performer's true motors (60 s at 60 Hz) and the real AnimFace jaw
and brow takes mapped by their preset; each model is fitted on the first 60 % of its motion and
measured on the rest, on the mapped motors only.
"""

from __future__ import annotations

import numpy as np

from bench.core import REALDATA, Figure
from capture import load_take, synthesize
from capture.performance import default_performance
from mapping import map_take
from mapping.predict import MotionModel, forecast
from toon import MotorTrack, motor_index
from toonface import truth_track


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the ``predict.*`` figures."""
    syn = synthesize(rate=60.0, noise_mm=0.3, performance=default_performance(20 if quick else 60, max_turn_deg=20))
    motions = {"synthetic": truth_track(syn)}
    folder = REALDATA / "facial" / "animface"
    for name, file in (("jaw", "JawMoCap.csv"), ("brows", "EyebrowsMoCap.csv")):
        if (folder / file).exists():
            motions[name] = map_take(load_take(folder / file, units="cm"))
    figures = []
    for name, track in motions.items():
        figures += _measure(name, track)
    return figures


def _measure(name: str, track: MotorTrack) -> list[Figure]:
    cols = [motor_index(c) for c in track.meta.get("mapped", [])] or list(range(track.values.shape[1]))
    values, times = track.values[:, cols], track.times
    split = int(0.6 * len(values))
    model = MotionModel().fit(values[:split], times[:split])
    test, test_times = values[split:], times[split:]
    figures = []
    for ms in (50, 100):
        ahead = int(round(ms / 1000 * track.rate))
        error = {method: float(np.sqrt(np.mean((forecast(test, test_times, ms / 1000, method, model)[:-ahead]
                                                 - test[ahead:]) ** 2)))
                 for method in ("hold", "velocity", "sindy")}
        detail = {"frames_tested": len(test) - ahead, "motors": len(cols),
                  "rms_error": {k: round(v, 5) for k, v in error.items()},
                  "velocity_vs_hold_ratio": round(error["velocity"] / error["hold"], 4)}
        figures.append(Figure(f"predict.{name}_{ms}ms_sindy_vs_hold_ratio", error["sindy"] / error["hold"], "ratio",
                              1.0, False, detail))
    return figures
