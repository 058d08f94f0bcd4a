"""L is the half-width for a window: the fit table gives its range across the configured
windows, and C5 does not decide a trial whose L crosses an end of the range between them."""

import numpy as np
import pandas as pd
import pytest

from lineload.claims import CLAIM_FUNCTIONS, ClaimSettings
from lineload.fitting.batch import FIT_COLUMNS, fit_trials, fit_windowed
from lineload.models import arc_deflection_mm

DISTANCE_MM = np.concatenate([np.arange(1, 11) * 0.05, np.arange(0.75, 8.01, 0.25)])


def test_window_range_is_the_smallest_and_largest_L_over_the_windows():
    # an arc read with the paper's parabola: its L depends on how far the fit reaches
    w = arc_deflection_mm(DISTANCE_MM, 2.0, 12.0)
    row = fit_trials([DISTANCE_MM], [w], [2.0], 3.0, other_windows_mm=(2.0, None))[0]
    L = [
        fit_windowed([DISTANCE_MM], [w], 2.0, window, ("waterbed",))["waterbed"].params["L_mm"][0]
        for window in (2.0, 3.0, np.inf)
    ]
    assert row["waterbed_L_window_min_mm"] == pytest.approx(min(L), rel=1e-9)
    assert row["waterbed_L_window_max_mm"] == pytest.approx(max(L), rel=1e-9)
    assert max(L) - min(L) > 0.1  # the window matters for this shape
    alone = fit_trials([DISTANCE_MM], [w], [2.0], 3.0)[0]
    assert (
        alone["waterbed_L_window_min_mm"]
        == alone["waterbed_L_window_max_mm"]
        == alone["waterbed_L_mm"]
    )


def test_the_fit_window_among_the_others_is_not_fitted_twice_and_changes_nothing():
    """A configured window equal to the fit window is skipped: the noise changes only the
    intervals, never the least-squares L, so the main fit's L is the refit's."""
    from lineload.noise import NoiseModel

    noise = NoiseModel(reading_sd_mm=0.005, tracing_sd_mm=0.003, tracing_length_mm=0.5)
    rng = np.random.default_rng(7)
    profiles = [arc_deflection_mm(DISTANCE_MM, 1.5, L) for L in (9.0, 12.0, 15.0)]
    profiles = [w + rng.normal(0.0, 0.005, w.size) for w in profiles]
    xs, depths = [DISTANCE_MM] * 3, [1.5] * 3
    with_noise = fit_windowed(xs, profiles, depths, 3.0, ("waterbed", "shifted", "arc"), noise)
    plain = fit_windowed(xs, profiles, depths, 3.0, ("waterbed", "shifted", "arc"))
    for model in ("waterbed", "shifted", "arc"):
        assert np.array_equal(with_noise[model].params["L_mm"], plain[model].params["L_mm"])
    rows = fit_trials(xs, profiles, depths, 3.0, noise=[noise] * 3, other_windows_mm=(2.0,))
    again = fit_trials(
        xs, profiles, depths, 3.0, noise=[noise] * 3, other_windows_mm=(2.0, 3.0, 3.0)
    )
    assert rows == again


def test_a_refit_without_intervals_finds_the_same_L_and_leaves_the_intervals_out():
    rng = np.random.default_rng(3)
    profiles = [arc_deflection_mm(DISTANCE_MM, 1.5, L) for L in (4.0, 9.0, 15.0)]
    profiles = [w + rng.normal(0.0, 0.01, w.size) for w in profiles]
    xs, depths = [DISTANCE_MM] * 3, [1.5] * 3
    models = ("waterbed", "shifted", "arc")
    for window in (2.0, np.inf):
        full = fit_windowed(xs, profiles, depths, window, models)
        alone = fit_windowed(xs, profiles, depths, window, models, intervals=False)
        for model in models:
            assert np.array_equal(full[model].params["L_mm"], alone[model].params["L_mm"])
            assert np.array_equal(full[model].at_bound, alone[model].at_bound)
            assert np.all(np.isfinite(full[model].params["L_ci_low_mm"]))
        for model in ("shifted", "arc"):  # the searched fits skip what costs
            assert np.all(np.isnan(alone[model].params["L_ci_low_mm"]))
            assert np.all(np.isnan(alone[model].params["L_ci_high_mm"]))


def _fit_row(window_min_mm, window_max_mm):
    row = dict.fromkeys(FIT_COLUMNS, np.nan)
    row.update(subject="A", species="human", depth_mm=1.0, fit_window_mm=3.0, n_points=20)
    for model in ("waterbed", "shifted", "arc"):
        row.update(
            {
                f"{model}_L_mm": 12.0,
                f"{model}_L_ci_low_mm": 11.9,
                f"{model}_L_ci_high_mm": 12.1,
                f"{model}_L_window_min_mm": window_min_mm,
                f"{model}_L_window_max_mm": window_max_mm,
            }
        )
    return row


@pytest.mark.parametrize(
    ("window_min_mm", "window_max_mm", "expected"),
    [
        (11.5, 13.0, "holds"),
        (np.nan, np.nan, "holds"),  # a table without the columns
        (9.5, 13.0, "cannot be checked on these data"),
        (11.5, 16.0, "cannot be checked on these data"),
    ],
)
def test_c5_is_undecided_where_the_window_moves_L_across_an_end(
    window_min_mm, window_max_mm, expected
):
    settings = ClaimSettings(noise_mm=0.01, large_depth_mm=1.5)
    fits = pd.DataFrame([_fit_row(window_min_mm, window_max_mm)])
    row = CLAIM_FUNCTIONS["C5"](fits, None, settings)
    assert row["verdict"] == expected
    if expected != "holds":
        assert "another" in row["reason"] and "window" in row["reason"]
