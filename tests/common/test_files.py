"""File round trips and errors: takes (.npz), motor tracks (.csv, .npz), atomic writes."""

import os
import re

import numpy as np
import pytest

from capture import Take, load_take, save_take, synthesize
from common import InputError, atomic_dir, atomic_path
from toon import MotorTrack, load_track, save_track


def test_take_npz_round_trip(tmp_path):
    take = synthesize(seconds=1.0, rate=50.0, seed=3).take
    pos = take.positions.copy()
    pos[5:9, 2] = np.nan
    take = Take(pos, take.labels, take.rate, meta={"note": "gap"})
    back = load_take(save_take(take, tmp_path / "t.npz"))
    np.testing.assert_array_equal(back.positions, take.positions)
    assert back.labels == take.labels and back.rate == 50.0 and back.meta == {"note": "gap", "file": "t.npz"}
    np.testing.assert_array_equal(back.times, take.times)
    assert int((~back.valid).sum()) == 4


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_motor_track_round_trip(tmp_path, suffix):
    rng = np.random.default_rng(0)
    track = MotorTrack(rng.uniform(0, 1, (40, 21)), 29.97, confidence=rng.uniform(0, 1, (40, 21)))
    back = load_track(save_track(track, tmp_path / f"m{suffix}"))
    np.testing.assert_allclose(back.values, track.values, atol=5e-7)  # the CSV keeps 6 decimals
    assert back.rate == pytest.approx(29.97, rel=1e-5)
    if suffix == ".npz":
        np.testing.assert_array_equal(back.confidence, track.confidence)


def test_movie_script_header_and_first_rows(tmp_path):
    values = np.full((3, 21), 0.25)
    text = save_track(MotorTrack(values, 10.0), tmp_path / "m.csv").read_text().splitlines()
    assert text[0] == "time,BRL,BRC,BRM,BLL,BLC,BLM,ERU,ERL,ELU,ELL,PLH,PLV,PRH,PRV,MLH,MLV,MRH,MRV,MB,HH,HV"
    assert text[2].startswith("0.100000,0.250000,")
    assert len(text) == 4


@pytest.mark.parametrize("content, message", [
    ("", "empty file"),
    ("frame,BRL\n", 'first column must be "time"'),
    ("time,BRL,BRC\n0,0,0\n", "header must name the 21 motors"),
    ("time," + ",".join(["BRL"] * 21) + "\n", "header must name the 21 motors"),
])
def test_movie_script_errors(tmp_path, content, message):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(InputError, match=message) as info:
        load_track(path)
    assert str(path) in str(info.value)


def test_movie_script_errors_name_the_line(tmp_path):
    good = save_track(MotorTrack(np.full((4, 21), 0.5), 10.0), tmp_path / "m.csv").read_text().splitlines()
    bad = good[:3] + [good[3].replace("0.500000", "abc", 1)]
    (tmp_path / "b.csv").write_text("\n".join(bad) + "\n")
    with pytest.raises(InputError, match="line 4: not a number"):
        load_track(tmp_path / "b.csv")
    uneven = good[:2] + [good[2].replace("0.100000", "0.150000", 1)] + good[3:]
    (tmp_path / "u.csv").write_text("\n".join(uneven) + "\n")
    with pytest.raises(InputError, match="not evenly spaced"):
        load_track(tmp_path / "u.csv")


def test_unknown_formats_and_missing_files(tmp_path):
    with pytest.raises(InputError, match="unknown take format '.xyz'.*Rhubarb's mouth cues: .tsv, .json, .xml"):
        load_take(tmp_path / "a.xyz")
    with pytest.raises(InputError, match="Moho's .dat switch data is written only"):  # what lipsync writes
        load_take(tmp_path / "cues.dat")
    with pytest.raises(InputError, match="a video, not a take file: capture.takefile.load_take_or_video"):
        load_take(tmp_path / "talk.mp4")
    with pytest.raises(InputError, match="no such file"):
        load_take(tmp_path / "missing.npz")
    (tmp_path / "junk.npz").write_bytes(b"not a zip")
    with pytest.raises(InputError, match="junk.npz"):
        load_take(tmp_path / "junk.npz")
    with pytest.raises(InputError, match="unknown motor track format"):
        save_track(MotorTrack(np.zeros((2, 21)), 1.0), tmp_path / "m.txt")


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "out.bin"
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_bytes(b"half")
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []
    target.write_bytes(b"old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_bytes(b"new")
            raise RuntimeError("boom")
    assert target.read_bytes() == b"old" and list(tmp_path.iterdir()) == [target]


def test_builtin_names_and_paths_resolve_the_same_way_for_faces_and_marker_sets(tmp_path):
    from capture import load_markerset
    from toon import load_face

    assert load_markerset("toon32").labels[0] == "FOREHEAD"
    with pytest.raises(InputError,
                       match=r'no built-in marker set "toon99" \(built-in: animface41, face, gluedots16, toon32, '
                             r'voice; a file of your own is written as a path, such as ./toon99.toml\)'):
        load_markerset("toon99")
    with pytest.raises(InputError, match=r'no built-in face "toon99" \(built-in: .*classic'):
        load_face("toon99")
    with pytest.raises(InputError, match="no such marker set file"):
        load_markerset(tmp_path / "sub" / "mine.toml")


@pytest.mark.parametrize("what", ["face", "marker set", "mapping", "profile", "expressions"])
def test_a_file_or_folder_named_like_a_builtin_does_not_shadow_it(tmp_path, monkeypatch, what):
    """A folder ``round`` in the working folder once made ``--face round`` say "round: no such face
    file", and a file ``face`` hid the built-in marker set: a bare name is the built-in's wherever
    one runs, and one's own file is written as a path."""
    from capture import load_markerset
    from mapping.mapfile import load_mapping
    from mapping.profile import load_profile
    from toon import load_face
    from toon.expressions import load_expressions

    loader, name = {"face": (load_face, "round"), "marker set": (load_markerset, "face"),
                    "mapping": (load_mapping, "toon32"), "profile": (load_profile, "toon32"),
                    "expressions": (load_expressions, "expressions")}[what]
    monkeypatch.chdir(tmp_path)
    builtin = loader(name)
    (tmp_path / name).mkdir()
    assert _same(loader(name), builtin)
    (tmp_path / name).rmdir()
    (tmp_path / name).write_text("not a file of any kind\n")
    assert _same(loader(name), builtin)
    with pytest.raises(InputError):  # written as a path, the file itself is read (and refused)
        loader(f"./{name}")


def _same(a: object, b: object) -> bool:
    """The same document read twice (their fields, as text: no two reads share an address)."""
    return repr(getattr(a, "__dict__", a)) == repr(getattr(b, "__dict__", b))


def test_undecodable_documents_name_the_file_and_the_format(tmp_path):
    from capture import load_markerset
    from toon import load_face

    (tmp_path / "bad.toml").write_text("format = [unclosed\n")
    with pytest.raises(InputError, match=r"bad.toml: not valid TOML"):
        load_markerset(tmp_path / "bad.toml")
    (tmp_path / "list.json").write_text("[1, 2]")
    with pytest.raises(InputError, match=r"list.json: expected a JSON object at the top level, got list"):
        load_face(tmp_path / "list.json")
    (tmp_path / "latin.json").write_bytes(b'{"name": "caf\xe9"}')
    with pytest.raises(InputError, match=r"latin.json: not valid JSON"):
        load_face(tmp_path / "latin.json")


def test_atomic_outputs_get_the_usual_permissions(tmp_path):
    """Not mkstemp's owner-only mode: batch outputs on a shared disk are read by others."""
    mask = os.umask(0o022)
    try:
        with atomic_path(tmp_path / "out.txt") as tmp:
            tmp.write_text("x")
        with atomic_dir(tmp_path / "frames") as tmp:
            (tmp / "f.png").write_bytes(b"x")
    finally:
        os.umask(mask)
    assert (tmp_path / "out.txt").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "frames").stat().st_mode & 0o777 == 0o755


def test_labels_are_checked_and_found_by_name_however_many_there_are():
    """A CSV with 100,000 columns took 26 s for info and 77 s for clean: labels were checked
    with list.count and found with list.index. The answers stay the same."""
    n = 40_000
    labels = tuple(f"M{i}" for i in range(n))
    take = Take(np.zeros((2, n, 3)), labels, 30.0)
    assert take.index(f"M{n - 1}") == n - 1 and take.index("M0") == 0
    with pytest.raises(InputError, match='no marker "M-1" in this take'):
        take.index("M-1")
    with pytest.raises(InputError, match=r"repeated: \['B', 'M7'\]"):
        Take(np.zeros((2, 5, 3)), ("M7", "B", "M7", "B", "C"), 30.0)


@pytest.mark.parametrize("kind", ["fifo", "missing"])
def test_a_named_pipe_is_not_called_missing(tmp_path, kind):
    """A FIFO given as a take or a motor track was reported as "no such file"."""
    for name, load in (("t.csv", load_take), ("m.csv", load_track)):
        path = tmp_path / name
        if kind == "fifo":
            os.mkfifo(path)
        expected = "a named pipe (FIFO), not a file" if kind == "fifo" else "no such file"
        with pytest.raises(InputError, match=rf"^{tmp_path / name}: {re.escape(expected)}$"):
            load(path)


@pytest.mark.parametrize(("suffix", "kind"), [(".json", "face"), (".toml", "mapping"), (".toml", "profile"),
                                              (".toml", "animation"), (".toml", "markerset"), (".toml", "batch"),
                                              (".toml", "expressions")])
@pytest.mark.parametrize("hostile", ["deep", "digits"])
def test_deeply_nested_or_huge_number_documents_are_one_line(tmp_path, capsys, suffix, kind, hostile):
    """Nesting 100,000 deep ended in "internal error: RecursionError" for every file kind; an
    integer of 5000 digits in a face in a ValueError."""
    from toonface.cli import main

    path = tmp_path / f"hostile{suffix}"
    if hostile == "deep":
        body = "[" * 100_000 + "]" * 100_000
    else:
        body = "9" * 5000
    path.write_text(f'{{"format": 1, "x": {body}}}' if suffix == ".json" else f"format = 1\nx = {body}\n")
    args = {"face": ["face", str(path), "--sheet", str(tmp_path / "s.png")],
            "mapping": ["map", "t.npz", "-o", str(tmp_path / "m.csv"), "--mapping", str(path)],
            "profile": ["map", "t.npz", "-o", str(tmp_path / "m.csv"), "--profile", str(path)],
            "animation": ["anim", "sample", str(path), "-o", str(tmp_path / "m.csv")],
            "markerset": ["markerset", "mapping", str(path), "-o", str(tmp_path / "x.toml")],
            "batch": ["batch", str(path)],
            "expressions": ["face", "classic", "--sheet", str(tmp_path / "s.png"), "--expressions", str(path)]}[kind]
    save_take(synthesize(seconds=1.0, seed=1).take, tmp_path / "t.npz")
    args = [str(tmp_path / "t.npz") if a == "t.npz" else a for a in args]
    status = main(args)
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2, err
    reason = "nested 100001 deep" if hostile == "deep" and suffix == ".json" else (
        "nested 100000 deep" if hostile == "deep" else "a number of thousands of digits")
    assert err == [f"toonface: error: {path}: {reason}" + (
        ": deeper than the 64 levels any toonface file has" if hostile == "deep" else "")] or (
        hostile == "digits" and err[0] == f"toonface: error: {path}: not valid {suffix[1:].upper()}: {reason}")


def test_absurd_positions_and_rates_are_refused_by_name(tmp_path):
    """A take full of 1e308 ended in LinAlgError with numpy warnings on the terminal; a time
    column of 1e300-second steps was read as a take of 1e302 seconds at 1e-300 Hz."""
    take = synthesize(seconds=1.0, seed=1).take
    huge = take.positions.copy()
    huge[3, 4] = 1e308
    save_take(Take(take.positions, take.labels, take.rate), tmp_path / "ok.csv")
    lines = (tmp_path / "ok.csv").read_text().splitlines()
    cells = [row.split(",") for row in lines[1:]]
    (tmp_path / "huge.csv").write_text("\n".join([lines[0]] + [",".join(c[:2] + ["1e308"] * (len(c) - 2))
                                                               for c in cells]) + "\n")
    (tmp_path / "slow.csv").write_text("\n".join([lines[0]] + [",".join([c[0], repr(i * 1e300)] + c[2:])
                                                               for i, c in enumerate(cells)]) + "\n")
    with pytest.raises(InputError, match=r"huge.csv: a position of 1e\+308 mm: markers lie within"):
        load_take(tmp_path / "huge.csv")
    with pytest.raises(InputError, match=r'slow.csv: the rate implied by column "time_s" is 1e-300; expected'):
        load_take(tmp_path / "slow.csv")
    with pytest.raises(InputError, match="a position of 1e\\+308 mm"):
        Take(huge, take.labels, take.rate)
    assert load_take(tmp_path / "ok.csv").frames == take.frames
