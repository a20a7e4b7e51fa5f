"""Take files: the real C3D/TRC/CSV files against their README, round trips, and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from capture import Take, load_take, save_take
from capture.info import summarize
from common import InputError
from toonface.cli import main

SAMPLE01 = ["Eb015pi", "Eb015pr", "Eb015vi", "Eb015vr", "Eb015si", "Eb015sr"]  # PC / DEC / SGI x int / float


def _same_columns(a: Take, b: Take) -> np.ndarray:
    """``b``'s positions in ``a``'s label order."""
    return b.positions[:, [b.labels.index(x) for x in a.labels]]


@pytest.mark.realdata
def test_sample01_every_processor_and_storage_gives_the_same_arrays(realdata):
    takes = [load_take(realdata / "c3d" / "c3d.org-sample01" / f"{n}.c3d") for n in SAMPLE01]
    first = takes[0]
    assert first.positions.shape == (450, 26, 3) and first.rate == 50.0
    assert int((~first.valid).sum()) == 226 and int((~first.valid).any(axis=0).sum()) == 10
    for name, take in zip(SAMPLE01, takes, strict=True):
        assert take.labels == first.labels, name
        assert np.array_equal(take.valid, first.valid), name
        np.testing.assert_allclose(take.positions, first.positions, atol=1e-4, err_msg=name)
    assert {t.meta["processor"] for t in takes} == {"INTEL", "DEC", "MIPS"}
    assert {t.meta["storage"] for t in takes} == {"integer", "float"}


@pytest.mark.realdata
def test_sample02_int_and_float_agree_within_one_scale_step(realdata):
    folder = realdata / "c3d" / "c3d.org-sample02"
    real = load_take(folder / "pc_real.c3d")
    assert real.positions.shape == (89, 36, 3)
    for name in ("pc_int.c3d", "DEC_INT.C3D", "sgi_int.c3d"):
        take = load_take(folder / name)
        assert np.array_equal(take.valid, real.valid), name
        step = take.meta["point_scale"]  # 0.2812 mm: "one POINT:SCALE step (0.28 mm)"
        assert step == pytest.approx(0.28, abs=0.005)
        assert np.nanmax(np.abs(take.positions - real.positions)) <= step + 1e-6, name


@pytest.mark.realdata
def test_sample08_moved_sections_read_the_same(realdata):
    takes = [load_take(realdata / "c3d" / "c3d.org-sample08" / f"TEST{k}PI.c3d") for k in "ABCD"]
    reference = load_take(realdata / "c3d" / "c3d.org-sample01" / "Eb015pi.c3d")
    for take in takes:
        assert np.array_equal(take.positions, takes[0].positions, equal_nan=True)
    np.testing.assert_allclose(takes[0].positions, reference.positions, atol=1e-4)


@pytest.mark.realdata
def test_dance_has_a_non_integer_rate_and_trimmed_labels(realdata):
    take = load_take(realdata / "c3d" / "c3d.org-sample13" / "Dance.c3d")
    assert take.positions.shape == (499, 40, 3)
    assert take.rate == pytest.approx(65.05, abs=0.01) and take.rate != round(take.rate)
    assert take.labels[0] == "Channel101" and all(x == x.strip() for x in take.labels)
    assert any("DATA_START" in w for w in take.meta["warnings"])


@pytest.mark.realdata
def test_adem01_real_gaps_come_back_as_nan(realdata):
    folder = realdata / "c3d" / "others"
    integer, real = (load_take(folder / f"ADemo1_rewrite_c3d_pc_{k}.c3d") for k in ("integer", "float"))
    assert integer.positions.shape == (512, 24, 3) and integer.rate == 200.0
    np.testing.assert_allclose(integer.positions, real.positions, atol=6e-5)
    ankle = integer.marker("L.Ankle")
    heel = integer.marker("L.Heel")
    # Frames 5-33 and 9-24, 1-based as the README counts them.
    assert np.isnan(ankle[4:33]).all() and not np.isnan(ankle[3]).any() and not np.isnan(ankle[33]).any()
    assert np.isnan(heel[8:24]).all() and not np.isnan(heel[7]).any() and not np.isnan(heel[24]).any()


@pytest.mark.realdata
def test_vicon_gaps_and_subject_prefixes(realdata):
    take = load_take(realdata / "c3d" / "vicon" / "Vicon.c3d")
    assert take.positions.shape == (580, 51, 3) and take.rate == 100.0
    assert int((~take.valid).sum()) == 305 and int((~take.valid).any(axis=0).sum()) == 13
    scap = take.marker("Daphnee:SCAP_CP")
    assert np.isnan(scap[339:410]).all()
    assert take.meta["analog_channels_skipped"] == 38


@pytest.mark.realdata
def test_empty_c3d_is_refused_in_one_line(realdata, capsys):
    path = realdata / "c3d" / "others" / "Empty.c3d"
    with pytest.raises(InputError, match="empty file"):
        load_take(path)
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Empty.c3d" in err


@pytest.mark.realdata
def test_nexus_csv_gives_the_c3d_arrays(realdata):
    csv = load_take(realdata / "trc_csv" / "vicon_nexus_markers.csv")
    c3d = load_take(realdata / "c3d" / "vicon" / "Vicon.c3d")
    assert set(csv.labels) == set(c3d.labels) and csv.rate == c3d.rate
    same = _same_columns(csv, c3d)
    assert np.array_equal(np.isnan(csv.positions), np.isnan(same))
    assert np.nanmax(np.abs(csv.positions - same)) <= 0.005
    assert int((~csv.valid).sum()) == 305


@pytest.mark.realdata
def test_odd_trc_reports_the_row_count_mismatch(realdata, caplog):
    take = load_take(realdata / "trc_csv" / "odd_comma_delimited.trc")
    assert take.positions.shape == (93, 51, 3) and take.rate == 100.0
    assert "652" in caplog.text and "93" in caplog.text
    assert take.times[1] == pytest.approx(0.01)


@pytest.mark.realdata
def test_facial_tables(realdata):
    brows = load_take(realdata / "facial" / "animface" / "EyebrowsMoCap.csv", units="cm")
    assert brows.positions.shape == (902, 41, 3) and brows.rate == pytest.approx(60.0, abs=1e-3)
    assert brows.valid.all()
    lift = np.ptp(brows.marker("Leyebrow_M")[:, 1])
    assert 10 < lift < 40  # "brow markers move about 2 cm", in mm now
    jaw = load_take(realdata / "facial" / "animface" / "JawMoCap.csv", units="cm")
    assert jaw.frames == 1590 and 30 < np.ptp(jaw.marker("Mouth_Down")[:, 1]) < 45
    dots = load_take(realdata / "facial" / "gluedots" / "Subject_01.csv", rate=30, units=8 / 0.04328)
    assert dots.positions.shape == (1714, 16, 3)
    seen = dots.valid.any(axis=1)
    assert seen[799:1650].all() and not seen[:799].any() and not seen[1650:].any()
    assert dots.meta["ignored_columns"] == ["Stimulustype"]


def _toy_take(dims: int = 3) -> Take:
    rng = np.random.default_rng(3)
    pos = rng.normal(0, 50, size=(7, 3, 3))
    if dims == 2:
        pos[:, :, 2] = 0
    pos[2, 1] = np.nan
    return Take(pos, ("A", "B_1", "C"), 120.0, dims=dims)


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".trc", ".c3d"])
def test_every_writable_format_round_trips(tmp_path, suffix):
    take = _toy_take()
    if suffix == ".c3d":  # C3D stores float32: start from what a C3D can hold
        take = Take(take.positions.astype(np.float32), take.labels, take.rate)
    once = load_take(save_take(take, tmp_path / f"a{suffix}"))
    twice = load_take(save_take(once, tmp_path / f"b{suffix}"))
    for got in (once, twice):
        assert got.labels == take.labels and got.rate == take.rate and got.dims == take.dims
        assert np.array_equal(got.positions, take.positions, equal_nan=True)
        np.testing.assert_allclose(got.times, take.times, rtol=0, atol=1e-12)


def test_a_planar_take_round_trips_through_csv_and_is_refused_by_c3d(tmp_path):
    take = _toy_take(dims=2)
    back = load_take(save_take(take, tmp_path / "p.csv"))
    assert back.dims == 2 and np.array_equal(back.positions, take.positions, equal_nan=True)
    with pytest.raises(InputError, match="planar"):
        save_take(take, tmp_path / "p.c3d")


def test_wide_tables_any_separator_na_and_frame_column(tmp_path):
    text = "Frame;M1_x;M1_y;M1_z;note\n10;1;2;3;a\n11;NA;NA;NA;b\n12;4;5;6;c\n"
    path = tmp_path / "t.csv"
    path.write_text(text)
    with pytest.raises(InputError, match="--rate"):
        load_take(path)
    take = load_take(path, rate=50, units="cm")
    assert take.labels == ("M1",) and take.rate == 50
    np.testing.assert_allclose(take.times, [0.2, 0.22, 0.24])
    np.testing.assert_allclose(take.positions[[0, 2], 0], [[10, 20, 30], [40, 50, 60]])
    assert np.isnan(take.positions[1]).all() and take.meta["ignored_columns"] == ["note"]
    tabbed = tmp_path / "t.tsv"
    tabbed.write_text("time\tA.x\tA.y\n0\t1\t2\n0.5\t\t\n")
    planar = load_take(tabbed)
    assert planar.dims == 2 and planar.rate == 2.0 and np.isnan(planar.positions[1]).all()


def test_headerless_tables_need_labels_and_rate(tmp_path):
    path = tmp_path / "h.csv"
    path.write_text("1,2,3,4,5,6\n7,8,9,10,11,12\n")
    with pytest.raises(InputError, match="--labels"):
        load_take(path)
    take = load_take(path, rate=25, labels=["P", "Q"])
    np.testing.assert_array_equal(take.marker("Q"), [[4, 5, 6], [10, 11, 12]])
    with pytest.raises(InputError, match="6 columns for 4 labels"):
        load_take(path, rate=25, labels=["P", "Q", "R", "S"])


@pytest.mark.parametrize("name, content, fragment", [
    ("a.csv", "", "empty file"),
    ("a.csv", "time,M_x,M_y,M_z\n", "no data rows"),
    ("a.csv", "time,M_x,M_y,M_z\n0,1,2,x3\n", 'line 2: column "M_z": not a number'),
    ("a.csv", "time,M_x,M_y,M_z,M_x\n0,1,2,3,4\n", 'duplicate column "M_x"'),
    ("a.csv", "time:M_x:M_y:M_z\n0:1:2:3\n", "no marker columns"),
    ("a.csv", "time,M_x,M_y,M_z\n0,1,2,3\n0,1,2,3\n", "must increase"),
    ("a.csv", "time,M_x,M_y,M_z\n0,1,2,3\n1e-9,1,2,3\n", "rate implied"),
    ("a.csv", "time,M_x,M_y,M_z\n0,1,2\n", "line 2: 3 cells"),
    ("a.csv", "time,M_x,M_y,M_z\n0,1,2,inf\n", "not a finite number"),
    ("a.trc", "PathFileType\t4\n", "not a TRC file"),
    ("a.trc", "hello\n1\n2\n3\n4\n5\n", "not a TRC file"),
    ("a.trc", "PathFileType\t4\t(X/Y/Z)\nDataRate\tNumFrames\tNumMarkers\tUnits\n-5\t1\t1\tmm\n"
              "Frame#\tTime\tA\nx\tx\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n", "DataRate is -5"),
    ("a.trc", "PathFileType\t4\t(X/Y/Z)\nDataRate\tNumFrames\tNumMarkers\tUnits\n100\t1\t1\tfurlongs\n"
              "Frame#\tTime\tA\n\t\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n", 'unknown Units "furlongs"'),
    ("a.c3d", "not a c3d at all, just some text that is long enough" * 20, "not a C3D file"),
    ("a.c3d", "\x02P", "not a C3D file"),
    ("a.npz", "PK not really a zip", "not a .npz zip archive"),
    ("t.npz", "time,BRL\n0,0\n", "a text file (it starts 'time,BRL'), not a .npz zip archive"),  # not pickle advice
])
def test_bad_files_give_one_line_naming_file_and_cause(tmp_path, capsys, name, content, fragment):
    path = tmp_path / name
    path.write_text(content, encoding="latin-1")
    with pytest.raises(InputError) as caught:
        load_take(path)
    assert fragment in str(caught.value) and name in str(caught.value)
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("toonface: error: ") and fragment in err


def test_info_json_has_the_documented_keys(tmp_path, capsys):
    take = _toy_take()
    path = save_take(take, tmp_path / "t.npz")
    assert main(["info", str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"frames", "markers", "rate", "duration", "units", "dims", "labels", "missing"} <= set(out)
    assert (out["frames"], out["markers"], out["rate"], out["missing"]) == (7, 3, 120.0, 1)
    assert out["duration"] == pytest.approx(7 / 120) and out["labels"] == ["A", "B_1", "C"]
    assert out["missing_per_marker"] == {"B_1": 1} and out["longest_gap"] == {"B_1": 1}
    assert main(["info", str(path)]) == 0
    text = capsys.readouterr().out
    assert "frames    7" in text and "missing   1 marker-samples in 1 markers" in text


def test_options_for_tables_are_refused_for_self_describing_formats(tmp_path):
    path = save_take(_toy_take(), tmp_path / "t.npz")
    with pytest.raises(InputError, match="carries its own rate"):
        load_take(path, rate=30)


def test_summary_counts_the_longest_gap():
    pos = np.zeros((10, 1, 3))
    pos[[1, 2, 5, 6, 7]] = np.nan
    summary = summarize(Take(pos, ("A",), 10.0))
    assert summary["missing"] == 5 and summary["longest_gap"] == {"A": 3}


@pytest.mark.parametrize("keep", [20_000, 0.6])
def test_a_c3d_that_ends_early_is_refused_unless_allowed(tmp_path, realdata, capsys, keep):
    """The first 20 kB of a real trial (or 60 % of one written here) used to read as a short take, exit 0."""
    if keep == 0.6:
        source = save_take(Take(np.random.default_rng(0).normal(size=(200, 8, 3)), tuple("ABCDEFGH"), 60.0),
                           tmp_path / "whole.c3d")
    else:
        source = realdata / "c3d" / "vicon" / "Vicon.c3d"
    data = source.read_bytes()
    cut = tmp_path / "cut.c3d"
    cut.write_bytes(data[: keep if isinstance(keep, int) else int(len(data) * keep)])
    with pytest.raises(InputError, match="the file ends early: it holds .* frames its header declares"):
        load_take(cut)
    assert main(["map", str(cut), "-o", str(tmp_path / "m.csv")]) == 2
    assert "ends early" in capsys.readouterr().err and not (tmp_path / "m.csv").exists()
    take = load_take(cut, allow_truncated=True)
    whole = load_take(source)
    assert 0 < take.frames < whole.frames and "ends early" in take.meta["warnings"][-1]
    assert np.array_equal(take.positions, whole.positions[: take.frames], equal_nan=True)
    assert main(["info", str(cut), "--allow-truncated"]) == 0
