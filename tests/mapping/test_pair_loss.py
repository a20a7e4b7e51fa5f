"""toon32's lids and pupils follow the other eye's while their own marker is lost (loss policy
``pair``): a blink or a glance behind a lost marker is not lost with it."""

import numpy as np

from capture import Take, synthesize
from capture.performance import Cue, Performance
from mapping import calibrate, choose_mapping, map_stabilised, prepare
from toon import MOTOR_CODES


def _mapped(take: Take) -> tuple[np.ndarray, np.ndarray]:
    mapping, markerset = choose_mapping(take)
    prepared = prepare(take, markerset)
    values = map_stabilised(prepared.stable, prepared.columns, take.times, take.rate, mapping,
                            calibrate(mapping, prepared, (0.0, 1.0))).values
    return values, prepared.stable.local


def test_a_blink_and_a_glance_while_one_eyes_markers_are_lost_show_on_both_eyes():
    """The left upper lid's and pupil's markers are lost for 2.5 s (longer than gap filling fills,
    as a fourth-performer draw lost its left lid over a blink): the left eye blinks and glances as
    it did with its markers seen, where before it eased to rest and missed both."""
    cues = (Cue("blink", 2.5, 0.25), Cue("gaze", 3.0, 1.0, x=0.8, y=-0.6))
    syn = synthesize(seconds=6.0, rate=60.0, noise_mm=0.0, performance=Performance(6.0, cues), seed=4)
    positions = syn.take.positions.copy()
    lost = (syn.take.times >= 1.8) & (syn.take.times < 4.3)
    for label in ("LID_L_UP", "PUPIL_L"):
        positions[lost, syn.take.index(label)] = np.nan
    seen, _ = _mapped(syn.take)
    values, local = _mapped(Take(positions, syn.take.labels, syn.take.rate, times=syn.take.times))
    assert np.isnan(local[lost, syn.take.index("LID_L_UP")]).all()  # too long a gap to fill
    for code in ("ELU", "PLH", "PLV"):
        j = MOTOR_CODES.index(code)
        moved = np.abs(seen[lost, j] - seen[0, j]).max()
        missed = np.abs(values[lost, j] - seen[lost, j]).max()
        assert moved > 0.05 and missed < 0.1 * moved, (code, moved, missed)
