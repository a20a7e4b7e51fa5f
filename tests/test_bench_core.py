"""The benchmarks' shared helpers."""

import os

import pytest

from bench.core import one_core


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="this platform does not pin threads to CPUs")
def test_one_core_pins_the_body_to_one_cpu_and_gives_the_others_back_even_after_an_error():
    before = os.sched_getaffinity(0)
    if len(before) < 2:
        pytest.skip("one CPU: pinned or not looks the same")
    with one_core() as pinned:
        assert pinned and os.sched_getaffinity(0) == {min(before)}
    assert os.sched_getaffinity(0) == before
    with pytest.raises(RuntimeError), one_core():
        raise RuntimeError("a benchmark that fails")
    assert os.sched_getaffinity(0) == before
