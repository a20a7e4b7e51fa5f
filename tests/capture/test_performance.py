"""The synthetic performer's script: cues, the calibration segment, script files and their errors."""

import re

import numpy as np
import pytest

from capture import synthesize
from capture.performance import (
    CALIBRATION_GROUPS,
    CODES,
    NEUTRAL,
    Cue,
    Performance,
    default_performance,
    load_performance,
    load_poses,
    perform,
)
from common import InputError

RATE = 100.0


def _motors(performance: Performance) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    times = np.arange(int(round(performance.seconds * RATE))) / RATE
    m = perform(performance, times)
    return times, {c: m[:, i] for i, c in enumerate(CODES)}


def test_an_expression_cue_reaches_its_pose_and_leaves_other_motors_at_neutral():
    poses = load_poses()
    _, m = _motors(Performance(3.0, (Cue("expression", 0.5, 2.0, name="surprise"),)))
    middle = int(1.5 * RATE)
    for code in CODES:
        expected = poses["surprise"].get(code, NEUTRAL[code])
        assert m[code][middle] == pytest.approx(expected), code
        assert m[code][0] == NEUTRAL[code] and m[code][-1] == pytest.approx(NEUTRAL[code])


def test_strength_scales_the_way_to_the_pose():
    _, m = _motors(Performance(3.0, (Cue("expression", 0.5, 2.0, name="happiness", strength=0.5),)))
    target = load_poses()["happiness"]["MLV"]
    assert m["MLV"][150] == pytest.approx(NEUTRAL["MLV"] + 0.5 * (target - NEUTRAL["MLV"]))


def test_blink_closes_both_eyes_wink_only_the_left():
    _, m = _motors(Performance(2.0, (Cue("blink", 0.2, 0.2), Cue("wink", 1.0, 0.5))))
    blink, wink = slice(0, 60), slice(80, 200)
    assert m["ERU"][blink].min() < 0.01 and m["ELU"][blink].min() < 0.01
    assert m["ELU"][wink].min() < 0.01 and m["ERU"][wink].min() == pytest.approx(NEUTRAL["ERU"])


def test_gaze_and_turn_reach_their_targets():
    cues = (Cue("gaze", 0.2, 1.0, x=-0.5, y=1.0), Cue("turn", 0.2, 1.0, yaw=24.0, pitch=-12.0))
    _, m = _motors(Performance(1.5, cues))
    assert m["PRH"][70] == pytest.approx(0.5 - 0.45 * 0.5) and m["PLH"][70] == m["PRH"][70]
    assert m["PRV"][70] == pytest.approx(0.9)
    assert m["HH"][70] == pytest.approx(0.9) and m["HV"][70] == pytest.approx(0.3)


def test_talking_opens_the_jaw_at_syllable_rate():
    times, m = _motors(Performance(3.0, (Cue("talk", 0.5, 2.0),)))
    jaw = m["MB"][int(0.75 * RATE):int(2.25 * RATE)]
    peaks = np.sum((jaw[1:-1] > jaw[:-2]) & (jaw[1:-1] >= jaw[2:]) & (jaw[1:-1] > NEUTRAL["MB"] + 0.2))
    assert 4 <= peaks <= 8  # 1.5 s at 3.5-4.5 Hz
    assert jaw.max() > 0.5 and jaw.min() < NEUTRAL["MB"] + 0.05


def test_calibration_segment_holds_neutral_then_takes_each_group_to_its_extremes():
    cue = Cue("calibrate", 0.0, hold=1.0, step=1.0)
    times, m = _motors(Performance(cue.end, (cue,)))
    hold = times < 1.0
    for code in CODES:
        assert (m[code][hold] == NEUTRAL[code]).all()
    for g, group in enumerate(CALIBRATION_GROUPS):
        inside = (times >= 1.0 + g) & (times < 2.0 + g)
        for code in CODES:
            span = (m[code][inside].min(), m[code][inside].max())
            assert span == ((0.0, 1.0) if code in group else (NEUTRAL[code], NEUTRAL[code])), (g, code)
    assert cue.end == 1.0 + len(CALIBRATION_GROUPS)


def test_calibration_overrides_other_cues_while_it_lasts():
    cal = Cue("calibrate", 0.0, hold=1.0, step=0.5)
    _, m = _motors(Performance(cal.end + 1, (cal, Cue("blink", 0.3, 0.4), Cue("talk", 0.0, cal.end + 1))))
    assert (m["ERU"][:100] == NEUTRAL["ERU"]).all() and (m["MB"][:100] == NEUTRAL["MB"]).all()
    assert m["MB"][int((cal.end + 0.5) * RATE)] != NEUTRAL["MB"]  # talking goes on afterwards


def test_default_performance_is_seeded_and_keeps_turns_within_the_limit():
    a, b, c = default_performance(20, seed=1), default_performance(20, seed=1), default_performance(20, seed=2)
    assert a == b and a != c
    times = np.arange(2000) / RATE
    for limit in (30.0, 12.0):
        m = perform(default_performance(20, max_turn_deg=limit), times)
        yaw = (m[:, CODES.index("HH")] - 0.5) * 60
        assert limit * 0.6 <= np.abs(yaw).max() <= limit + 1e-9
    with pytest.raises(InputError, match="max turn must be 0-30 degrees"):
        default_performance(10, max_turn_deg=45)


def test_default_performance_acts_the_requested_expressions_in_turn():
    perf = default_performance(12, expressions=("anger", "fear"), calibration=True)
    assert perf.cues[0].kind == "calibrate" and perf.seconds == pytest.approx(perf.cues[0].end + 12)
    acted = [c.name or c.kind for c in sorted(perf.cues, key=lambda c: c.start) if c.kind in ("expression", "talk")]
    assert acted[:4] == ["anger", "fear", "talk", "anger"]
    assert {c.kind for c in perf.cues} == {"calibrate", "expression", "talk", "blink", "gaze", "turn"}


def test_a_synthetic_take_spans_its_performance():
    syn = synthesize(rate=30.0, noise_mm=0.0, performance=default_performance(3, calibration=True))
    assert syn.take.frames == round((1.0 + 1.2 * len(CALIBRATION_GROUPS) + 3) * 30)
    assert "calibrate" in syn.take.meta["cues"]


def test_a_script_file_reads_into_cues(tmp_path):
    path = tmp_path / "script.toml"
    path.write_text('format = "toonface.performance/1"\nseconds = 4\nseed = 3\n'
                    '[[cue]]\nkind = "expression"\nname = "anger"\nstart = 1\nseconds = 2\nstrength = 0.7\n'
                    '[[cue]]\nkind = "blink"\nstart = 0.5\n'
                    '[[cue]]\nkind = "turn"\nstart = 2\nyaw = -30\npitch = 10\n')
    perf = load_performance(path)
    assert perf == Performance(4.0, (Cue("expression", 1.0, 2.0, name="anger", strength=0.7),
                                     Cue("blink", 0.5, 0.2), Cue("turn", 2.0, 1.0, yaw=-30.0, pitch=10.0)), 3)


@pytest.mark.parametrize("body, message", [
    ('format = "x"\nseconds = 2', "format: unsupported format 'x'"),
    ('format = "toonface.performance/1"', "seconds: missing"),
    ('format = "toonface.performance/1"\nseconds = -1', "seconds: expected a number of at least 0, got -1"),
    ('format = "toonface.performance/1"\nseconds = 2\n[[cue]]\nkind = "dance"\nstart = 0',
     "cue[0].kind: expected one of"),
    ('format = "toonface.performance/1"\nseconds = 2\n[[cue]]\nkind = "turn"\nstart = 0\nyaw = 45',
     "cue[0].yaw: expected a number from -30 to 30, got 45"),
    ('format = "toonface.performance/1"\nseconds = 2\n[[cue]]\nkind = "gaze"\nstart = 0\ncolour = 1',
     "cue[0].colour: unknown field (known: "),
    ('format = "toonface.performance/1"\nseconds = 2\n[[cue]]\nkind = "expression"\nstart = 0',
     "cue[0].name: an expression cue needs a name"),
    ('format = "toonface.performance/1"\nseconds = 2\n[[cue]]\nkind = "talk"\nstart = "soon"',
     "cue[0].start: expected a number of at least 0, got 'soon'"),
])
def test_bad_script_files_name_the_field(tmp_path, body, message):
    path = tmp_path / "bad.toml"
    path.write_text(body)
    with pytest.raises(InputError, match=re.escape(message)) as info:
        load_performance(path)
    assert str(path) in str(info.value)


def test_an_unknown_expression_is_refused_when_performed():
    with pytest.raises(InputError, match='no expression "smirk" in the repertoire'):
        perform(Performance(1.0, (Cue("expression", 0.0, name="smirk"),)), np.arange(10) / 10)
