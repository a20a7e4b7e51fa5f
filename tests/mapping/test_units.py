"""A take in other units than it is read in is caught, by its size against its marker set and a
face's, on the real shared takes: inferred where the file does not say, refused where the user
said otherwise, questioned where the file says so."""

from __future__ import annotations

import numpy as np
import pytest

from capture import Take, load_markerset, load_take, save_take, synthesize
from capture.scale import check_scale
from common import InputError
from mapping import choose_mapping, prepare
from toonface.cli import main

CM = ("facial", "animface", "JawMoCap.csv")


def _animface_mm(realdata) -> Take:
    return load_take(realdata.joinpath(*CM), units="cm")


def _rewritten(take: Take, path, divide: float) -> str:
    """``take`` written as a wide CSV whose numbers are millimetres divided by ``divide`` (the
    file does not say its units)."""
    save_take(Take(take.positions / divide, take.labels, take.rate, times=take.times), path)
    return str(path)


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
def test_a_centimetre_take_read_without_units_is_read_in_centimetres(realdata, tmp_path, capsys):
    """It gave a face that barely moved (MB at most 0.24) with exit 0 and no word of units."""
    take = load_take(realdata.joinpath(*CM))
    assert take.meta["units"] == {"mm_per_unit": 1.0, "from": "assumed"}
    prepared = prepare(take, choose_mapping(take)[1])
    assert prepared.units.origin == "inferred" and prepared.units.name() == "cm"
    np.testing.assert_allclose(prepared.take.positions, _animface_mm(realdata).positions, rtol=1e-12)
    assert "read in cm" in prepared.units.notes[0]
    assert main(["map", str(realdata.joinpath(*CM)), "-o", str(tmp_path / "m.csv")]) == 0
    err = capsys.readouterr().err
    assert "note: units: JawMoCap.csv read in cm (it does not say its units" in err
    assert "head references" not in err  # the 38 mm doubt about labels was the units all along


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
@pytest.mark.parametrize(("divide", "unit"), [(1000.0, "m"), (10.0, "cm"), (25.4, "in")])
def test_metres_centimetres_and_inches_are_inferred_on_a_known_layout(realdata, tmp_path, divide, unit):
    take = load_take(_rewritten(_animface_mm(realdata), tmp_path / "t.csv", divide))
    prepared = prepare(take, choose_mapping(take)[1])
    assert prepared.units.origin == "inferred" and prepared.units.name() == unit
    assert np.nanmax(np.abs(prepared.take.positions - _animface_mm(realdata).positions)) < 0.01


def test_a_metre_take_read_without_units_says_so_when_calibrated_and_its_extent_in_both_units(tmp_path, capsys):
    """Issue 66: calibrate said nothing of the units it inferred, and map's units line called a
    metre take's 0.162 (metres) "0.162 mm"."""
    path = _rewritten(synthesize(seconds=3).take, tmp_path / "m.csv", 1000.0)
    assert main(["calibrate", path, "-o", str(tmp_path / "p.toml")]) == 0
    assert "note: units: m.csv read in m (it does not say its units" in capsys.readouterr().err
    take = load_take(path)
    figure = prepare(take, choose_mapping(take)[1]).units.check.figure()
    extent = float(figure.split("extent ")[1].split(" m,")[0])
    assert 0.1 < extent < 0.3 and figure.endswith(f"{extent * 1000:.3g} mm")  # metres, then millimetres


@pytest.mark.slow  # over a second: make test runs it, test-fast does not
@pytest.mark.parametrize(("written", "given", "likely"), [(10.0, "m", "cm"), (1.0, "cm", "mm"), (10.0, "mm", "cm")])
def test_units_given_that_cannot_be_a_face_are_an_error_naming_the_likely_ones(realdata, tmp_path, capsys, written,
                                                                               given, likely):
    """--units m by mistake ended in "internal error: LinAlgError" from gap filling."""
    path = _rewritten(_animface_mm(realdata), tmp_path / "t.csv", written)
    assert main(["map", path, "--units", given, "-o", str(tmp_path / "m.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("toonface: error: t.csv: --units ")
    assert err[0].endswith(f"give --units {likely}")
    assert not (tmp_path / "m.csv").exists()


def test_the_glue_dots_own_units_pass_and_a_wrong_number_is_refused(realdata, capsys, tmp_path):
    path = realdata / "facial" / "gluedots" / "Subject_01.csv"
    take = load_take(path)  # 184.84 mm per unit from the marker set's [tables]
    prepared = prepare(take, choose_mapping(take)[1])
    assert prepared.units.origin == "marker set gluedots16" and not prepared.units.notes
    assert main(["map", str(path), "--units", "18.484", "-o", str(tmp_path / "m.csv")]) == 2
    assert "give --units 185" in capsys.readouterr().err  # not a named unit: the number


def test_a_file_that_states_the_wrong_units_is_questioned(tmp_path):
    """A .npz (or C3D) states millimetres; one in centimetres is mapped with a warning that
    names them (the file's word is not overruled)."""
    synthetic = synthesize(seconds=2.0, noise_mm=0.0, seed=3).take
    save_take(Take(synthetic.positions / 10.0, synthetic.labels, synthetic.rate), tmp_path / "t.npz")
    take = load_take(tmp_path / "t.npz")
    prepared = prepare(take, load_markerset("toon32"))
    assert prepared.units.origin == "file" and prepared.units.check.likely_unit == "cm"
    assert prepared.units.notes[0].startswith("warning: units: t.npz read in the units its file states, but its "
                                              "markers lie 10")
    np.testing.assert_array_equal(prepared.take.positions, take.positions)


def test_a_take_of_the_right_size_is_left_alone_on_every_built_in_layout(realdata):
    synthetic = synthesize(seconds=2.0, seed=1).take
    for take, name in ((synthetic, "toon32"), (_animface_mm(realdata), "animface41"),
                       (load_take(realdata / "facial" / "gluedots" / "Subject_01.csv"), "gluedots16")):
        check = check_scale(take, load_markerset(name))
        assert not check.off and 0.7 < check.ratio < 1.4, (name, check)
        assert 30 < check.extent_mm < 400


@pytest.mark.slow  # a few seconds: make test runs it
def test_a_drafted_layout_catches_both_directions(realdata, tmp_path, capsys):
    """A drafted set is made in the take's own units, so its shape cannot tell: the face's size
    does. Drafting from centimetres read as millimetres is refused naming cm; a drafted set then
    catches the same file read as mm (inferred) or in metres (refused)."""
    take = _animface_mm(realdata)
    np.savetxt(tmp_path / "s.csv", take.positions.reshape(take.frames, -1) / 10.0, delimiter=",", fmt="%.5f")
    (tmp_path / "names.txt").write_text("\n".join(take.labels) + "\n")
    reading = ["--rate", "60", "--labels", f"@{tmp_path / 'names.txt'}"]
    draft = ["markerset", "draft", str(tmp_path / "s.csv"), "-o", str(tmp_path / "mine.toml"), *reading]
    assert main(draft) == 2
    assert capsys.readouterr().err.strip().endswith("it looks to be in cm; give --units cm")
    assert main([*draft, "--units", "cm"]) == 0
    drafted = load_markerset(tmp_path / "mine.toml")
    as_mm = load_take(tmp_path / "s.csv", rate=60, labels=list(take.labels))
    assert check_scale(as_mm, drafted).likely_unit == "cm"
    prepared = prepare(as_mm, drafted)
    assert prepared.units.name() == "cm" and prepared.units.origin == "inferred"
    with pytest.raises(InputError, match="it looks to be in cm; give --units cm"):
        prepare(load_take(tmp_path / "s.csv", rate=60, labels=list(take.labels), units="m"), drafted)
    # the face's size alone (a set that shares the take's units) names the unit too
    small = check_scale(Take(take.positions / 10.0, take.labels, take.rate), None)
    large = check_scale(Take(take.positions * 10.0, take.labels, take.rate), None, 10.0)
    assert (small.likely_unit, large.likely_unit) == ("cm", "mm")
