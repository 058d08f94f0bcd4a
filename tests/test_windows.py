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
