"""The share of each interval's variance that the stated priors make: the priors enter
the covariance linearly in their variances, so the share follows from refits with the
priors removed or scaled."""

import numpy as np
import pytest

from lineload.fitting.batch import fit_trials
from lineload.models import arc_deflection_mm
from lineload.noise import NoiseModel

DISTANCE_MM = np.linspace(0.1, 3.0, 20)
DEPTH_MM = 1.0
MEASURED = {
    "reading_sd_mm": 0.01,
    "tracing_sd_mm": 0.005,
    "tracing_length_mm": 0.5,
    "side_offset_sd_mm": 0.003,
}
PRIORS = {
    "shared_offset_sd_mm": 0.005,
    "shared_tilt_sd": 0.0005,
    "depth_sd_mm": 0.01,
    "wedge_position_sd_mm": 0.01,
}
COLUMNS = {
    "waterbed_L_prior_share": "waterbed_L",
    "shifted_L_prior_share": "shifted_L",
    "arc_L_prior_share": "arc_L",
    "boussinesq_A_prior_share": "boussinesq_A",
}


def _fit(priors, scale=1.0):
    rng = np.random.default_rng(3)
    y = arc_deflection_mm(DISTANCE_MM, DEPTH_MM, 11.0) + rng.normal(0, 0.007, DISTANCE_MM.size)
    noise = NoiseModel(**MEASURED, **{k: scale * v for k, v in priors.items()})
    return fit_trials([DISTANCE_MM], [y], [DEPTH_MM], 3.0, noise=noise)[0]


def _half_width_squared(row, name):
    return ((row[f"{name}_ci_high_mm"] - row[f"{name}_ci_low_mm"]) / 2) ** 2


@pytest.mark.parametrize("column", COLUMNS)
def test_prior_share_is_what_removing_the_priors_takes_from_the_interval(column):
    full, measured_only = _fit(PRIORS), _fit(dict.fromkeys(PRIORS, 0.0))
    share = full[column]
    assert 0.05 < share < 0.95  # both parts matter at these sizes
    name = COLUMNS[column]
    removed = 1.0 - _half_width_squared(measured_only, name) / _half_width_squared(full, name)
    # the intervals follow the profile's shape (L) or a wedge-shifted centre (A), so
    # their widths are quadratic in the spread to a few per cent only
    assert removed == pytest.approx(share, abs=0.03)
    assert np.isnan(measured_only[column]) or measured_only[column] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("column", ["waterbed_L_prior_share", "arc_L_prior_share"])
def test_prior_share_scales_as_the_priors_variances(column):
    # without the wedge (which enters A through a non-linear correction), doubling every
    # prior's SD multiplies its variance by 4: share' = 4 p / (4 p + 1 - p)
    priors = {**PRIORS, "wedge_position_sd_mm": 0.0}
    p = _fit(priors)[column]
    doubled = _fit(priors, scale=2.0)[column]
    assert doubled == pytest.approx(4 * p / (4 * p + 1 - p), rel=1e-6)


def test_no_noise_model_no_share():
    row = fit_trials([DISTANCE_MM], [arc_deflection_mm(DISTANCE_MM, 1.0, 11.0)], [1.0], 3.0)[0]
    assert all(np.isnan(row[column]) for column in COLUMNS)
