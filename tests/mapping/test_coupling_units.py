"""A coupling is a distance the driver carries a source, whichever side of rest the source
stands (:mod:`mapping.coupling`): measured and taken away in the source's own units, so that a
source whose range differs either side of rest (an upper lid shuts by 3.5 mm, opens by 0.6)
reads right when it blinks under raised brows. Values by hand."""

import numpy as np
import pytest

from mapping import load_mapping
from mapping.coupling import decoupled, learn_couplings
from mapping.plan import reach_of
from mapping.profile import Profile, SourceRange

UP, DOWN = 0.6, 3.5  # the lid's range above and below its rest, mm
CARRIED = 0.9  # mm the lid rises per unit of the brow's rise


@pytest.fixture(scope="module")
def lid():
    mapping = load_mapping("toon32")
    rule = next(r for r in mapping.rules if r.code == "ERU")
    brow = next(r for r in mapping.rules if r.code == "BRC").sources[0]
    profile = Profile("toon32", {rule.sources[0].key: SourceRange(2.0, 2.0 - DOWN, 2.0 + UP),
                                 brow.key: SourceRange(0.0, -4.0, 12.0)}, np.eye(3), full_range=True)
    return mapping, rule, brow, profile


def _normalised(mm: np.ndarray) -> np.ndarray:
    """The lid's distance from rest as :func:`mapping.mapper.normalise` gives it: a share of its
    range on the side it stands."""
    return np.where(mm >= 0, mm / UP, mm / DOWN)


def test_the_sources_reach_either_side_is_its_range(lid):
    mapping, rule, _, profile = lid
    assert reach_of(rule.sources[0], rule, profile) == pytest.approx((UP, DOWN))


def test_a_brow_sweep_teaches_the_lift_as_a_share_of_the_side_it_lifts_toward(lid):
    """Brows raised with the lid at rest lift it 0.9 mm: 1.5 of its 0.6 mm upper range."""
    mapping, rule, brow, profile = lid
    d = np.linspace(0.0, 1.0, 40)  # the brow rising (its normalised value)
    lowered = np.linspace(0.0, -1.0, 40)  # and lowered: carries nothing
    values = {brow.key: np.concatenate([d, lowered]),
              rule.sources[0].key: _normalised(np.concatenate([CARRIED * d, np.zeros(40)]))}
    for source in (s for r in mapping.rules for s in r.sources):
        values.setdefault(source.key, np.zeros(80))
    couplings = learn_couplings(mapping, profile, values)
    below, above = couplings[rule.sources[0].key][brow.key]
    assert above == pytest.approx(CARRIED / UP) and below == pytest.approx(0.0, abs=1e-12)


def test_a_blink_under_raised_brows_reads_as_far_shut_as_it_is(lid):
    """The lid 3 mm shut, the brows fully raised lift it back 0.9 mm: seen 2.1 mm below rest.
    Taken away in millimetres the lid reads 3 mm shut (-0.857 of its way); taken away as a share
    of the lower side (1.5 of 3.5 mm) it read 5.25 mm shut, past its whole range."""
    _, rule, brow, profile = lid
    profile = Profile(profile.markerset, profile.sources, profile.rest_rotation, full_range=True,
                      couplings={rule.sources[0].key: {brow.key: (0.0, CARRIED / UP)}})
    own = np.array([-3.0, -1.0, 0.0, 0.3])  # the lid's own motion, mm
    brows = np.array([1.0, 0.5, 1.0, 0.0])
    seen = _normalised(own + CARRIED * brows)
    out = decoupled(seen, rule.sources[0], {brow.key: brows}, profile, reach_of(rule.sources[0], rule, profile))
    assert out == pytest.approx(_normalised(own))
    assert out[0] == pytest.approx(-3.0 / DOWN)


def test_a_side_of_the_drivers_range_no_wider_than_its_jitter_teaches_nothing():
    """A jaw closed at rest (the third performer's) opens 20.6 mm and closes no further than its
    0.2 mm of jitter: the lower lip's noise above rest is no motion of the jaw, so whatever a
    mouth corner happened to do then is not learnt as carried by it (it was: the corners then
    rose and fell with the lower lip's jitter). The side the jaw opens on is learnt as before."""
    mapping = load_mapping("toon32")
    corner = next(r for r in mapping.rules if r.code == "MRV")
    lip = next(r for r in mapping.rules if r.code == "MB").sources[0]  # inverted: opening is positive
    profile = Profile("toon32", {corner.sources[0].key: SourceRange(-64.0, -71.0, -56.0),
                                 lip.key: SourceRange(-72.0, -92.6, -71.8)}, np.eye(3), full_range=True)
    assert reach_of(lip, next(r for r in mapping.rules if r.code == "MB"), profile) == pytest.approx((20.6, 0.2))
    opening, jitter = np.linspace(0.0, 1.0, 40), -np.linspace(0.3, 1.5, 40)  # the lip's noise over 0.2 mm
    values = {lip.key: np.concatenate([opening, jitter]),
              corner.sources[0].key: np.concatenate([-3.0 / 7.0 * opening, 0.2 * jitter])}  # down 3 of 7 mm
    for source in (s for r in mapping.rules for s in r.sources):
        values.setdefault(source.key, np.zeros(80))
    key = corner.sources[0].key
    below, above = learn_couplings(mapping, profile, values, {lip.key: 0.3})[key][lip.key]
    assert below == 0.0 and above == pytest.approx(-3.0 / 7.0)
    unknown = learn_couplings(mapping, profile, values)[key][lip.key]  # no jitter given: both sides as measured
    assert unknown[0] == pytest.approx(0.2) and unknown[1] == pytest.approx(-3.0 / 7.0)
