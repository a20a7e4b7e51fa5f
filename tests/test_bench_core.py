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


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="this platform does not pin threads to CPUs")
def test_one_core_runs_its_body_on_one_blas_thread_even_after_a_fork():
    """The bench's one-core figures ran with the BLAS libraries' threads where they were: after
    any child process, on the pinned CPU beside the body (gap filling 68 frames/s, not 350)."""
    import subprocess
    import sys

    import numpy  # noqa: F401 (its BLAS loaded, as every bench group's)
    from threadpoolctl import threadpool_info

    def blas_threads() -> int:
        return max(lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas")

    before = blas_threads()
    if before < 2:
        pytest.skip("one BLAS thread already: the test could not fail")
    subprocess.run([sys.executable, "-c", "pass"], check=True, preexec_fn=lambda: None)  # a fork, as pinned_child's
    with one_core():
        assert blas_threads() == 1
    assert blas_threads() == before


def test_a_group_that_fails_is_named_the_others_still_run_and_the_exit_status_says_so(monkeypatch, capsys):
    import sys
    import types

    from bench import __main__ as bench_main
    from bench.core import Figure

    good = types.ModuleType("bench.fake_good")
    good.run = lambda quick=False: [Figure("fake.value", 1.0, "x", None, True, {})]  # type: ignore[attr-defined]
    bad = types.ModuleType("bench.fake_bad")

    def broken(quick=False):
        raise ValueError("expected 21 motor values, got shape (26,)")

    bad.run = broken  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "bench.fake_good", good)
    monkeypatch.setitem(sys.modules, "bench.fake_bad", bad)
    monkeypatch.setattr(bench_main, "GROUPS", ("fake_bad", "fake_good"))
    assert bench_main.main(["--quick"]) == 1
    out, err = capsys.readouterr()
    assert '"fake.value"' in out  # the group after the failure ran
    assert "group fake_bad failed" in err and "expected 21 motor values" in err
    assert err.strip().endswith("1 group(s) failed: fake_bad")
    monkeypatch.setattr(bench_main, "GROUPS", ("fake_good",))
    assert bench_main.main([]) == 0


def test_solver_min_r_names_every_seeds_lowest() -> None:
    """The lowest r's detail gives each seed's lowest motor, not only the lowest over the seeds: a
    second seed under the goal (0.927 beside 0.924) was hidden by the first."""
    from bench.generators import _lowest_each

    scored = [{"r": {"ELL": 0.927, "BLL": 0.99, "MB": 0.98}}, {"r": {"ELL": 0.99, "BLL": 0.924, "MB": 0.97}},
              {"r": {"ELL": 0.96, "BLL": 0.97, "MB": 0.955}}]
    assert _lowest_each(scored) == {"r_each": [0.927, 0.924, 0.955], "motor_each": ["ELL", "BLL", "MB"]}
