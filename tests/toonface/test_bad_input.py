"""Bad input gets one line and status 2: every number option refuses NaN and infinities, a binary
file is not a movie script, and numpy's warnings stay off the terminal."""

import click
import pytest

from toonface.cli import main


def _commands(group, path=()):
    for name, command in group.commands.items():
        if isinstance(command, click.Group):
            yield from _commands(command, (*path, name))
        else:
            yield (*path, name), command


def test_every_number_option_refuses_nan_and_infinities_by_name(tmp_path, capsys):
    """clean --max-gap nan|inf ended in "internal error" (ValueError, OverflowError); anim's
    --rate, --time, --value and --fade let NaN through to a file the reader then rejected."""
    from toonface.cli import cli
    from toonface.cli_options import FiniteFloat

    numbers = [(path, p) for path, command in _commands(cli) for p in command.params
               if isinstance(p.type, click.types.FloatParamType)]
    assert len(numbers) > 30
    plain = [f"{' '.join(path)} {p.opts[0]}" for path, p in numbers if not isinstance(p.type, FiniteFloat)]
    assert not plain, plain
    for _, param in numbers:
        for bad in ("nan", "inf", "-inf"):
            with pytest.raises(click.BadParameter, match="is not a finite number|not in the range"):
                param.type.convert(bad, param, None)
    assert main(["clean", "missing.npz", "-o", str(tmp_path / "x.npz"), "--max-gap", "nan"]) == 2
    assert "Invalid value for '--max-gap': 'nan' is not a finite number" in capsys.readouterr().err
    for path in sorted({path for path, _ in numbers}):  # an unbounded number's help said "x<=None"
        assert main([*path, "--help"]) == 0
        assert "None]" not in capsys.readouterr().out.replace("\n", " "), path


@pytest.mark.parametrize("command", [["render", "{path}", "-o", "{out}/x.mp4"], ["anim", "from-track", "{path}", "-o",
                                                                              "{out}/a.toml"]])
@pytest.mark.parametrize("content", [bytes(range(256)) * 8, b"time,BRL\n\xff\xfe\x00\x01"])
def test_a_binary_file_given_as_a_motor_csv_is_one_line(tmp_path, capsys, command, content):
    """It ended in "internal error: UnicodeDecodeError"."""
    path = tmp_path / "m.csv"
    path.write_bytes(content)
    args = [a.format(path=path, out=tmp_path) for a in command]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"toonface: error: {path}: binary data")


def test_no_numpy_warning_reaches_the_terminal(small_take, tmp_path, monkeypatch, capsys):
    """Overflow and empty-slice warnings were printed among a command's own lines."""
    import warnings as python_warnings

    from mapping import workflow

    report = workflow.take_report

    def noisy(*args, **kwargs):
        python_warnings.warn("overflow encountered in add", RuntimeWarning, stacklevel=1)
        return report(*args, **kwargs)

    monkeypatch.setattr(workflow, "take_report", noisy)
    assert main(["map", str(small_take / "t.npz"), "-o", str(tmp_path / "m.csv")]) == 0
    assert "RuntimeWarning" not in capsys.readouterr().err
    monkeypatch.setenv("TOONFACE_DEBUG", "1")  # a developer still sees them
    with pytest.warns(RuntimeWarning, match="overflow"):
        main(["map", str(small_take / "t.npz"), "-o", str(tmp_path / "m.csv")])
