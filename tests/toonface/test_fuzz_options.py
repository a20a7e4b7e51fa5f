"""Every number a command takes, fuzzed (hypothesis, derandomized): one clear line and status 2,
or a file that toonface reads back; never "internal error" (status 70), a traceback or a hang."""

import math

import pytest
from fuzzing import fuzz_settings
from hypothesis import given
from hypothesis import strategies as st

from capture import load_take
from common import InputError
from toon import load_track
from toon.animation_file import load_animation
from toonface.cli import main

#: Values that broke commands before: tiny, huge, negative zero, the smallest subnormal.
HOSTILE = (0.0, -0.0, 5e-324, 1e-300, -1e-300, 1e300, -1e300, 1.7e308, 1e15, -1.0, 0.5, 2.0)
NUMBERS = st.one_of(st.sampled_from(HOSTILE), st.floats(allow_nan=False, allow_infinity=False))
SETTINGS = fuzz_settings(14)

#: (command with {take}, {motors}, {anim} and {out}, the option, how its value is written).
INVOCATIONS = [
    ("info {take}", "--rate", "{}"),
    *[("clean {take} -o {out}.npz", option, "{}") for option in ("--max-gap", "--cutoff", "--rate")],
    *[("map {take} -o {out}.csv", option, "{}") for option in ("--max-gap", "--cutoff", "--rate")],
    ("retarget {take} -o {out}.csv --no-picture", "--rate", "{}"),
    ("anim sample {anim} -o {out}.csv", "--rate", "{}"),
    *[(f"anim {verb} {{anim}} -o {{out}}.toml", option, "{}") for verb in ("cut", "copy", "flip")
      for option in ("--from", "--to")],
    ("anim paste {anim} {anim} -o {out}.toml", "--at", "{}"),
    *[("anim scale {anim} -o {out}.toml", option, "{}") for option in ("--time", "--value", "--from", "--to")],
    ("anim from-track {motors} -o {out}.toml", "--tolerance", "{}"),
    ("anim concat {anim} {anim} -o {out}.toml", "--fade", "{}"),
    ("anim knot {anim} -o {out}.toml --motor MB", "--add", "{},0.5"),
    ("anim knot {anim} -o {out}.toml --motor MB", "--add", "1,{}"),
    ("anim knot {anim} -o {out}.toml --motor MB", "--move", "1:{},0.5"),
    ("markerset draft {take} -o {out}.toml", "--rate", "{}"),
]


def _read_back(path):
    if path.suffix == ".npz":
        load_take(path)
    elif path.suffix == ".toml" and "markerset" not in path.name:
        load_animation(path)
    elif path.suffix == ".csv":
        load_track(path)


@pytest.fixture(scope="module")
def inputs(small_take):
    anim = small_take / "a.toml"
    if not anim.exists():
        assert main(["anim", "from-track", str(small_take / "m.csv"), "-o", str(anim)]) == 0
    return {"take": small_take / "t.npz", "motors": small_take / "m.csv", "anim": anim}


@pytest.mark.slow
@pytest.mark.parametrize(("command", "option", "form"), INVOCATIONS,
                         ids=[f"{c.split(' {')[0]} {o} {f}" for c, o, f in INVOCATIONS])
@SETTINGS
@given(value=NUMBERS)
def test_a_number_option_answers_in_one_line_or_writes_what_reads_back(inputs, tmp_path, capsys, command, option,
                                                                      form, value):
    out = tmp_path / ("markerset" if command.startswith("markerset") else "out")
    args = command.format(out=out, **inputs).split() + [option, form.format(repr(value))]
    for stale in tmp_path.iterdir():
        stale.unlink()
    status = main(args)
    err = capsys.readouterr().err
    assert status in (0, 2), (args, status, err)
    assert "internal error" not in err and "Traceback" not in err, (args, err)
    if status == 2:
        assert err.startswith("toonface: error:") or "Usage:" in err, (args, err)
    for written in tmp_path.iterdir():
        if status == 0:
            try:
                _read_back(written)
            except InputError as exc:
                pytest.fail(f"{' '.join(args)} wrote {written.name}, which toonface refuses: {exc}")
        else:
            assert ".partial" not in written.name and not math.isnan(value)
