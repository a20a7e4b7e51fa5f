"""C3D files as other vendors write them, and the reader against an independent one (ezc3d)."""

from __future__ import annotations

import warnings

import c3d_vendors as vendors
import ezc3d
import numpy as np
import pytest

from capture import load_take
from common import InputError


@pytest.fixture
def plain(tmp_path):
    return load_take(vendors.plain(tmp_path / "plain.c3d"))


@pytest.mark.parametrize("quirk", ["units_in_rows", "units_padded", "units_nul_padded", "duplicated_parameter"])
def test_vendor_quirks_read_as_the_plain_file(tmp_path, plain, quirk):
    """Units padded or one per row were refused as unknown; a parameter named twice as corrupt."""
    take = load_take(vendors.QUIRKS[quirk](tmp_path / f"{quirk}.c3d"))
    assert take.labels == plain.labels
    np.testing.assert_allclose(take.positions, plain.positions, atol=1e-4)
    assert take.meta["reader"] == ("ezc3d" if quirk == "duplicated_parameter" else "c3d")


def test_zero_coordinates_with_a_residual_are_gaps(tmp_path, plain):
    take = load_take(vendors.zeros_for_gaps(tmp_path / "z.c3d"))
    missing = np.isnan(take.positions[..., 0])
    assert missing[:, 1].tolist() == [10 <= f < 20 for f in range(vendors.FRAMES)]  # B's written gap
    assert not missing[:, [0, 2]].any()  # C at x = 0 (but not all three) is seen
    assert take.meta["zero_gaps"] == 10


def test_modelled_outputs_are_not_markers(tmp_path, plain):
    """Plug-in Gait stores angles, forces, moments and powers as points; they were read as markers."""
    take = load_take(vendors.plug_in_gait(tmp_path / "pig.c3d"))
    assert take.labels == ("A", "B", "C")
    np.testing.assert_allclose(take.positions, plain.positions, atol=1e-4)
    assert take.meta["modelled_points"] == {"ANGLES": ["LKneeAngles"], "FORCES": ["LHipForce"],
                                            "MOMENTS": ["LHipMoment"], "POWERS": ["LHipPower"]}


def _ezc3d(path):
    """Positions (frames, points, 3) in mm and the gap mask, as ezc3d reads them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        doc = ezc3d.c3d(str(path))
    units = {"mm": 1.0, "cm": 10.0, "m": 1000.0}[str(doc["parameters"]["POINT"]["UNITS"]["value"][0]).strip()]
    points = np.transpose(doc["data"]["points"][:3], (2, 1, 0)) * units
    gaps = np.isnan(points).any(axis=2) | (doc["data"]["meta_points"]["residuals"][0].T < 0)
    return points, gaps


def test_every_real_c3d_reads_as_ezc3d_reads_it(realdata):
    """Every file of the corpus both libraries read: the same labels, coordinates and gaps."""
    compared = 0
    for path in sorted((realdata / "c3d").rglob("*")):
        if path.suffix.lower() != ".c3d" or path.stat().st_size == 0 or path.parent.name == "c3d.org-sample13":
            continue  # Dance.c3d: ezc3d refuses its float ANALOG:OFFSET
        if path.stem in ("Eb015si", "Eb015sr", "sgi_int"):
            continue  # ezc3d refuses SGI/MIPS files; test_takefiles checks them against the PC files
        take = load_take(path)
        points, gaps = _ezc3d(path)
        assert np.array_equal(np.isnan(take.positions[..., 0]), gaps), path.name
        step = take.meta["point_scale"] if take.meta["storage"] == "integer" else 1e-4
        np.testing.assert_allclose(take.positions[~gaps], points[~gaps], atol=step, err_msg=path.name)
        compared += 1
    assert compared == 14


def test_a_zero_rate_is_said_as_a_number_not_as_numpy_spells_it(tmp_path):
    """An error showed "POINT:RATE is np.float32(0.0)": what a reader gives a file whose
    POINT:RATE is 0 (the c3d library reads such a file; its writer refuses to make one)."""
    from capture import c3dfile

    raw = c3dfile._Raw(np.float32(0.0), ["A"], "mm", np.zeros((3, 1, 4), np.float32), 3, {})
    with pytest.raises(InputError, match=r"p.c3d: POINT:RATE is 0; expected a positive frame rate$"):
        c3dfile._take(raw, tmp_path / "p.c3d", False)
