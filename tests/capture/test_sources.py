"""Performer sources and output sinks: one interface each, opened by kind from a spec; a new
kind is one function and one registration."""

import numpy as np
import pytest

from capture import Take, load_take, synthesize
from capture.sources import KINDS, Frame, Source, SourceKind, open_source, paced, take_source
from common import InputError
from toonface.outputs import MOTOR_SINKS, Outputs, SinkKind, open_sink


class FakeClock:
    def __init__(self) -> None:
        self.now, self.slept = 100.0, []

    def __call__(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.slept.append(seconds)
        self.now += seconds


def counting_source(target: str, rate: float = 10.0, **_) -> Source:
    """A stand-in for a new kind (a camera, a bridge): frames at ``rate`` forever, live."""
    def frames():
        k = 0
        while True:
            yield Frame(k / rate, np.full((1, 3), float(k)))
            k += 1
    return Source(("DOT",), rate, frames(), f"counter {target}", live=True)


def test_a_new_source_kind_is_one_function_and_one_registration():
    kinds = {"counter": SourceKind(f"{__name__}:counting_source", lambda spec: spec.startswith("count")), **KINDS}
    source = open_source("counter:7", kinds, rate=20.0, colour="ignored")
    assert source.name == "counter 7" and source.rate == 20.0 and source.live
    assert [f.positions[0, 0] for f, _ in zip(source.frames, range(3), strict=False)] == [0.0, 1.0, 2.0]
    assert open_source("count-anything", kinds).name == "counter count-anything"
    clock = FakeClock()
    list(zip(paced(open_source("counter:x", kinds), clock, clock.sleep), range(5), strict=False))
    assert clock.slept == []  # a live source's frames are passed on as they come


def test_a_recorded_source_is_paced_on_the_clock_from_its_own_times(tmp_path):
    take = Take(np.zeros((4, 1, 3)), ("M",), 10.0, times=np.array([5.0, 5.1, 5.25, 5.3]))
    clock = FakeClock()
    seen = [(round(clock.now - 100.0, 6), f.t) for f in paced(take_source(take), clock, clock.sleep)]
    assert seen == [(0.0, 0.0), (pytest.approx(0.1), pytest.approx(0.1)), (pytest.approx(0.25), pytest.approx(0.25)),
                    (pytest.approx(0.3), pytest.approx(0.3))]
    again = take_source(take, repeat=True)
    times = [f.t for f, _ in zip(again.frames, range(6), strict=False)]
    assert times == pytest.approx([0.0, 0.1, 0.25, 0.3, 0.4, 0.5])  # the take again, one frame period on


def test_specs_pick_their_kind_and_bad_ones_say_so(tmp_path):
    syn = synthesize(seconds=1.0, rate=30.0, seed=1).take
    from capture import save_take
    path = save_take(syn, tmp_path / "take.npz")
    source = open_source(str(path), read_take=load_take)
    assert source.recording is not None and source.to_take().frames == 30
    np.testing.assert_array_equal(open_source(str(path)).to_take().positions, syn.positions)
    assert open_source("synthetic", seconds=0.5, rate=20.0).to_take().frames == 10
    with pytest.raises(InputError, match="missing.mp4"):
        open_source("missing.mp4")
    with pytest.raises(InputError, match="not a known kind of source"):
        open_source("x", {"synthetic": KINDS["synthetic"]})


class Printer:
    """A stand-in for a new motor sink (an OSC bridge, a browser viewer)."""

    def __init__(self, spec: str, rate: float = 60.0, **_) -> None:
        self.where, self.rate, self.written = spec, rate, []

    def write(self, t, values, captured=None, confidence=None):
        self.written.append((t, float(values[0])))

    def close(self):
        self.written.append("closed")

    def abort(self):
        self.written.append("aborted")


def test_outputs_open_by_kind_and_a_new_kind_is_one_registration(tmp_path):
    kinds = {"printer": SinkKind(f"{__name__}:Printer", lambda spec: spec.startswith("print:")), **MOTOR_SINKS}
    sink = open_sink("print:here", kinds, "a printer", rate=30.0, size=(8, 8))
    sink.write(0.5, np.ones(21))
    sink.close()
    assert (sink.where, sink.rate, sink.written) == ("print:here", 30.0, [(0.5, 1.0), "closed"])
    with pytest.raises(InputError, match=r"take\.txt: not a known output: expected a \.csv or \.npz"):
        Outputs().motor(str(tmp_path / "take.txt"))
    with pytest.raises(InputError, match="udp://nowhere: expected udp://HOST:PORT"):
        Outputs().motor("udp://nowhere")
    with pytest.raises(RuntimeError), Outputs() as outputs:
        recording = outputs.motor(str(tmp_path / "m.npz"), rate=10.0)
        recording.write(0.0, np.zeros(21))
        raise RuntimeError("a failure half way")
    assert not (tmp_path / "m.npz").exists()  # an error leaves nothing that looks complete
    with pytest.raises(KeyboardInterrupt), Outputs() as outputs:
        recording = outputs.motor(str(tmp_path / "m.npz"), rate=10.0)
        recording.write(0.0, np.zeros(21))
        raise KeyboardInterrupt
    assert (tmp_path / "m.npz").exists()  # Ctrl-C keeps what was recorded
