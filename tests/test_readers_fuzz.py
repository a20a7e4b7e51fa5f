"""Every document reader, fed mutated and random bytes (hypothesis, derandomized), raises only
InputError: a face, an animation, a motor track, a mapping, a marker set, a profile, expressions,
a batch job, a label file, Rhubarb's mouth cues. (The take readers have their own:
tests/capture/test_takefile_fuzz.py.)"""

from __future__ import annotations

import numpy as np
import pytest
from fuzzing import Seeds, fuzz_settings
from hypothesis import example, given
from hypothesis import strategies as st

from capture.cues import read_cues
from capture.markerset import load_markerset
from common import InputError
from common.data import data_path
from mapping.mapfile import load_mapping
from mapping.profile import load_profile
from toon import MOTOR_CODES, MotorTrack, load_face, load_track, save_track
from toon.animation_file import load_animation
from toon.expressions import load_expressions
from toonface.batch.job import load_job
from toonface.studio.sound import load_labels

SETTINGS = fuzz_settings(150)

JOB = b'''format = "toonface.batch/1"
faces = ["classic"]
[[takes]]
path = "t.npz"
'''
ANIMATION = b'''format = "toonface.animation/1"
duration = 2.0
[knots]
MB = [[0.0, 0.2], [1.0, 0.9], [1.0, 0.4], [2.0, 0.2]]
'''
LABELS = b"0.5\t0.9\thello\n1.2\t1.2\tmark\n"

#: (suffix, reader, where the seed comes from: a built-in file's path parts, or its bytes).
READERS = {
    "face": (".json", load_face, ("faces", "classic.json")),
    "mapping": (".toml", load_mapping, ("mappings", "toon32.toml")),
    "markerset": (".toml", load_markerset, ("markersets", "toon32.toml")),
    "profile": (".toml", load_profile, ("profiles", "toon32.toml")),
    "expressions": (".toml", load_expressions, ("expressions.toml",)),
    "animation": (".toml", load_animation, ANIMATION),
    "job": (".toml", load_job, JOB),
    "labels": (".txt", load_labels, LABELS),
    "cues-tsv": (".tsv", read_cues, b"0.00\tX\n0.92\tA\n0.99\tB\n1.18\tX\n"),
    "cues-json": (".json", read_cues, b'{"metadata": {"duration": 1.2}, "mouthCues": [{"start": 0.0, "end": 0.92, '
                                      b'"value": "X"}, {"start": 0.92, "end": 1.2, "value": "D"}]}'),
    "cues-xml": (".xml", read_cues, b'<?xml version="1.0"?><rhubarbResult><metadata><duration>1.2</duration>'
                                    b'</metadata><mouthCues><mouthCue start="0.00" end="0.92">X</mouthCue>'
                                    b'<mouthCue start="0.92" end="1.20">D</mouthCue></mouthCues></rhubarbResult>'),
    "track-csv": (".csv", load_track, None),
    "track-npz": (".npz", load_track, None),
}


@pytest.fixture(scope="module")
def seeds(tmp_path_factory) -> dict[str, bytes]:
    folder = tmp_path_factory.mktemp("seeds")
    values = np.random.default_rng(0).uniform(0, 1, size=(10, len(MOTOR_CODES)))
    out = Seeds()
    for kind, (suffix, _, seed) in READERS.items():
        if seed is None:
            out[kind] = save_track(MotorTrack(values, 30.0), folder / f"m{suffix}").read_bytes()
        else:
            out[kind] = seed if isinstance(seed, bytes) else data_path(*seed).read_bytes()
    return out


def _read(kind: str, path) -> None:
    try:
        READERS[kind][1](path)
    except InputError:
        pass


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(READERS))
@SETTINGS
@given(edits=st.lists(st.tuples(st.integers(0, 1 << 20), st.integers(0, 255)), max_size=8),
       cut=st.one_of(st.none(), st.integers(0, 4096)))
def test_a_mutated_document_raises_only_input_error(tmp_path, seeds, kind, edits, cut):
    data = bytearray(seeds[kind])
    for where, value in edits:
        data[where % len(data)] = value
    path = tmp_path / f"x{READERS[kind][0]}"
    path.write_bytes(bytes(data[:cut] if cut is not None else data))
    _read(kind, path)


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(READERS))
@SETTINGS
@given(data=st.binary(max_size=1024))
@example(data=b"\r")  # a motor CSV's header read as empty: IndexError
def test_random_bytes_raise_only_input_error(tmp_path, kind, data):
    path = tmp_path / f"x{READERS[kind][0]}"
    path.write_bytes(data)
    _read(kind, path)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["face", "animation", "job", "mapping"])
@SETTINGS
@given(text=st.text(alphabet='[]{}"=,:.0123456789-eE \nabcxyz', max_size=400))
def test_document_shaped_text_raises_only_input_error(tmp_path, kind, text):
    path = tmp_path / f"x{READERS[kind][0]}"
    path.write_text(text)
    _read(kind, path)
