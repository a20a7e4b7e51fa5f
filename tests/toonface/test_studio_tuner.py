"""The studio's mapping tuner without a browser: edits re-map the take, and what it saves maps
the take exactly as `toonface map` does with those files."""

import os
from pathlib import Path

import numpy as np
import pytest
from studios import temp_folder

from capture import save_take, synthesize
from common import InputError
from toon import load_track, motor_index
from toonface.cli import main
from toonface.studio.guard import Folder
from toonface.studio.messages import apply
from toonface.studio.session import StudioSession


@pytest.fixture
def take(tmp_path):
    return save_take(synthesize(seconds=4.0, rate=60.0).take, tmp_path / "take.npz")


def test_tuning_remaps_and_the_saved_files_map_as_the_command_does(take, tmp_path):
    session = StudioSession("classic", folder=temp_folder())
    said = apply(session, {"op": "tune", "action": "open", "take": str(take)}, 0.0)[1]
    assert said.startswith("tuning toon32") and session.showing == "tune"
    tuner = session.tuner
    before = tuner.track.values[:, motor_index("MB")].copy()
    apply(session, {"op": "tune", "action": "rule", "code": "MB", "field": "gain", "value": 1.6}, 0.0)
    after = tuner.track.values[:, motor_index("MB")]
    rest = session.neutral[motor_index("MB")]
    assert np.abs(after - rest).max() > np.abs(before - rest).max()  # exaggerated
    key = tuner.describe()["sources"]["BRC"][0]
    neutral, low, high = tuner.ready.profile.sources[key].neutral, tuner.ready.profile.sources[key].low, \
        tuner.ready.profile.sources[key].high
    apply(session, {"op": "tune", "action": "range", "key": key, "neutral": neutral, "low": low,
                    "high": neutral + (high - neutral) / 2}, 0.0)  # half the range: the brow moves twice as far
    mapping, profile = tmp_path / "tuned.toml", tmp_path / "me.toml"
    for action, path in (("save_mapping", mapping), ("save_profile", profile)):
        assert apply(session, {"op": "tune", "action": action, "path": str(path)}, 0.0)[1] == f"wrote {path}"
    out = tmp_path / "motors.csv"
    assert main(["map", str(take), "-o", str(out), "--mapping", str(mapping), "--profile", str(profile),
                 "--face", "classic"]) == 0
    np.testing.assert_allclose(load_track(out).values, tuner.track.values, atol=1e-6)  # the CSV keeps 6 decimals


def test_a_bad_tuning_is_refused_and_the_take_keeps_playing(take):
    session = StudioSession("classic", folder=temp_folder())
    apply(session, {"op": "tune", "action": "open", "take": str(take)}, 10.0)
    tuner = session.tuner
    track = tuner.track
    with pytest.raises(InputError, match=r"motor\.MB\.clamp"):
        apply(session, {"op": "tune", "action": "rule", "code": "MB", "field": "clamp", "value": "wobbly"}, 10.0)
    with pytest.raises(ValueError, match="does not drive 'XX'"):
        apply(session, {"op": "tune", "action": "motor", "code": "XX"}, 10.0)
    with pytest.raises(ValueError, match="low <= neutral <= high"):
        apply(session, {"op": "tune", "action": "range", "key": "CHIN.y", "neutral": 0, "low": 1, "high": 2}, 10.0)
    assert tuner.track is track
    session.tick(11.5)
    assert session.values == pytest.approx(tuner.values_at(1.5))
    apply(session, {"op": "tune", "action": "pause"}, 11.5)
    session.tick(13.0)
    assert session.values == pytest.approx(tuner.values_at(1.5)) and not session.busy()


def test_the_sources_are_shown_as_measured_in_millimetres_and_degrees(tmp_path):
    from capture import load_take
    from common import read_document, resolve_builtin, write_toml

    take = save_take(synthesize(seconds=4.0, rate=60.0, noise_mm=0.0).take, tmp_path / "still.npz")
    doc = read_document(resolve_builtin("toon32", "mappings", ".toml", "mapping"))
    doc["motor"]["MB"]["sources"] = [{"distance": ["LIP_UP", "LIP_LOW"]}]
    doc["motor"]["MB"].pop("combine", None)
    mapping = write_toml(doc, tmp_path / "distance.toml")
    session = StudioSession("classic", folder=temp_folder())
    apply(session, {"op": "tune", "action": "open", "take": str(take), "mapping": str(mapping)}, 0.0)
    apply(session, {"op": "tune", "action": "motor", "code": "MB"}, 0.0)
    curve = session.tuner.describe("MB")["curve"]
    key = "distance(LIP_UP,LIP_LOW)"
    assert curve["units"] == {key: "mm"}
    # a distance does not depend on how the head is held: measured here straight from the file's markers
    recorded = load_take(take)
    up, low = recorded.labels.index("LIP_UP"), recorded.labels.index("LIP_LOW")
    direct = np.linalg.norm(recorded.positions[:, up] - recorded.positions[:, low], axis=1)
    at = np.round(np.array(curve["times"]) * recorded.rate).astype(int)
    # within what cleaning's zero-phase low-pass (mapping/clean.py) takes off the fastest jaw motion
    np.testing.assert_allclose(curve["raw"][key], direct[at], atol=0.3)
    assert 5 < np.ptp(direct) < 60  # millimetres of jaw travel, not centimetres or metres
    apply(session, {"op": "tune", "action": "motor", "code": "HH"}, 0.0)
    assert session.tuner.describe("HH")["curve"]["units"] == {"head.yaw": "°"}


@pytest.mark.slow
def test_a_talking_head_video_is_tracked_and_tuned_and_maps_as_its_tracked_take(realdata, tmp_path):
    video = realdata / "video" / "grid" / "bbaf2n.mpg"
    if not video.is_file():
        pytest.skip(f"{video} is absent")
    both = Path(os.path.commonpath([video.resolve(), tmp_path.resolve()]))  # the studio works where both are
    session = StudioSession("classic", folder=Folder(both))
    said = apply(session, {"op": "tune", "action": "open", "take": str(video)}, 0.0)[1]
    assert said.startswith("tuning face on") and session.tuner.duration == pytest.approx(3.0)
    tuner = session.tuner
    assert "MB" in tuner.describe()["motors"]
    mb = tuner.track.values[:, motor_index("MB")]
    assert np.ptp(mb) > 0.2  # the speaker's jaw moves
    apply(session, {"op": "tune", "action": "rule", "code": "MB", "field": "gain", "value": 1.5}, 0.0)
    mapping, profile = tmp_path / "video.toml", tmp_path / "speaker.toml"
    for action, path in (("save_mapping", mapping), ("save_profile", profile)):
        apply(session, {"op": "tune", "action": action, "path": str(path)}, 0.0)
    take, out = tmp_path / "speaker.npz", tmp_path / "motors.npz"
    assert main(["track", str(video), "--markers", "face", "-o", str(take)]) == 0
    assert main(["map", str(take), "-o", str(out), "--mapping", str(mapping), "--profile", str(profile),
                 "--face", "classic"]) == 0
    np.testing.assert_allclose(load_track(out).values, tuner.track.values, atol=1e-9)
    with pytest.raises(InputError, match="own units"):
        apply(session, {"op": "tune", "action": "open", "take": str(video), "units": "cm"}, 0.0)
