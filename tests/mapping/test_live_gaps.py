"""Live gap filling: a lost marker regressed on the markers seen now, learned on the last seconds
(mapping.live_gaps)."""

import numpy as np
import pytest

from capture import load_markerset
from mapping import load_mapping
from mapping.live_gaps import REGRESS_SECONDS, LiveGapFiller
from mapping.profile import Profile
from mapping.stepwise import LiveMapper

RATE = 120.0


def _moving(seconds: float = 14.0, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Times ``(F,)`` and eight head-frame markers ``(F, 8, 3)`` that one smooth motion moves, each
    along its own direction by its own amount (a mouth opening), 10-40 mm apart, with 0.05 mm of
    seeded jitter; and the markers without it ``(F, 8, 3)``."""
    rng = np.random.default_rng(seed)
    times = np.arange(int(seconds * RATE)) / RATE
    motion = 3.0 * np.sin(2 * np.pi * 0.4 * times) + 2.0 * np.sin(2 * np.pi * 1.1 * times + 1.0)  # mm
    base = rng.uniform(-20.0, 20.0, (8, 3))
    way = rng.normal(0.0, 1.0, (8, 3))
    way /= np.linalg.norm(way, axis=1, keepdims=True)
    truth = base[None] + motion[:, None, None] * way[None] * rng.uniform(0.5, 1.5, 8)[None, :, None]
    return times, truth + rng.normal(0.0, 0.05, truth.shape), truth


def _run(filler: LiveGapFiller, times: np.ndarray, seen: np.ndarray, lost: dict[int, float]
         ) -> tuple[np.ndarray, np.ndarray]:
    """Each frame's filled markers ``(F, 8, 3)`` and which were filled ``(F, 8)``, the markers in
    ``lost`` unseen from that many seconds on."""
    out, filled = np.empty_like(seen), np.zeros(seen.shape[:2], dtype=bool)
    for k, t in enumerate(times):
        frame = seen[k].copy()
        for m, start in lost.items():
            if t >= start:
                frame[m] = np.nan
        out[k], filled[k] = filler.step(frame, float(t))
    return out, filled


def test_a_lost_marker_follows_the_others_motion_and_is_lost_after_two_seconds():
    """Marker 0 lost from 11 s to the end: regressed on the other seven, it is within 0.3 mm of
    where it went for two seconds (held, it would be more than 4 mm off at worst), then lost;
    marker 1, not regressed, is held for half a second, then lost."""
    times, seen, truth = _moving()
    filler = LiveGapFiller(8, RATE, regressed=[0, 2, 3, 4, 5, 6, 7], hold_seconds=0.5)
    out, filled = _run(filler, times, seen, {0: 11.0, 1: 11.0})
    gap = (times >= 11.0) & (times < 11.0 + REGRESS_SECONDS - 1e-9)
    assert filled[gap, 0].all() and not filled[times >= 11.0 + REGRESS_SECONDS + 1e-9, 0].any()
    assert np.isnan(out[times >= 11.0 + REGRESS_SECONDS + 1e-9, 0]).all()
    assert np.linalg.norm(out[gap, 0] - truth[gap, 0], axis=1).max() < 0.3
    held_at = seen[np.flatnonzero(times < 11.0)[-1], 0]
    assert np.linalg.norm(held_at - truth[gap, 0], axis=1).max() > 4.0  # what holding would have given
    last = np.flatnonzero(times < 11.0)[-1]  # the frame each was last seen
    held = (times >= 11.0) & (times - times[last] <= 0.5)
    assert held.sum() == 60 and filled[held, 1].all() and not filled[times - times[last] > 0.5, 1].any()
    np.testing.assert_array_equal(out[held, 1], np.broadcast_to(seen[last, 1], (60, 3)))
    np.testing.assert_array_equal(out[times < 11.0], seen[times < 11.0])  # what was seen stays as it was


def test_a_predictor_lost_in_turn_refits_on_those_left_and_too_little_past_holds():
    """Marker 0 lost at 11 s and marker 2 at 11.5 s: from then on marker 0 is regressed on the six
    left, still within 0.3 mm. Lost 0.3 s into the stream (36 frames to learn from, under 60), a
    marker is held as it was last seen."""
    times, seen, truth = _moving(seed=1)
    out, _ = _run(LiveGapFiller(8, RATE, regressed=range(8)), times, seen, {0: 11.0, 2: 11.5})
    late = (times >= 11.5) & (times < 13.0)
    assert np.linalg.norm(out[late, 0] - truth[late, 0], axis=1).max() < 0.3
    early = times < 0.6
    out, filled = _run(LiveGapFiller(8, RATE, regressed=range(8)), times[early], seen[early], {0: 0.3})
    lost = times[early] >= 0.3
    assert filled[lost, 0].all()
    np.testing.assert_array_equal(out[lost, 0], np.broadcast_to(seen[np.flatnonzero(~lost)[-1], 0], (lost.sum(), 3)))


def test_reset_forgets_what_was_learned_and_no_regression_holds_alone():
    """After :meth:`reset` (a new head frame) nothing is learned: a lost marker is held; with
    ``regress_seconds`` 0 every lost marker is held, as the live mapper did before."""
    times, seen, _ = _moving(seed=2)
    filler = LiveGapFiller(8, RATE, regressed=range(8))
    _run(filler, times[:1200], seen[:1200], {})
    filler.reset()
    frame = seen[1200].copy()
    filler.step(frame, float(times[1200]))
    frame = seen[1201].copy()
    frame[0] = np.nan
    out, filled = filler.step(frame, float(times[1201]))
    assert filled[0] and np.array_equal(out[0], seen[1200, 0])
    out, filled = _run(LiveGapFiller(8, RATE, regressed=range(8), regress_seconds=0.0), times, seen, {0: 11.0})
    last = np.flatnonzero(times < 11.0)[-1]
    held = (times >= 11.0) & (times - times[last] <= 0.5)
    assert filled[held, 0].all() and not filled[times - times[last] > 0.5, 0].any()
    np.testing.assert_array_equal(out[held, 0], np.broadcast_to(seen[last, 0], (held.sum(), 3)))


def test_the_live_mapper_regresses_only_markers_no_pair_rule_reads():
    """toon32: the brows', lids' and pupils' markers (their motors follow the other side's once
    lost) are held; the mouth's and cheeks' are regressed; the pupils apart."""
    markerset = load_markerset("toon32")
    labels = tuple(markerset.labels)
    mapper = LiveMapper(load_mapping("toon32"), markerset, Profile("toon32", {}, np.eye(3)), labels, RATE,
                        rest_seconds=1.0, learn_seconds=5.0)
    regressed = {labels[c] for c in mapper.gaps.regressed}
    assert {"LIP_LOW", "MOUTH_L", "CHIN", "CHEEK_R"} <= regressed
    assert not regressed & {"BROW_L_LAT", "LID_R_UP", "LID_L_LOW", "PUPIL_L"}
    assert {labels[c] for c in mapper.gaps.apart} == {"PUPIL_L", "PUPIL_R"}


@pytest.mark.parametrize("rate", [30.0, 240.0])
def test_the_window_is_ten_seconds_at_any_rate(rate):
    assert LiveGapFiller(3, rate, ()).rows == int(10 * rate)


class _Counted(LiveGapFiller):
    """A filler that counts its regressions fitted afresh."""

    fits = 0

    def _fit(self, *args):  # type: ignore[no-untyped-def]
        self.fits += 1
        return super()._fit(*args)


def test_a_marker_lost_again_within_a_second_reuses_its_fit_and_a_brief_dropout_of_a_predictor_is_not_fitted_around():
    """Marker 0 lost at 11 s for 0.3 s, and again from 11.6 s: the second gap reuses the first's
    fit (one fit, not two), its miss measured afresh, within 0.3 mm throughout; lost again 1.4 s
    after the fit, it is fitted anew. Predictor 2 lost for one frame at 11.1 s (a spike taken out)
    is read where it was last seen: no fit more, still within 0.3 mm."""
    times, seen, truth = _moving(seed=3)
    gaps = ((times >= 11.0) & (times < 11.3)) | ((times >= 11.6) & (times < 12.0)) | (times >= 12.4)
    frames = seen.copy()
    frames[gaps, 0] = np.nan
    frames[np.flatnonzero(times >= 11.1)[0], 2] = np.nan
    filler = _Counted(8, RATE, regressed=[0])  # marker 2 only held: no fit of its own
    out, filled = _run(filler, times[times < 12.2], frames[times < 12.2], {})
    early = gaps[times < 12.2]
    assert filler.fits == 1 and filled[early, 0].all()
    assert np.linalg.norm(out[early, 0] - truth[times < 12.2][early, 0], axis=1).max() < 0.3
    _run(filler, times[times >= 12.2], frames[times >= 12.2], {})
    assert filler.fits == 2
