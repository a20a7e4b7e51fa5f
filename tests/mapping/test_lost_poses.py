"""Stretches without a head pose in cleaning: carried across from the poses either side (as long
as a gap is filled), so that the face seen there is kept (:mod:`mapping.lost_poses`)."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from capture import Take, load_markerset, synthesize
from capture.performance import default_performance
from mapping.clean import clean_stabilised

#: Five of toon32's seven head references: too few left for a head fit.
FIVE_REFERENCES = ("TEMPLE_R", "TEMPLE_L", "NOSE_TIP", "EYE_R_IN", "EYE_L_IN")


def test_a_face_is_kept_through_half_a_second_with_too_few_head_references():
    """Five of the seven head references lost together for half a second leave no pose there; the pose is
    carried across from the fits either side, so the jaw that opens in that half second is
    seen (the markers there were all left to gap filling, which drew the jaw shut)."""
    syn = synthesize(rate=60.0, noise_mm=0.2, performance=default_performance(10, max_turn_deg=20), seed=2)
    ms = load_markerset("toon32")
    intact, _ = clean_stabilised(syn.take, ms)
    jaw = intact.local[:, syn.take.index("LIP_LOW"), 1]
    start = int(np.argmax([np.ptp(jaw[f:f + 30]) for f in range(60, len(jaw) - 90)])) + 60
    cut = syn.take.positions.copy()
    cut[start:start + 30, [syn.take.index(r) for r in FIVE_REFERENCES]] = np.nan
    stable, report = clean_stabilised(Take(cut, syn.take.labels, 60.0), ms)
    assert report.bridged == 30 and report.no_head_frames == 0 and stable.ok.all()
    assert "head pose carried across 30 frames" in report.summary()
    ours = np.abs(stable.local[start:start + 30, syn.take.index("LIP_LOW"), 1] - jaw[start:start + 30]).max()
    seen = np.r_[0:start, start + 30:len(jaw)]
    spline = np.abs(CubicSpline(syn.take.times[seen], jaw[seen])(syn.take.times[start:start + 30])
                    - jaw[start:start + 30]).max()
    assert ours < 1.5 < 5.0 < spline and np.ptp(jaw[start:start + 30]) > 5.0, (ours, spline)


@pytest.mark.parametrize("seconds", [1.5, 2.5])
def test_a_pose_is_carried_across_as_long_as_a_gap_is_filled_and_no_longer(seconds):
    """A stretch without a head pose is bridged as long as gap filling fills a gap (2 s by
    default). At 1 s the fourth performer's forehead, lost for 1.3 s while a temple was turned
    away, left the whole face to one spline per marker across it, which swung raised brows to
    fully lowered; a longer stretch stays without a pose, as a longer gap stays unfilled."""
    syn = synthesize(rate=60.0, noise_mm=0.2, performance=default_performance(12, max_turn_deg=20), seed=2)
    ms = load_markerset("toon32")
    intact, _ = clean_stabilised(syn.take, ms)
    frames = int(round(seconds * 60.0))
    jaw = intact.local[:, syn.take.index("LIP_LOW"), 1]
    start = int(np.argmax([np.ptp(jaw[f:f + frames]) for f in range(60, len(jaw) - frames - 60)])) + 60
    cut = syn.take.positions.copy()
    cut[start:start + frames, [syn.take.index(r) for r in FIVE_REFERENCES]] = np.nan
    stable, report = clean_stabilised(Take(cut, syn.take.labels, 60.0), ms)
    lost = slice(start, start + frames)
    if seconds < 2.0:
        assert report.bridged == frames and report.no_head_frames == 0 and stable.ok.all()
        ours = np.abs(stable.local[lost, syn.take.index("LIP_LOW"), 1] - jaw[lost]).max()
        assert ours < 1.5 < 5.0 < np.ptp(jaw[lost]), ours
    else:
        assert report.bridged == 0 and report.no_head_frames == frames
        assert np.isnan(stable.local[lost, syn.take.index("LIP_LOW")]).all()
