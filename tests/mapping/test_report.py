"""The report every mapped take ends with: what was chosen (units, rest, profile), each motor's
frames pinned at its bounds and range used, and every warning; for map, retarget and batch."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from capture import Take, load_markerset, save_take, synthesize
from mapping import calibrate, choose_mapping, map_take, prepare
from mapping.report import TakeReport, take_report
from mapping.workflow import map_ready, ready_take
from toon import MOTOR_CODES, MotorTrack, motor_index, standard_neutral
from toonface.cli import main


def test_shares_are_counted_and_a_motor_pinned_away_from_its_rest_is_a_warning():
    """Counted by hand on a made-up track: MB at 1 in 30 of 100 frames, BRL at 0 in 50, ERU
    at 1 in 20 (ERU rests at 0.8: pinned at a bound it does not rest at)."""
    syn = synthesize(seconds=2.0, seed=2)
    ready = ready_take(syn.take)
    values = np.tile(standard_neutral(), (100, 1))
    values[:30, motor_index("MB")] = 1.0
    values[:50, motor_index("BRL")] = 0.0
    values[:20, motor_index("ERU")] = 1.0
    values[20:25, motor_index("ERL")] = 0.0  # 5 %: not a warning
    track = MotorTrack(values, 30.0, meta={"mapped": list(MOTOR_CODES)})
    rest = standard_neutral().copy()
    rest[motor_index("BRL")] = 0.02  # BRL rests at its bottom here: pinned there is its rest
    report = take_report(ready, track, rest)
    assert report.motors["MB"] == {"at_0": 0.0, "at_1": 0.3, "range_used": pytest.approx(0.9)}
    assert report.motors["BRL"]["at_0"] == 0.5 and report.motors["ERL"]["at_0"] == 0.05
    pinned = [w for w in report.warnings if "pinned" in w]
    assert [w.split()[0] for w in pinned] == ["ERU", "MB"]
    assert pinned[1].startswith("MB is pinned at 1 (its top) in 30% of the frames, and rests at 0.10")


def test_a_profile_narrower_than_the_take_pins_motors_and_says_so():
    """A profile whose range is the rest second alone: the take's expressions go past it."""
    syn = synthesize(seconds=12.0, seed=3)
    mapping, markerset = choose_mapping(syn.take)
    narrow = calibrate(mapping, prepare(syn.take, markerset), (0.0, 1.0), range_window=(0.0, 1.0),
                       require_motion=False)
    ready = ready_take(syn.take, profile=narrow)
    track = map_ready(ready)
    report = TakeReport.from_dict(track.meta["report"])
    assert report.profile == "calibrated on a range of motion" and report.rest.startswith("the profile's")
    flagged = {w.split()[0] for w in report.warnings if "pinned" in w}
    by_hand = {c for c in track.meta["mapped"]
               if max(np.mean(track.column(c) <= 0.005) * (standard_neutral()[motor_index(c)] > 0.05),
                      np.mean(track.column(c) >= 0.995) * (standard_neutral()[motor_index(c)] < 0.95)) > 0.1}
    assert flagged == by_hand and "MB" in flagged


def test_map_prints_the_report_and_json_gives_it_as_data(realdata, tmp_path, capsys):
    path = realdata / "facial" / "animface" / "JawMoCap.csv"
    assert main(["map", str(path), "-o", str(tmp_path / "m.csv")]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("wrote ")
    lines = captured.err.splitlines()
    assert lines[0] == "report for JawMoCap.csv:"
    assert lines[1].startswith("  units: cm (inferred; as read, shape 0.1")
    assert lines[2].startswith("  rest: 0-1 s (first second with the head seen")
    assert lines[3] == ("  profile: from the take itself (1st-99th percentiles), each side at least a typical "
                        "face's (x1.00)")
    assert any(" MLH " in line for line in lines)
    assert main(["map", str(path), "-o", str(tmp_path / "m.csv"), "--json"]) == 0
    captured = capsys.readouterr()
    doc = json.loads(captured.out)
    assert doc["units"]["unit"] == "cm" and doc["units"]["from"] == "inferred"
    assert set(doc["motors"]) == {c for c in MOTOR_CODES if c not in ("PLH", "PLV", "PRH", "PRV")}
    assert doc["motors"]["MB"]["range_used"] > 0.8  # the jaw take opens the mouth wide
    assert captured.err.startswith("wrote ")


def test_retarget_ends_with_the_same_report_as_map(tmp_path, capsys):
    """retarget printed none of map's warnings and notes."""
    syn = synthesize(seconds=1.5, seed=4).take
    save_take(Take(syn.positions / 10.0, syn.labels, syn.rate), tmp_path / "cm.npz")  # a file in the wrong units
    assert main(["map", str(tmp_path / "cm.npz"), "-o", str(tmp_path / "m.csv")]) == 0
    mapped = capsys.readouterr().err.splitlines()
    assert main(["retarget", str(tmp_path / "cm.npz"), "-o", str(tmp_path / "v.mp4"), "--size", "48"]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith(f"wrote {tmp_path / 'v.mp4'} (45 frames, 48x48)")
    reported = [line for line in captured.err.splitlines() if not line.startswith("render")]
    assert reported == mapped
    assert any(line.startswith("  warning: units: cm.npz read in the units its file states") for line in reported)


def test_the_markerset_drafted_with_one_marker_says_one_marker(tmp_path, capsys):
    take = synthesize(seconds=1.0, seed=1).take
    positions = np.full_like(take.positions, np.nan)
    positions[:, 0] = take.positions[:, 0]
    save_take(replace(take, positions=positions), tmp_path / "t.npz")
    assert main(["markerset", "draft", str(tmp_path / "t.npz"), "-o", str(tmp_path / "m.toml")]) == 2
    assert "only 1 marker is ever seen" in capsys.readouterr().err


def test_a_toon32_take_has_units_from_its_file_and_nothing_to_warn(tmp_path):
    syn = synthesize(seconds=4.0, seed=6)
    report = TakeReport.from_dict(map_ready(ready_take(syn.take)).meta["report"])
    assert report.units.startswith("mm (file; shape 1") and not report.warnings
    assert report.profile == f"typical for {load_markerset('toon32').name} (built in)"


def test_a_squint_on_a_layout_without_a_typical_profile_is_not_a_shut_eye(realdata):
    """A take's own extremes were its motors' ends: upper lids that narrow by 5 mm in a smile
    (a typical face closes them by 11) shut the cartoon's eyes. Bounded by a typical face's
    range, and said so."""
    from capture import load_take
    from mapping import map_take

    take = load_take(realdata / "facial" / "animface" / "JawMoCap.csv", units="cm")
    take = take.part(*take.times[[340, 980]])  # between its blinks (which say where its lids shut)
    positions = take.positions.copy()
    squint = slice(300, 400)
    for lid in ("Reye_Up", "Leye_Up"):  # the recording's axes are the head frame's: y is up
        positions[squint, take.index(lid), 1] -= 5.0
    track = map_take(replace(take, positions=positions))
    eru = track.column("ERU")
    assert eru[squint].min() > 0.3 and np.median(eru[squint]) < eru[:250].mean() - 0.2  # narrowed, not shut
    assert any("widened to a typical face's" in n and "Reye_Up.y" in n for n in track.meta["notes"])


def test_the_blinks_a_take_shows_shut_the_cartoons_eyes(realdata):
    """The jaw take's performer blinks four times, the lid markers dipping 1.6-5 mm; widened to a
    typical face's 10 mm the blinks rendered as squints (the lids at 0.46-0.63 of 0.80, issue
    69). Its own blinks now say where its lids shut."""
    from capture import load_take
    from mapping import map_take

    track = map_take(load_take(realdata / "facial" / "animface" / "JawMoCap.csv", units="cm"))
    for code in ("ERU", "ELU"):
        lid = track.column(code)
        deepest = [float(lid[max(f - 10, 0):f + 10].min()) for f in (59, 323, 999, 1568)]  # its blinks' frames
        assert max(deepest) <= 0.15, (code, deepest)
        assert np.median(lid) > 0.75  # open between them
    told = next(n for n in track.meta["notes"] if n.startswith("lids shut where the take's own blinks"))
    assert "Reye_Up.y" in told and "Leye_Up.y" in told and "4 blinks" in told


def test_the_report_names_a_motor_that_no_seen_marker_drove_for_a_second_or_more():
    """The left outer brow's marker hidden for 1.5 s of 8 (19 %): BLL is named with that stretch;
    the right one's hidden for 0.5 s is not (a short gap filled from its neighbours is no news)."""
    take = synthesize(seconds=8.0, rate=60.0, noise_mm=0.0, seed=5).take
    positions = take.positions.copy()
    positions[(take.times >= 3.0) & (take.times < 4.5), take.index("BROW_L_LAT")] = np.nan
    positions[(take.times >= 6.0) & (take.times < 6.5), take.index("BROW_R_LAT")] = np.nan
    track = map_take(Take(positions, take.labels, take.rate, times=take.times))
    said = [n for n in track.meta["report"]["notes"] if n.startswith("no seen marker drove these for 1 s")]
    assert len(said) == 1 and said[0].endswith(": BLL 1.5 s at 3.0 s (19%)"), track.meta["report"]["notes"]
    full = map_take(take).meta["report"]["notes"]
    assert not [n for n in full if n.startswith("no seen marker")], full
    mapping, _ = choose_mapping(take)  # played at half speed: the stretch is still said in the take's seconds
    slow = replace(mapping, style=replace(mapping.style, time_scale=2.0))
    notes = map_take(Take(positions, take.labels, take.rate, times=take.times), slow).meta["report"]["notes"]
    assert [n for n in notes if n.startswith("no seen marker")][0].endswith(": BLL 1.5 s at 3.0 s (19%)"), notes
