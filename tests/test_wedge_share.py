"""The wedge's position: why it stays a prior, and what its share of A's variance means.

The misplaced wedge enters Boussinesq A's interval through a Gauss-Hermite correction
(:func:`lineload.fitting.boussinesq._boussinesq_sandwich_intervals`); the fit table reports
its share of A's variance apart (``boussinesq_A_wedge_share``) and in the priors' share.
Here, on simulated fingers: a known shift is recovered from the left-right difference of a
symmetric finger, but an asymmetric finger read without any shift fits as well with a shift
of the prior's size, so the shift is not identifiable apart from the finger's asymmetry;
the share is what the stated prior adds to the interval, keeps the coverage where the
shifts are as stated, and cannot warn when the prior is set to 0 and the wedge is misplaced.
"""

import numpy as np
import pytest

from lineload.fitting.batch import fit_trials
from lineload.noise import NoiseModel
from lineload.rawdata.readings import reading_distances_mm

DISTANCE_MM = reading_distances_mm(3.0, first_mm=0.1)
A_MM, X0_MM = 0.4, 4.0
READING_SD_MM = 0.005
#: The config's default wedge prior (mm), the size a shift is compared with.
WEDGE_PRIOR_MM = 0.01
#: Trials of the coverage checks: a 95 % coverage is then known to about +-1.1 %.
TRIALS = 400


def _profile(x):
    return A_MM * np.log(X0_MM / np.abs(x))


def _fitted_shift(difference_mm):
    """The shift and the RMS misfit of the noise fit's fixed effects (offset, rotation,
    quadratic and ``2 d w'(x)``) fitted to one left-minus-right difference."""
    x = DISTANCE_MM
    design = np.stack([np.ones_like(x), x, x**2, 2 * (-A_MM / x)], axis=1)
    coef, *_ = np.linalg.lstsq(design, difference_mm, rcond=None)
    return coef[3], np.sqrt(np.mean((difference_mm - design @ coef) ** 2))


def test_a_known_shift_of_a_symmetric_finger_is_recovered():
    x, shift = DISTANCE_MM, WEDGE_PRIOR_MM
    fitted, misfit = _fitted_shift(_profile(x + shift) - _profile(x - shift))
    # third order in d/x at the first reading: (d/x)^2 / 3 of d, under 1 %
    assert fitted == pytest.approx(shift, rel=0.01)
    assert misfit < 0.1 * READING_SD_MM


def test_an_asymmetric_finger_without_a_shift_fits_as_well_with_one():
    # one side 10 % softer (A larger), the wedge where it belongs: the fixed effects read
    # a shift comparable with the prior, and fit the difference to far below the noise,
    # so the readings cannot tell this finger from a symmetric one with a misplaced wedge
    x = DISTANCE_MM
    fitted, misfit = _fitted_shift(0.1 * _profile(x))
    assert abs(fitted) > 0.5 * WEDGE_PRIOR_MM
    assert misfit < 0.5 * READING_SD_MM
    # the symmetric finger read with that shift: the two differences agree to the misfit
    symmetric = _profile(x + fitted) - _profile(x - fitted)
    _, apart = _fitted_shift(0.1 * _profile(x) - symmetric)
    assert apart < 0.5 * READING_SD_MM


def _boussinesq_rows(shifts_mm, wedge_prior_mm, seed=5, **priors):
    """Fits of profiles whose two sides were read at ``x +- shift`` and averaged."""
    rng = np.random.default_rng(seed)
    x = DISTANCE_MM
    readings = [
        (_profile(x + s) + _profile(x - s)) / 2 + rng.normal(0, READING_SD_MM / np.sqrt(2), x.size)
        for s in shifts_mm
    ]
    noise = NoiseModel(reading_sd_mm=READING_SD_MM, wedge_position_sd_mm=wedge_prior_mm, **priors)
    count = len(readings)
    return fit_trials(
        [x] * count, readings, [1.0] * count, 3.0, noise=noise, n_sides=[np.full(x.size, 2)] * count
    )


def _column(rows, name):
    return np.array([row[f"boussinesq_{name}"] for row in rows])


def _coverage(rows):
    return np.mean((_column(rows, "A_ci_low_mm") <= A_MM) & (A_MM <= _column(rows, "A_ci_high_mm")))


def test_the_wedge_share_is_what_the_wedge_prior_adds_to_the_interval():
    other = {"shared_offset_sd_mm": 0.003, "depth_sd_mm": 0.01}
    with_wedge = _boussinesq_rows([0.0], 0.015, **other)[0]
    without = _boussinesq_rows([0.0], 0.0, **other)[0]
    share = with_wedge["boussinesq_A_wedge_share"]
    assert 0.05 < share < 0.95
    assert share < with_wedge["boussinesq_A_prior_share"]  # the other priors count too
    half = {
        key: ((row["boussinesq_A_ci_high_mm"] - row["boussinesq_A_ci_low_mm"]) / 2) ** 2
        for key, row in (("with", with_wedge), ("without", without))
    }
    # A's interval is centred on the line with the wedge's mean removed, which stretches A
    # by a fraction of a per cent: quadratic in the spread to that much
    assert 1 - half["without"] / half["with"] == pytest.approx(share, abs=0.01)
    assert without["boussinesq_A_wedge_share"] == 0.0


def test_the_share_grows_with_the_wedge_prior():
    shares = [_boussinesq_rows([0.0], sd)[0]["boussinesq_A_wedge_share"] for sd in (0.005, 0.01)]
    assert 0 < shares[0] < shares[1] < 1


def test_stated_at_its_size_the_wedge_prior_keeps_the_coverage():
    shifts = np.random.default_rng(17).normal(0.0, 0.015, TRIALS)
    rows = _boussinesq_rows(shifts, 0.015)
    assert 0.93 <= _coverage(rows) <= 0.975
    assert np.median(_column(rows, "A_wedge_share")) > 0.3


def test_a_wedge_prior_of_zero_gives_share_zero_and_intervals_that_miss():
    # the share can fail: with the prior set to 0 it is 0 however misplaced the wedge was,
    # and the intervals then cover far less than 95 %
    shifts = np.random.default_rng(17).normal(0.0, 0.015, TRIALS)
    rows = _boussinesq_rows(shifts, 0.0)
    assert np.all(_column(rows, "A_wedge_share") == 0.0)
    assert _coverage(rows) < 0.88


def test_the_fits_of_L_carry_no_wedge_share():
    row = _boussinesq_rows([0.0], WEDGE_PRIOR_MM)[0]
    assert not any(
        name.endswith("_wedge_share") and name.startswith(("waterbed", "arc", "shifted"))
        for name in row
    )
