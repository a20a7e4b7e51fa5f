"""Mapping a take onto the motors: calibration, the preset mappings, confidence and loss."""

import numpy as np
import pytest

from capture import Take, synthesize
from capture.performance import default_performance
from common import InputError, data_path
from mapping import CleanSettings, calibrate, choose_mapping, load_profile, map_take, prepare, save_profile
from toon import MOTOR_CODES, motor_index, standard_neutral
from toonface import truth_track

EXACT = CleanSettings(spikes=False, max_gap_seconds=2.0, cutoff_hz=0.0)


def _calibrated(seconds=6.0, rate=30.0, noise=0.0, turn=20.0, settings=EXACT):
    syn = synthesize(rate=rate, noise_mm=noise, seed=2,
                     performance=default_performance(seconds, calibration=True, max_turn_deg=turn))
    mapping, markerset = choose_mapping(syn.take)
    profile = calibrate(mapping, prepare(syn.take, markerset, settings), (0.0, 1.0), range_window=(1.0, 15.4))
    return syn, mapping, profile


def test_a_noiseless_take_calibrated_on_its_calibration_segment_maps_exactly():
    syn, mapping, profile = _calibrated()
    assert mapping.name == "toon32"
    track = map_take(syn.take, mapping, profile, settings=EXACT)
    error = np.abs(track.values - truth_track(syn).values)
    assert error.max() < 1e-6, f"worst motor {MOTOR_CODES[np.argmax(error.max(0))]}: {error.max():.2e}"
    assert (track.confidence == 1).all()
    # the profile holds each source's rest and range: the upper lid travels 14 mm per unit from 0.8
    lid = profile.sources["LID_R_UP.y"]
    assert lid.high - lid.neutral == pytest.approx(14 * 0.2) and lid.neutral - lid.low == pytest.approx(14 * 0.8)


def test_profile_round_trips_and_bad_profiles_name_the_field(tmp_path):
    _, _, profile = _calibrated(seconds=2.0)
    path = save_profile(profile, tmp_path / "p.toml")
    again = load_profile(path)
    assert again.sources == profile.sources and np.allclose(again.rest_rotation, profile.rest_rotation)
    text = path.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('format = "toonface.profile/1"', 'format = "x"'))
    with pytest.raises(InputError, match="bad.toml: format: unsupported format"):
        load_profile(bad)
    start = text.index("[sources.")
    bad.write_text(text[:start] + '[sources."LID_R_UP.y"]\nneutral = 1.0\nlow = 2.0\nhigh = 3.0\n')
    with pytest.raises(InputError, match=r'sources."LID_R_UP.y": expected low <= neutral <= high'):
        load_profile(bad)


def test_calibration_that_cannot_be_made_says_why():
    syn = synthesize(seconds=2, noise_mm=0.0)
    mapping, markerset = choose_mapping(syn.take)
    pos = syn.take.positions.copy()
    for ref in markerset.head_reference[2:]:  # two left
        pos[:, syn.take.index(ref)] = np.nan
    with pytest.raises(InputError, match="cannot remove head motion: fewer than 3 head reference markers"):
        prepare(Take(pos, syn.take.labels, syn.take.rate), markerset)
    still = Take(np.repeat(syn.take.positions[:1], 60, axis=0), syn.take.labels, 30.0)
    with pytest.raises(InputError, match="cannot calibrate: no motion"):
        calibrate(mapping, prepare(still, markerset))
    with pytest.raises(InputError, match="no frames in the range window 5-6 s"):
        calibrate(mapping, prepare(syn.take, markerset), (0.0, 1.0), range_window=(5.0, 6.0))


def test_lost_markers_lower_confidence_and_ease_to_neutral():
    """A mouth corner's marker (toon32's lids, pupils and brows follow the other side's instead:
    test_pair_loss.py)."""
    syn, mapping, profile = _calibrated(seconds=8.0)
    pos = syn.take.positions.copy()
    corner = syn.take.index("MOUTH_R")
    start = int(17 * 30)
    pos[start:start + 9, corner] = np.nan  # 0.3 s: filled
    pos[start + 60:start + 150, corner] = np.nan  # 3 s: too long to fill, lost
    track = map_take(Take(pos, syn.take.labels, 30.0), mapping, profile, settings=EXACT)
    mrh = motor_index("MRH")
    assert (track.confidence[start:start + 9, mrh] == 0.5).all()
    lost = track.confidence[start + 60:start + 150, mrh]
    assert (lost == 0).all() and track.confidence[start - 5, mrh] == 1
    # ease to neutral over half a second, then stay there
    assert track.values[start + 60 + 15:start + 150, mrh] == pytest.approx(standard_neutral()[mrh])
    assert track.meta["lost_frames"] == 90


@pytest.mark.slow
def test_fidelity_on_a_faulty_take_is_close_to_the_truth():
    syn, mapping, _ = _calibrated(seconds=6.0, rate=60.0, noise=0.3, settings=CleanSettings())
    rng = np.random.default_rng(0)
    pos = syn.take.positions.copy()
    pos[rng.random(pos.shape[:2]) < 0.10] = np.nan
    take = Take(pos, syn.take.labels, 60.0)
    profile = calibrate(mapping, prepare(take, choose_mapping(take)[1]), (0.0, 1.0), range_window=(1.0, 15.4))
    error = map_take(take, mapping, profile).values - truth_track(syn).values
    assert np.sqrt(np.mean(error ** 2)) < 0.025


def test_the_preset_is_chosen_by_the_takes_markers_and_an_unknown_layout_is_refused():
    syn = synthesize(seconds=1, noise_mm=0.0)
    odd = Take(syn.take.positions, tuple(f"M{i}" for i in range(syn.take.markers)), 30.0)
    with pytest.raises(InputError, match="no built-in mapping matches"):
        choose_mapping(odd)
    few = Take(syn.take.positions[:, :20], syn.take.labels[:20], 30.0)
    mapping, _ = choose_mapping(few, "toon32")  # a partial rig: what it lacks is left out and said (test_no_pupils)
    assert {"MRH", "MB", "PLH"} <= set(mapping.left_out) and "PRH" not in mapping.left_out
    assert "MOUTH_R" in mapping.absent


@pytest.mark.parametrize("name, kwargs, brows, jaw", [
    ("animface/EyebrowsMoCap.csv", {"units": "cm"}, True, False),
    ("animface/JawMoCap.csv", {"units": "cm"}, False, True),
    ("gluedots/Subject_01.csv", {"rate": 30, "units": "184.84"}, True, True),
])
def test_real_facial_takes_drive_their_brows_and_jaw(realdata, name, kwargs, brows, jaw):
    from capture import load_take
    take = load_take(realdata / "facial" / name, **kwargs)
    track = map_take(take, neutral_window=None)
    spread = {code: np.percentile(track.column(code), 95) - np.percentile(track.column(code), 5)
              for code in MOTOR_CODES}
    if brows:
        assert min(spread[c] for c in ("BRM", "BRC", "BLM", "BLC")) > 0.2
    if jaw:
        assert spread["MB"] > 0.3
    unmapped = [c for c in MOTOR_CODES if c not in track.meta["mapped"]]
    assert all(spread[c] == 0 for c in unmapped)
    if name.startswith("gluedots"):  # the posed neutral (rows 800-985), said as a person reads it: not 26.6667
        assert track.meta["report"]["rest"].startswith("26.667-27.667 s (first second with the head seen")


def test_the_rest_window_is_the_first_second_with_the_head_seen_or_the_stillest():
    from mapping.workflow import rest_window
    syn = synthesize(seconds=6, noise_mm=0.0, performance=default_performance(6, max_turn_deg=0))
    pos = syn.take.positions.copy()
    pos[:45] = np.nan  # nothing seen for 1.5 s
    _, markerset = choose_mapping(syn.take)
    prepared = prepare(Take(pos, syn.take.labels, 30.0), markerset)
    assert rest_window(prepared, "first") == ((1.5, 2.5), "first second with the head seen")
    assert rest_window(prepared, None) == ((1.5, 2.5), "first second with the head seen, as still and typical as any")
    assert rest_window(prepared, (3.0, 4.0)) == ((3.0, 4.0), "given")
    (start, end), how = rest_window(prepared, "stillest")
    motion = np.linalg.norm(np.diff(prepared.stable.local, axis=0), axis=2).mean(axis=1)  # NaN before 1.5 s
    per_second = [motion[f:f + 30].mean() for f in range(45, len(motion) - 29)]
    assert how == "stillest second" and round(start * 30) == 45 + int(np.argmin(per_second))
    with pytest.raises(InputError, match='"first" or "stillest"'):
        rest_window(prepared, "middle")


def test_a_feature_that_does_not_move_in_the_calibration_keeps_a_range(realdata, tmp_path, capsys):
    """Calibrating the eyebrow take on itself stretched the mouth's 1-3 mm of drift to its full range."""
    from capture import load_take
    from mapping import load_profile
    from toonface.cli import main

    path = realdata / "facial" / "animface" / "EyebrowsMoCap.csv"
    assert main(["calibrate", str(path), "--units", "cm", "-o", str(tmp_path / "p.toml")]) == 0
    err = capsys.readouterr().err
    assert "not moving over the range frames (under 4 mm (1 mm for lids and pupils" in err and "Mouth_Lend.y" in err
    profile = load_profile(tmp_path / "p.toml")
    assert "Mouth_Lend.y" in profile.notes["no_motion"] and "Leyebrow_M.y" not in profile.notes["no_motion"]
    corner = profile.sources["Mouth_Lend.y"]
    assert corner.high - corner.neutral >= 10 - 1e-9 and corner.neutral - corner.low >= 10 - 1e-9  # floats round
    track = map_take(load_take(path, units="cm"), profile=profile)
    spread = {c: np.percentile(track.column(c), 95) - np.percentile(track.column(c), 5) for c in MOTOR_CODES}
    assert max(spread[c] for c in ("MLH", "MLV", "MRH", "MRV")) < 0.2  # they were 0.73-0.84
    assert min(spread[c] for c in ("BRC", "BRM", "BLC", "BLM")) > 0.9  # the brows still act in full


def test_a_profile_for_another_marker_set_names_both_files(tmp_path, capsys):
    """It said 'the profile is for marker set animface41, the mapping for toon32', naming no file."""
    from capture import save_take
    from toonface.cli import main

    save_take(synthesize(seconds=2, noise_mm=0.0).take, tmp_path / "t.npz")
    other = tmp_path / "animface.toml"
    other.write_text(data_path("profiles", "toon32.toml").read_text().replace('markerset = "toon32"',
                                                                            'markerset = "animface41"'))
    assert main(["map", str(tmp_path / "t.npz"), "-o", str(tmp_path / "m.csv"), "--profile", str(other)]) == 2
    err = capsys.readouterr().err
    assert f"the profile {other} is for marker set animface41, but the built-in mapping toon32 reads marker set " \
           "toon32" in err


def test_a_marker_lost_through_the_neutral_window_is_named_when_calibrating():
    """A profile-normalised motor's marker unseen for the whole rest window has no rest: calibrate
    says which marker, which motor and what to do, instead of failing later in mapping."""
    syn = synthesize(seconds=4.0, seed=0)
    positions = syn.take.positions.copy()
    positions[syn.take.times < 1.2, syn.take.labels.index("BROW_L_CEN")] = np.nan
    take = Take(positions, syn.take.labels, syn.take.rate, times=syn.take.times)
    mapping, markerset = choose_mapping(take)
    with pytest.raises(InputError, match=r"marker BROW_L_CEN is not seen in the neutral window 0-1 s \(motors BLC"):
        calibrate(mapping, prepare(take, markerset), (0.0, 1.0), range_window=(1.0, 4.0))
