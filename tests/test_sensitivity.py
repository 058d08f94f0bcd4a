"""Refits under other analysis choices, and the per-trial shift and reach."""

import numpy as np
import pandas as pd
import pytest

from conftest import run_snakemake, write_small_dataset
from lineload import models
from lineload.fitting import batch as fitting
from lineload.fitting import sensitivity

DISTANCE_MM = np.round(
    np.r_[np.arange(0.05, 0.5001, 0.05), np.arange(0.75, 3.0001, 0.25), np.arange(3.5, 8.01, 0.5)],
    6,
)


def test_free_depth_fit_recovers_both_parameters():
    y = models.waterbed_deflection_mm(DISTANCE_MM, 1.3, 11.0)
    fit = fitting.fit_waterbed_free_depth(DISTANCE_MM, y)
    assert fit.params["W0_mm"] == pytest.approx(1.3, rel=1e-8)
    assert fit.params["L_mm"] == pytest.approx(11.0, rel=1e-8)
    rng = np.random.default_rng(8)
    noisy = fitting.fit_waterbed_free_depth(DISTANCE_MM, y + rng.normal(0, 0.01, y.size))
    assert noisy.params["W0_mm"] == pytest.approx(1.3, rel=0.02)
    assert noisy.params["L_ci_low_mm"] < 11.0 < noisy.params["L_ci_high_mm"]


def test_every_model_in_every_window():
    y = models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 12.0)
    y = y + np.random.default_rng(1).normal(0, 0.01, y.size)
    rows = pd.DataFrame(sensitivity.sensitivity_rows(DISTANCE_MM, y, 1.0, [2.0, 3.0, np.inf]))
    assert len(rows) == 3 * len(sensitivity.MODELS)
    assert list(rows["window"].unique()) == ["2 mm", "3 mm", "whole"]
    counts = rows.groupby("window")["n_points"].first()
    assert counts["2 mm"] == np.sum(DISTANCE_MM <= 2.0)
    assert counts["whole"] == DISTANCE_MM.size
    # the best model of each window has delta 0, the others more
    assert (rows.groupby("window")["delta_aicc"].min() == 0).all()
    assert (rows["delta_aicc"] >= 0).all()
    # on waterbed data the fixed-depth parabola recovers L in every window
    waterbed = rows[rows["model"] == "waterbed"]
    assert np.allclose(waterbed["L_mm"], 12.0, rtol=0.03)
    assert rows[rows["model"] == "boussinesq"]["L_mm"].isna().all()


def test_reach_stops_before_the_first_miss():
    distance = np.array([0.5, 0.1, 2.0, 1.0, 3.0])
    residual = np.array([0.01, 0.0, 0.2, -0.05, 0.0])
    assert sensitivity.agreement_reach_mm(distance, residual, 0.1) == 1.0
    assert sensitivity.agreement_reach_mm(distance, residual, 0.3) == 3.0
    assert sensitivity.agreement_reach_mm(distance, residual + 1.0, 0.1) == 0.0


def test_trial_checks_match_the_analytic_shift():
    y = models.waterbed_deflection_mm(DISTANCE_MM, 2.0, 12.0)
    checks = sensitivity.trial_checks(DISTANCE_MM, y, 2.0, 3.0, 0.1)
    assert checks["waterbed_L_mm"] == pytest.approx(12.0)
    shift = -models.waterbed_shift_mm([12.0 / 3], 2.0, 12.0)[0]
    assert checks["shift_at_third_mm"] == pytest.approx(shift)
    assert checks["shift_fraction_at_third"] == pytest.approx(8 * 2.0**2 / (3 * 12.0**2))
    # a profile made by the model is matched everywhere, so the reach is the whole profile
    assert checks["reach_mm"] == DISTANCE_MM.max()
    assert checks["n_beyond_window"] == np.sum(DISTANCE_MM > 3.0)


@pytest.mark.e2e
def test_sensitivity_tables_on_a_small_dataset(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    out = tmp_path / "out"
    process = run_snakemake(str(out / "tables" / "sensitivity.md"), raw=raw, results=out)
    assert process.returncode == 0, process.stderr[-2000:]
    table = pd.read_csv(out / "tables" / "sensitivity.csv")
    n_trials = 3  # MK at 1 and 2 mm, HU at 1 mm
    assert len(table) == n_trials * 3 * len(sensitivity.MODELS)
    checks = pd.read_csv(out / "tables" / "trial_checks.csv")
    assert list(zip(checks["subject"], checks["depth_mm"], strict=True)) == [
        ("MK", 1.0),
        ("MK", 2.0),
        ("HU", 1.0),
    ]
    assert "Synthetic" not in (out / "tables" / "sensitivity.md").read_text()


def test_curve_gap_follows_the_first_order_expansion():
    # W(X) at x = X + U: to first order W(x) - W'(x) U(x), a gap of
    # 6 W0^3 / L^2 * max |(6s - 4) s (s - 1)^2| over the fitted range
    L_mm, x_max = 12.0, 3.0
    s = np.linspace(0, x_max / L_mm, 100001)
    shape = np.max(np.abs((6 * s - 4) * s * (s - 1) ** 2))
    for depth_mm in (0.05, 0.1):
        gap = sensitivity.curve_gap_mm(depth_mm, L_mm, L_mm, x_max, "shifted", n_points=4001)
        assert gap == pytest.approx(6 * depth_mm**3 / L_mm**2 * shape, rel=0.02)
    # against the arc, the gap is the definition evaluated directly; a missing L gives NaN
    assert sensitivity.curve_gap_mm(1.0, 12.0, 12.0, 3.0, "arc") == pytest.approx(
        np.max(
            np.abs(
                models.arc_deflection_mm(np.linspace(0, 3, 601), 1.0, 12.0)
                - models.waterbed_deflection_mm(np.linspace(0, 3, 601), 1.0, 12.0)
            )
        )
    )
    assert np.isnan(sensitivity.curve_gap_mm(1.0, np.nan, 12.0, 3.0, "shifted"))


def test_trial_checks_see_what_the_coordinates_cost():
    # readings that are the small-slope solution in measured coordinates at 2 mm
    y = models.shifted_deflection_mm(DISTANCE_MM, 2.0, 12.0)
    checks = sensitivity.trial_checks(DISTANCE_MM, y, 2.0, 3.0, 0.1)
    assert checks["shifted_L_mm"] == pytest.approx(12.0, rel=1e-6)
    # the paper's procedure is short by more than the first-order (8/3) (W0/L)^2
    assert checks["waterbed_L_mm"] < 12.0 * (1.0 - 8.0 / 3.0 * (2.0 / 12.0) ** 2)
    assert checks["gap_shifted_mm"] > 0.01  # larger than one reading's noise
    flat = models.waterbed_deflection_mm(DISTANCE_MM, 0.5, 12.0)
    assert sensitivity.trial_checks(DISTANCE_MM, flat, 0.5, 3.0, 0.1)["gap_shifted_mm"] < 1e-3
