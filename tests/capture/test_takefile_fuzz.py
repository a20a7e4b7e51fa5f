"""Property tests: every take reader, fed random and mutated bytes, raises only InputError."""

from __future__ import annotations

import numpy as np
import pytest
from fuzzing import Seeds, fuzz_settings
from hypothesis import example, given
from hypothesis import strategies as st

from capture import Take, load_take, save_take
from common import InputError

SETTINGS = fuzz_settings(80)


@pytest.fixture(scope="module")
def seeds(tmp_path_factory) -> dict[str, bytes]:
    """A small valid file of each format, written by our own writers."""
    folder = tmp_path_factory.mktemp("seeds")
    rng = np.random.default_rng(0)
    pos = rng.normal(0, 100, size=(12, 4, 3)).astype(np.float32)
    pos[3, 2] = np.nan
    take = Take(pos, ("A", "B", "C", "D"), 60.0)
    return Seeds({suffix: save_take(take, folder / f"s{suffix}").read_bytes()
                   for suffix in (".c3d", ".trc", ".csv", ".npz")})


def _mutate(data: bytes, edits: list[tuple[int, int]], cut: int | None) -> bytes:
    out = bytearray(data)
    for where, value in edits:
        out[where % len(out)] = value
    return bytes(out[:cut] if cut is not None else out)


def _read(path) -> None:
    try:
        load_take(path)
    except InputError:
        pass


@pytest.mark.parametrize("suffix", [".c3d", ".trc", ".csv", ".npz"])
@SETTINGS
@given(edits=st.lists(st.tuples(st.integers(0, 1 << 20), st.integers(0, 255)), max_size=12),
       cut=st.one_of(st.none(), st.integers(0, 4096)))
def test_mutated_files_raise_only_input_error(tmp_path, seeds, suffix, edits, cut):
    path = tmp_path / f"m{suffix}"
    path.write_bytes(_mutate(seeds[suffix], edits, cut))
    _read(path)


@pytest.mark.parametrize("suffix", [".c3d", ".trc", ".csv", ".npz"])
@SETTINGS
@given(data=st.binary(max_size=2048))
@example(data=b"\x1f")  # a lone unit separator: blank to str.split, not to the blank-line test (IndexError)
def test_random_bytes_raise_only_input_error(tmp_path, suffix, data):
    path = tmp_path / f"r{suffix}"
    path.write_bytes(data)
    _read(path)


@SETTINGS
@given(text=st.text(alphabet=st.sampled_from(list("0123456789.,;\t -eENnAa_xyzXYZ\ntime")), max_size=300))
def test_csv_like_text_raises_only_input_error(tmp_path, text):
    path = tmp_path / "t.csv"
    path.write_text(text)
    _read(path)
