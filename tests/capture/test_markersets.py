"""Marker sets: the built-ins, aliases and MPEG-4 numbers, and the two real facial layouts."""

from __future__ import annotations

import numpy as np
import pytest

from capture import load_markerset, load_take
from common import InputError, data_path


def test_the_sets_with_pupils_bridge_them_on_their_own():
    assert load_markerset("face").independent == load_markerset("toon32").independent == ("PUPIL_R", "PUPIL_L")
    assert load_markerset("animface41").independent == ()


def test_toon32_aliases_prefixes_and_mpeg4():
    ms = load_markerset("toon32")
    assert len(ms.labels) == 32 and ms.head_reference[0] == "FOREHEAD"
    assert ms.canonical("LBRO_IN") == "BROW_L_MED" and ms.canonical("Daphnee:LBRO_IN") == "BROW_L_MED"
    assert ms.canonical("Actor1:MOUTH_R") == "MOUTH_R"
    assert ms.mpeg4["MOUTH_L"] == "8.3" and ms.mpeg4["PUPIL_R"] == "3.6"
    np.testing.assert_array_equal(ms.neutral_of("RMOU"), [-25.0, -70.0, 12.0])
    assert ms.match(["S:LBRO_IN", "junk", "CHIN"]) == {"BROW_L_MED": "S:LBRO_IN", "CHIN": "CHIN"}
    with pytest.raises(InputError, match='"NOPE" is not in marker set "toon32"'):
        ms.canonical("NOPE")
    # Every side-specific marker has a mirror twin at -x, so symmetric pairs are well defined.
    for label in ms.labels:
        if "_R" in label:
            twin = label.replace("_R", "_L")
            np.testing.assert_allclose(ms.neutral_of(twin) * [-1, 1, 1], ms.neutral_of(label))


@pytest.mark.realdata
@pytest.mark.parametrize("name, file, options, markers", [
    ("animface41", "animface/EyebrowsMoCap.csv", {"units": "cm"}, 41),
    ("animface41", "animface/JawMoCap.csv", {"units": "cm"}, 41),
    ("gluedots16", "gluedots/Subject_01.csv", {"rate": 30, "units": 8 / 0.04328}, 16),
])
def test_real_layouts_describe_their_files(realdata, name, file, options, markers):
    ms = load_markerset(name)
    take = load_take(realdata / "facial" / file, **options)
    assert len(ms.labels) == markers and set(ms.match(take.labels)) == set(ms.labels)
    # The head references are among the most rigid markers: their pairs change length over the
    # take less than half of all marker pairs do, on average.
    seen = take.valid.all(axis=1)
    pos = take.select(list(ms.labels))[seen]
    spread = np.ptp(np.linalg.norm(pos[:, :, None] - pos[:, None, :], axis=3), axis=0)
    refs = [ms.labels.index(r) for r in ms.head_reference]
    ref_spread = spread[np.ix_(refs, refs)][np.triu_indices(len(refs), 1)]
    all_spread = spread[np.triu_indices(len(ms.labels), 1)]
    assert ref_spread.mean() < np.median(all_spread), (ref_spread.mean(), np.median(all_spread))
    # Neutral positions are in millimetres between the eyes: a face is 100-200 mm wide.
    width = np.ptp(ms.neutral[:, 0])
    assert 60 < width < 200


@pytest.mark.parametrize("body, fragment", [
    ('[markers]\nA = { neutral = [0, 0, 0], aliases = ["B"] }\nB = { neutral = [1, 0, 0] }\n', "already a label"),
    ('[markers]\nA = { neutral = [0, 0, 0], mpeg4 = "left brow" }\n', "MPEG-4 feature point"),
    ('[markers]\nA = { neutral = [0, 0, 0], colour = "red" }\n',
     "markers.A.colour: unknown field (known: aliases, mpeg4, neutral)"),
    ('[markers]\nA = { neutral = [0, 0] }\n', "markers.A.neutral"),
    ('independent = ["Z"]\n[markers]\nA = { neutral = [0, 0, 0] }\nB = { neutral = [1, 0, 0] }\n'
     'C = { neutral = [0, 1, 0] }\n', "independent: expected markers of this set; unknown ['Z']"),
])
def test_bad_marker_sets_name_the_field(tmp_path, body, fragment):
    path = tmp_path / "set.toml"
    path.write_text('format = "toonface.markerset/1"\nhead_reference = ["A", "B", "C"]\n' + body)
    with pytest.raises(InputError, match="set.toml") as caught:
        load_markerset(path)
    assert fragment in str(caught.value)


def test_a_marker_set_gives_the_rate_and_units_its_tables_leave_out(realdata, tmp_path):
    """The glue-dot take needed --rate 30 --units 184.84, found only in a comment."""
    path = realdata / "facial" / "gluedots" / "Subject_01.csv"
    plain, told = load_take(path), load_take(path, rate=30, units="184.84")
    assert plain.rate == 30 and np.array_equal(plain.positions, told.positions, equal_nan=True)
    assert plain.meta["defaults_from_markerset"] == {"rate": 30.0, "units": "184.84", "markerset": "gluedots16"}
    assert "defaults_from_markerset" not in told.meta
    assert load_take(path, rate=60).rate == 60  # what the user says wins
    assert np.nanmax(np.abs(load_take(path, units="mm").positions)) < 1.0  # the file is in scene units


def test_a_marker_set_s_table_defaults_are_checked(tmp_path):
    text = (data_path("markersets", "gluedots16.toml").read_text()
            .replace("rate = 30\n", "rate = -30\n"))
    (tmp_path / "bad.toml").write_text(text)
    with pytest.raises(InputError, match="tables.rate: expected a number from 0 to 100000, got -30"):
        load_markerset(tmp_path / "bad.toml")
