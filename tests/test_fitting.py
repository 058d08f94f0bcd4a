"""Each fit recovers known parameters from profiles made by its own model."""

import numpy as np
import pytest

from lineload import models
from lineload.fitting import batch as fitting
from lineload.simulation import synthetic

# the reading grid of the study within the 3 mm fit window (tissue mm)
DISTANCE_MM = np.round(np.r_[np.arange(0.05, 0.5001, 0.05), np.arange(0.75, 3.0001, 0.25)], 6)
NOISE_MM = 0.01


def noisy(profile_mm, seed):
    return profile_mm + np.random.default_rng(seed).normal(0.0, NOISE_MM, profile_mm.size)


@pytest.mark.parametrize("depth_mm", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("L_mm", [8.0, 12.0, 15.0])
def test_waterbed_recovers_L(depth_mm, L_mm):
    exact = models.waterbed_deflection_mm(DISTANCE_MM, depth_mm, L_mm)
    assert fitting.fit_waterbed(DISTANCE_MM, exact, depth_mm).params["L_mm"] == pytest.approx(
        L_mm, rel=1e-9
    )
    estimates = [
        fitting.fit_waterbed(DISTANCE_MM, noisy(exact, seed), depth_mm).params["L_mm"]
        for seed in range(20)
    ]
    # unbiased within its scatter, and each estimate close
    assert abs(np.mean(estimates) - L_mm) < 3 * np.std(estimates) / np.sqrt(20) + 1e-3 * L_mm
    assert np.all(np.abs(np.array(estimates) / L_mm - 1) < 0.05)


@pytest.mark.parametrize("seed", range(5))
def test_waterbed_minimum_is_global(seed):
    # compare with a brute-force scan of the objective over L
    rng = np.random.default_rng(100 + seed)
    depth_mm = rng.uniform(0.5, 2.0)
    y = noisy(depth_mm * np.exp(-DISTANCE_MM / rng.uniform(1.0, 3.0)), seed)
    fit = fitting.fit_waterbed(DISTANCE_MM, y, depth_mm)
    scan_L = np.geomspace(DISTANCE_MM.max(), 1e4, 200001)
    scan_sse = [
        np.sum((y - models.waterbed_deflection_mm(DISTANCE_MM, depth_mm, L)) ** 2)
        for L in scan_L[::50]
    ]
    assert fit.sse_mm2 <= min(scan_sse) + 1e-12
    assert fit.params["L_mm"] >= DISTANCE_MM.max()


def test_waterbed_respects_the_wall():
    # data that want a membrane narrower than the fitted region: L stops at max(x)
    y = models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 2.0)
    fit = fitting.fit_waterbed(DISTANCE_MM, y, 1.0)
    assert fit.params["L_mm"] == pytest.approx(DISTANCE_MM.max())


@pytest.mark.parametrize("depth_mm", [0.5, 2.0])
@pytest.mark.parametrize("L_mm", [6.0, 12.0])
def test_arc_recovers_L(depth_mm, L_mm):
    exact = models.arc_deflection_mm(DISTANCE_MM, depth_mm, L_mm)
    assert fitting.fit_arc(DISTANCE_MM, exact, depth_mm).params["L_mm"] == pytest.approx(
        L_mm, rel=1e-7
    )
    estimates = np.array(
        [fitting.fit_arc(DISTANCE_MM, noisy(exact, s), depth_mm).params["L_mm"] for s in range(10)]
    )
    assert np.all(np.abs(estimates / L_mm - 1) < 0.05)


@pytest.mark.parametrize("depth_mm", [0.5, 1.0, 2.0])
@pytest.mark.parametrize("L_mm", [8.0, 12.0, 15.0])
def test_shifted_recovers_L(depth_mm, L_mm):
    exact = models.shifted_deflection_mm(DISTANCE_MM, depth_mm, L_mm)
    assert fitting.fit_shifted(DISTANCE_MM, exact, depth_mm).params["L_mm"] == pytest.approx(
        L_mm, rel=1e-7
    )
    estimates = np.array(
        [
            fitting.fit_shifted(DISTANCE_MM, noisy(exact, s), depth_mm).params["L_mm"]
            for s in range(10)
        ]
    )
    assert np.all(np.abs(estimates / L_mm - 1) < 0.05)


@pytest.mark.parametrize("L_mm", [10.0, 12.0, 14.0])
def test_papers_procedure_underestimates_L_of_shifted_profiles(L_mm):
    # profiles that are exactly the small-slope solution in measured coordinates: read
    # as if x were X, eq. 19 gives a narrower membrane, by more the deeper the load
    shortfall, first_order = [], []
    for depth_mm in (0.5, 1.0, 1.5, 2.0):
        exact = models.shifted_deflection_mm(DISTANCE_MM, depth_mm, L_mm)
        paper_L = fitting.fit_waterbed(DISTANCE_MM, exact, depth_mm).params["L_mm"]
        shortfall.append(1.0 - paper_L / L_mm)
        # matching the zero crossings, L/3 + U(L/3) = L_paper / 3, gives to first order
        # 1 - L_paper / L = (8/3) (W0/L)^2, the paper's own |U| / X at L/3
        first_order.append(8.0 / 3.0 * (depth_mm / L_mm) ** 2)
    assert np.all(np.diff(shortfall) > 0) and shortfall[0] > 0
    # the fit gives up more than the zero crossing alone suggests, but not wildly more
    ratio = np.array(shortfall) / np.array(first_order)
    assert np.all((ratio > 1.0) & (ratio < 2.0)), ratio


def test_shifted_fit_stops_at_the_fold():
    # data that want L below sqrt(6) W0, where x(X) folds (a steep straight drop far
    # below the resting surface): L ends at that bound
    depth_mm = 2.0
    y = depth_mm - 3.0 * DISTANCE_MM
    fit = fitting.fit_shifted(DISTANCE_MM, y, depth_mm)
    fold_mm = np.sqrt(6.0) * depth_mm
    assert fit.params["L_mm"] == pytest.approx(fold_mm, rel=1e-6)
    assert fit.params["L_ci_low_mm"] == pytest.approx(fold_mm, rel=1e-6)
    assert np.isfinite(fit.rmse_mm)


def test_arc_and_parabola_disagree_at_large_depth():
    # the parabola fitted to an exact arc at W0/L = 0.2 misses by more than the noise
    exact = models.arc_deflection_mm(DISTANCE_MM, 2.0, 10.0)
    assert fitting.fit_arc(DISTANCE_MM, exact, 2.0).rmse_mm < 1e-8
    assert fitting.fit_waterbed(DISTANCE_MM, exact, 2.0).rmse_mm > 2 * NOISE_MM


@pytest.mark.parametrize("A_mm, x0_mm", [(0.2, 4.0), (0.5, 9.0)])
def test_boussinesq_recovers_A_and_x0(A_mm, x0_mm):
    exact = models.boussinesq_deflection_mm(DISTANCE_MM, A_mm, x0_mm)
    fit = fitting.fit_boussinesq(DISTANCE_MM, exact)
    assert fit.params["A_mm"] == pytest.approx(A_mm, rel=1e-10)
    assert fit.params["x0_mm"] == pytest.approx(x0_mm, rel=1e-10)
    fits = [fitting.fit_boussinesq(DISTANCE_MM, noisy(exact, s)) for s in range(10)]
    assert np.all([abs(f.params["A_mm"] / A_mm - 1) < 0.1 for f in fits])
    assert np.all([abs(f.params["x0_mm"] / x0_mm - 1) < 0.1 for f in fits])


def test_models_tell_each_other_apart():
    waterbed = noisy(models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 12.0), 1)
    boussinesq = noisy(models.boussinesq_deflection_mm(DISTANCE_MM, 0.25, 5.0), 2)
    assert (
        fitting.fit_waterbed(DISTANCE_MM, waterbed, 1.0).aicc
        < fitting.fit_boussinesq(DISTANCE_MM, waterbed).aicc
    )
    assert (
        fitting.fit_boussinesq(DISTANCE_MM, boussinesq).aicc
        < fitting.fit_waterbed(DISTANCE_MM, boussinesq, boussinesq[0]).aicc
    )


def test_goodness_of_fit_matches_gaussian_likelihood():
    residual = np.random.default_rng(3).normal(0, 0.02, 25)
    n, p = residual.size, 2
    measures = fitting.goodness_of_fit(residual, n_params=p)
    sigma2 = np.mean(residual**2)
    log_likelihood = -0.5 * n * (np.log(2 * np.pi * sigma2) + 1)
    k = p + 1
    aicc = -2 * log_likelihood + 2 * k + 2 * k * (k + 1) / (n - k - 1)
    # AICc up to the constant n (ln 2 pi + 1), which cancels in comparisons
    assert measures["aicc"] == pytest.approx(aicc - n * (np.log(2 * np.pi) + 1))
    assert measures["rmse_mm"] == pytest.approx(np.sqrt(sigma2))
    assert measures["max_abs_residual_mm"] == np.abs(residual).max()


def test_fit_trial_uses_only_the_window():
    x = np.r_[0.0, DISTANCE_MM, 3.5, 5.0, 8.0]
    y = np.r_[1.0, models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 12.0), 0.0, 0.0, 0.0]
    row = fitting.fit_trial(x, y, 1.0, 3.0)
    y_changed = y.copy()
    y_changed[[0, -3, -2, -1]] = [5.0, 9.0, 9.0, 9.0]
    assert fitting.fit_trial(x, y_changed, 1.0, 3.0) == row
    assert row["n_points"] == DISTANCE_MM.size
    assert row["max_distance_mm"] == 3.0
    assert row["waterbed_L_mm"] == pytest.approx(12.0)
    assert set(row) == set(fitting.FIT_COLUMNS) - {"subject", "species"}


def test_fit_trial_with_too_few_points_gives_nan():
    row = fitting.fit_trial([0.1, 5.0], [0.9, 0.0], 1.0, 3.0)
    assert row["n_points"] == 1
    assert np.isnan(row["boussinesq_A_mm"])
    assert np.isfinite(row["waterbed_L_mm"])


@pytest.mark.parametrize(
    "x, y",
    [([0.1, 0.2], [1.0]), ([0.0, 0.2], [1.0, 0.9]), ([0.1, np.nan], [1.0, 0.9])],
)
def test_bad_points_are_refused(x, y):
    with pytest.raises(ValueError):
        fitting.fit_waterbed(x, y, 1.0)


def test_chi_square_quantile():
    from scipy.stats import chi2

    assert fitting.CHI2_1DOF_95 == pytest.approx(chi2.ppf(0.95, 1), rel=1e-12)


@pytest.mark.parametrize(
    "fit, model",
    [
        (fitting.fit_waterbed, models.waterbed_deflection_mm),
        (fitting.fit_arc, models.arc_deflection_mm),
        (fitting.fit_shifted, models.shifted_deflection_mm),
    ],
)
def test_confidence_interval_covers_the_truth_about_95_percent(fit, model):
    rng = np.random.default_rng(2024)
    depth_mm, L_mm, trials = 1.5, 12.0, 120
    covered = 0
    for _ in range(trials):
        y = model(DISTANCE_MM, depth_mm, L_mm) + rng.normal(0, NOISE_MM, DISTANCE_MM.size)
        params = fit(DISTANCE_MM, y, depth_mm).params
        assert params["L_ci_low_mm"] < params["L_mm"] < params["L_ci_high_mm"]
        covered += params["L_ci_low_mm"] <= L_mm <= params["L_ci_high_mm"]
    # binomial(120, 0.95): 3 standard deviations either side is 0.89 to 1.0
    assert 0.89 <= covered / trials <= 0.995


def _boussinesq_z_scores(wedge_sd_mm, assumed_sd_mm, trials=400):
    """z = (true A - interval centre) / (half-width / 1.96) of Boussinesq profiles read
    with independent noise and a wedge misplaced by ``wedge_sd_mm`` (mean of two sides),
    fitted with the wedge's standard deviation taken as ``assumed_sd_mm``."""
    from lineload.noise import NoiseModel

    rng = np.random.default_rng(1989)
    x = synthetic.reading_distances_mm(3.0)
    A_mm, x0_mm, noise_mm = 0.4, 6.0, 0.006
    noise = NoiseModel(reading_sd_mm=noise_mm, wedge_position_sd_mm=assumed_sd_mm)
    means = []
    for _ in range(trials):
        delta = rng.normal(0.0, wedge_sd_mm)
        sides = [
            models.boussinesq_deflection_mm(np.clip(x + s * delta, 1e-3, None), A_mm, x0_mm)
            + rng.normal(0.0, noise_mm, x.size)
            for s in (1.0, -1.0)
        ]
        means.append(0.5 * (sides[0] + sides[1]))
    fits = fitting.fit_windowed([x] * trials, means, 1.0, 3.0, ("boussinesq",), noise=noise)
    params = fits["boussinesq"].params
    low, high = params["A_ci_low_mm"], params["A_ci_high_mm"]
    return (A_mm - 0.5 * (low + high)) / (0.5 * (high - low)) * np.sqrt(fitting.CHI2_1DOF_95)


def test_boussinesq_interval_allows_for_the_wedge_position():
    # the left-right mean of a log-singular profile read with the wedge misplaced by d
    # keeps A d^2 / (2 x^2): the least-squares A is biased up.  With the wedge's SD
    # known the interval is centred on the truth (mean z within 4 SE of 0, SE
    # 1/sqrt(400)) and as wide as the scatter (SD of z within 10 % of 1)
    z = _boussinesq_z_scores(0.01, 0.01)
    assert abs(np.mean(z)) < 4 / np.sqrt(z.size)
    assert abs(np.std(z) - 1.0) < 0.1
    # the same readings with the wedge ignored: the bias is plain
    ignored = _boussinesq_z_scores(0.01, 0.0)
    assert np.mean(ignored) < -4 / np.sqrt(ignored.size)


def test_confidence_interval_ends_are_likelihood_ratio_crossings():
    y = noisy(models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 12.0), 5)
    fit = fitting.fit_waterbed(DISTANCE_MM, y, 1.0)
    n = DISTANCE_MM.size
    for end in ("L_ci_low_mm", "L_ci_high_mm"):
        sse = np.sum((y - models.waterbed_deflection_mm(DISTANCE_MM, 1.0, fit.params[end])) ** 2)
        assert n * np.log(sse / fit.sse_mm2) == pytest.approx(fitting.CHI2_1DOF_95, rel=1e-6)


def test_confidence_interval_stops_at_the_wall():
    # a profile that pushes L to its lower bound: the interval ends there too
    y = models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 2.0)
    fit = fitting.fit_waterbed(DISTANCE_MM, y + noisy(np.zeros_like(y), 0), 1.0)
    assert fit.params["L_mm"] == pytest.approx(DISTANCE_MM.max())
    assert fit.params["L_ci_low_mm"] == pytest.approx(DISTANCE_MM.max())


def test_each_trial_can_have_its_own_noise_model():
    # two copies of one profile, one with a large shared offset and one with a small:
    # each interval is what that trial fitted alone under its own model gives
    from lineload.noise import NoiseModel

    x = DISTANCE_MM
    y = noisy(models.waterbed_deflection_mm(x, 1.0, 12.0), 3)
    wide = NoiseModel(reading_sd_mm=0.005, shared_offset_sd_mm=0.02)
    narrow = NoiseModel(reading_sd_mm=0.005, shared_offset_sd_mm=0.001)
    both = fitting.fit_windowed([x, x], [y, y], 1.0, 3.0, ("waterbed",), noise=[wide, narrow])
    width = both["waterbed"].params["L_ci_high_mm"] - both["waterbed"].params["L_ci_low_mm"]
    assert width[0] > 1.5 * width[1]
    for model, i in ((wide, 0), (narrow, 1)):
        alone = fitting.fit_windowed([x], [y], 1.0, 3.0, ("waterbed",), noise=model)
        for end in ("L_ci_low_mm", "L_ci_high_mm"):
            assert alone["waterbed"].params[end][0] == pytest.approx(
                both["waterbed"].params[end][i], rel=1e-9
            )
    with pytest.raises(ValueError, match="one per trial"):
        fitting.fit_windowed([x, x], [y, y], 1.0, 3.0, ("waterbed",), noise=[wide])
