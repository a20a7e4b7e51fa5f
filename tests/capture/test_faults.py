"""Synthetic capture faults: each switchable, seeded, and where it says it is."""

from __future__ import annotations

import numpy as np
import pytest

from capture import synthesize
from capture.faults import Faults, apply_faults


@pytest.fixture(scope="module")
def clean():
    return synthesize(seconds=4, rate=50, noise_mm=0.0).take


def test_no_faults_changes_nothing(clean):
    same, hit = apply_faults(clean, Faults())
    assert np.array_equal(same.positions, clean.positions) and not any(m.any() for m in hit.values())


def test_each_fault_lands_where_its_mask_says(clean):
    spiky, hit = apply_faults(clean, Faults(spike_rate=0.01, spike_mm=15.0), seed=1)
    moved = np.linalg.norm(spiky.positions - clean.positions, axis=2)
    assert hit["spike"].any() and np.allclose(moved[hit["spike"]], 15.0) and (moved[~hit["spike"]] == 0).all()
    assert spiky.meta["faults"] == {"spike_rate": 0.01, "spike_mm": 15.0}  # only what is switched on
    holey, hit = apply_faults(clean, Faults(gap_rate=0.5, gap_seconds=0.2), seed=2)
    assert np.array_equal(~holey.valid, hit["gap"]) and hit["gap"].sum() >= 10
    swapped, hit = apply_faults(clean, Faults(swap_rate=0.02, swap_frames=5), seed=3)
    changed = (swapped.positions != clean.positions).any(axis=2)
    assert hit["swap"].any() and np.array_equal(changed, hit["swap"])
    noisy, _ = apply_faults(clean, Faults(jitter_mm=0.5), seed=4)
    assert np.std(noisy.positions - clean.positions) == pytest.approx(0.5, rel=0.05)


def test_faults_are_seeded(clean):
    a, _ = apply_faults(clean, Faults(jitter_mm=1, gap_rate=0.2, drift_mm=2), seed=7)
    b, _ = apply_faults(clean, Faults(jitter_mm=1, gap_rate=0.2, drift_mm=2), seed=7)
    c, _ = apply_faults(clean, Faults(jitter_mm=1, gap_rate=0.2, drift_mm=2), seed=8)
    assert np.array_equal(a.positions, b.positions, equal_nan=True)
    assert not np.array_equal(a.positions, c.positions, equal_nan=True)


def test_synth_command_writes_a_faulty_take_beside_its_truth(tmp_path):
    from capture import load_take
    from toonface.cli import main

    out = tmp_path / "t.trc"
    assert main(["synth", "-o", str(out), "--seconds", "2", "--gaps", "1", "--seed", "3"]) == 0
    take = load_take(out)
    assert (~take.valid).sum() > 0 and (tmp_path / "t.truth.csv").is_file()
    assert main(["synth", "-o", str(tmp_path / "c.npz"), "--seconds", "2"]) == 0
    assert load_take(tmp_path / "c.npz").valid.all()
