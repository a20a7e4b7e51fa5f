"""Ranges learned live (a camera with no profile), by hand."""

import numpy as np
import pytest

from mapping.learning import RangeLearner
from mapping.profile import Profile, SourceRange


def _learner(**options) -> RangeLearner:
    return RangeLearner(Profile("face", {"LID.y": SourceRange(10.0, 10.0, 10.0)}, np.eye(3)), **options)


def test_a_range_starts_min_side_about_rest_widens_at_once_and_eases_back():
    learner = _learner(min_side=2.0, decay_seconds=10.0, freeze_after=100.0)
    assert learner.profile.sources["LID.y"] == SourceRange(10.0, 8.0, 12.0)
    span = learner.update({"LID.y": 17.0}, 0.0).sources["LID.y"]
    assert (span.low, span.high) == (8.0, 17.0)  # at once, no lag
    span = learner.update({"LID.y": 10.0}, 1.0).sources["LID.y"]  # a tenth of the excess goes in 1 s
    assert span.high == pytest.approx(12.0 + 5.0 * 0.9) and span.low == 8.0
    span = learner.update({"LID.y": 3.0}, 2.0).sources["LID.y"]
    assert span.low == 3.0 and span.high == pytest.approx(12.0 + 4.5 * 0.9)
    span = learner.update({"LID.y": float("nan")}, 3.0).sources["LID.y"]  # unseen: nothing learned
    assert span.low == 3.0


def test_learning_stops_after_its_time():
    learner = _learner(min_side=1.0, freeze_after=5.0)
    learner.update({"LID.y": 12.0}, 0.0)
    learner.update({"LID.y": 13.0}, 5.0)
    assert learner.frozen
    assert learner.update({"LID.y": 30.0}, 6.0).sources["LID.y"].high == 13.0
