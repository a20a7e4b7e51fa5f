"""Gap filling against a spline and against the published PCA method, on real facial and body takes.

Gaps of 4 frames, 250, 500 and 1000 ms are cut at random (seeded) where a marker was seen, in
the real facial takes (``../shared/realdata/facial/animface/``, the jaw and brow takes) and in
real full-body trials (the C3D format's gait sample, a Vicon Nexus trial, a dance and a
walking demo from ``../shared/realdata/c3d/``), and filled three ways: ours
(:class:`mapping.gaps.GapFiller`), a cubic spline through the marker's own samples, and
Gløersen & Federolf's R2 (:mod:`bench.r2`). The error of a cut is the mean distance to the
marker's true positions over the gap; a figure is one mean error over another's, on the same
cuts:

``fidelity.gapfill_<len>_ratio``
    Ours over the spline's, facial takes (goal 1 at 4 frames and 250 ms, 0.5 from 500 ms).
``fidelity.gapfill_body_250ms_ratio``
    The same on the body trials (goal 1).
``fidelity.gapfill_<face|body>_<len>_vs_r2``
    Ours over R2's (goal 1).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline

from bench.core import REALDATA, Figure
from bench.r2 import fill_r2
from capture import Take, load_take
from mapping.gaps import GapFiller

FACE = (("facial/animface/JawMoCap.csv", "cm"), ("facial/animface/EyebrowsMoCap.csv", "cm"))
BODY = (("c3d/c3d.org-sample01/Eb015pi.c3d", None), ("c3d/vicon/Vicon.c3d", None),
        ("c3d/c3d.org-sample13/Dance.c3d", None), ("c3d/others/ADemo1_rewrite_c3d_pc_float.c3d", None))
LENGTHS = (("4frames", None), ("250ms", 0.25), ("500ms", 0.5), ("1000ms", 1.0))


def run(quick: bool = False) -> list[Figure]:
    """Measure and return the gap-filling figures (none where the real takes are absent)."""
    face, body = _takes(FACE), _takes(BODY)
    figures: list[Figure] = []
    for label, seconds in LENGTHS:
        if face:
            errors = _errors(face, seconds, trials=5 if quick else 30, with_r2=seconds is not None)
            goal = 1.0 if seconds is None or seconds < 0.5 else 0.5
            figures.append(_ratio(f"fidelity.gapfill_{label}_ratio", errors, "spline", goal, "animface jaw + brows"))
            if seconds is not None:
                figures.append(_ratio(f"fidelity.gapfill_face_{label}_vs_r2", errors, "r2", 1.0,
                                      "animface jaw + brows"))
        if body and seconds is not None:
            errors = _errors(body, seconds, trials=3 if quick else 15, with_r2=True)
            if label == "250ms":
                figures.append(_ratio("fidelity.gapfill_body_250ms_ratio", errors, "spline", 1.0, "body C3D trials"))
            figures.append(_ratio(f"fidelity.gapfill_body_{label}_vs_r2", errors, "r2", 1.0, "body C3D trials"))
    return figures


def _takes(files: tuple[tuple[str, str | None], ...]) -> list[Take]:
    """The takes present, without frames where most markers are missing (R2 needs complete markers)."""
    takes = []
    for name, units in files:
        path = REALDATA / name
        if not path.exists():
            continue
        take = load_take(path, units=units) if units else load_take(path)
        keep = take.valid.mean(axis=1) > 0.5
        takes.append(Take(take.positions[keep], take.labels, take.rate, times=take.times[keep], meta=take.meta))
    return takes


def _errors(takes: list[Take], seconds: float | None, trials: int, with_r2: bool) -> dict[str, list[float]]:
    """Mean error per cut of each method, ``trials`` cuts per take."""
    rng = np.random.default_rng(0)
    errors: dict[str, list[float]] = {"ours": [], "spline": [], "r2": []}
    for take in takes:
        n = 4 if seconds is None else int(round(seconds * take.rate))
        for _ in range(trials):
            for _attempt in range(200):  # a marker seen around the cut
                m, start = int(rng.integers(take.markers)), int(rng.integers(10, take.frames - n - 10))
                if take.valid[start - 5:start + n + 5, m].all():
                    break
            cut = take.positions.copy()
            cut[start:start + n, m] = np.nan
            truth = take.positions[start:start + n, m]
            seen = np.isfinite(cut[:, m, 0])
            spline = CubicSpline(take.times[seen], cut[seen, m], axis=0)(take.times[start:start + n])
            errors["ours"].append(_error(GapFiller().apply(cut, take.times).positions[start:start + n, m], truth))
            errors["spline"].append(_error(spline, truth))
            if with_r2:
                errors["r2"].append(_error(fill_r2(cut)[start:start + n, m], truth))
    return errors


def _error(estimate: np.ndarray, truth: np.ndarray) -> float:
    return float(np.linalg.norm(estimate - truth, axis=1).mean())


def _ratio(name: str, errors: dict[str, list[float]], peer: str, goal: float, takes: str) -> Figure:
    ours, theirs = float(np.nanmean(errors["ours"])), float(np.nanmean(errors[peer]))
    return Figure(name, ours / theirs, "ratio", goal, False,
                  {"cuts": len(errors["ours"]), "mean_error_mm": round(ours, 4),
                   f"{peer}_mean_error_mm": round(theirs, 4),
                   "takes": takes})
