"""What the hypothesis tests share: settings that give the same examples on every run, and seed
files that print short in a failure report."""

from hypothesis import HealthCheck, settings


def fuzz_settings(examples: int) -> settings:
    """``examples`` per test, derandomized (the same on every run and machine), no deadline."""
    return settings(max_examples=examples, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


class Seeds(dict):
    """Seed files' bytes by kind, shown as ``<seed files>`` in hypothesis's failure report."""

    def __repr__(self) -> str:
        return "<seed files>"
