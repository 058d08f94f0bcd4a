"""The digitiser's stated uncertainties against rendered truth (docs/calibration/digitiser.md).

Pairs rendered from known fingers with seeds the committed calibration does not use are
digitised as the workflow does; each stated SD must cover its error at about the nominal
95 %, and the same check must fail when the SDs are made too small.
"""

import numpy as np
import pytest

from lineload.io import config_defaults
from lineload.rawdata.photographs import _registration_sd_mm, _sample
from lineload.simulation.digitiser import coverage_summary, digitiser_calibration

#: Pairs rendered here; the committed calibration (docs/calibration/scripts/digitiser.py)
#: uses seeds 0 on, these are held out.
PAIRS, FIRST_SEED = 60, 5000
#: The issue's band for a nominal 95 % interval: within 90-98.5 %.
LOW, HIGH = 0.90, 0.985
#: The registration is one error per pair: of 60 draws at 95 %, fewer than 51 covered
#: has a probability under 0.2 % (binomial).
REGISTRATION_LOW = 51 / PAIRS


@pytest.fixture(scope="module")
def calibration():
    return digitiser_calibration(PAIRS, config_defaults("digitise"), first_seed=FIRST_SEED)


def test_the_stated_uncertainties_cover_at_their_nominal_rate(calibration):
    summary = coverage_summary(*calibration)
    assert summary["read"] == PAIRS
    assert summary["readings"] > 30 * PAIRS
    assert LOW <= summary["own"] <= HIGH, summary
    assert LOW <= summary["total"] <= HIGH, summary
    assert summary["registration"] >= REGISTRATION_LOW, summary


@pytest.mark.parametrize("multiple", [0.5, 0.7])
def test_uncertainties_stated_too_small_fail_the_coverage(calibration, multiple):
    """The check can come out the other way: SDs too small by a third or a half cover
    visibly less than the band asks."""
    summary = coverage_summary(*calibration, multiple=multiple)
    assert summary["own"] < LOW and summary["total"] < LOW, summary
    if multiple == 0.5:
        assert summary["registration"] < REGISTRATION_LOW, summary


def test_uncertainties_stated_too_large_fail_the_coverage(calibration):
    summary = coverage_summary(*calibration, multiple=2.0)
    assert summary["own"] > HIGH and summary["total"] > HIGH, summary


def test_a_reading_is_the_outline_at_its_distance_not_at_its_columns_mean():
    """On a straight sloped outline whose columns are not centred on the reading, the
    reading is the line at the reading's distance (the columns' mean would be off by
    the slope times the offset)."""
    x = np.arange(0.0, 2.0, 0.013) + 0.004
    z = 0.3 * x - 0.1
    at = np.array([0.5, 0.75, 1.0, 1.5])
    values, counts = _sample(x, z, at, 0.02)
    assert np.all(counts >= 3)
    np.testing.assert_allclose(values, 0.3 * at - 0.1, rtol=0, atol=1e-12)
    # one column only: its value, as before
    single, _ = _sample(x, z, np.array([x[10]]), 0.001)
    assert single[0] == pytest.approx(z[10])


def test_the_registration_sd_is_the_least_squares_sd_for_white_errors():
    """With independent errors the sandwich is the textbook ``sigma^2 (X'X)^-1``; with
    errors correlated along the outline it is larger."""
    rng = np.random.default_rng(3)
    n = 4000
    design = np.column_stack([np.ones(n), rng.uniform(-0.5, 0.5, n)])
    white = rng.normal(0.0, 1e-3, n)
    expected = 1e-3 * np.sqrt(np.linalg.inv(design.T @ design)[0, 0])
    assert _registration_sd_mm(design, white, np.arange(n)) == pytest.approx(expected, rel=0.1)
    smooth = np.convolve(rng.normal(0.0, 1e-3, n + 20), np.ones(21) / np.sqrt(21), "valid")
    assert _registration_sd_mm(design, smooth, np.arange(n)) > 3 * expected
