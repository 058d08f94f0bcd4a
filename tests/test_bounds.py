"""Fits that end on a bound of their search: flagged, given a one-sided interval as wide as
the readings allow, never taken as precise by a claim, and no NaN in what is shown."""

import numpy as np
import pandas as pd
import pytest

from lineload import models
from lineload.claims import CLAIM_FUNCTIONS, ClaimSettings
from lineload.figures import supplements
from lineload.fitting.batch import FIT_COLUMNS, at_search_bound, fit_trials, fit_windowed
from lineload.noise import NoiseModel
from lineload.publishing.tables import (
    AT_BOUND_MARK,
    fits_markdown,
    summarise_fits,
    summary_markdown,
)

UNTESTABLE = "cannot be checked on these data"
DISTANCE_MM = np.linspace(0.2, 3.0, 15)
WINDOW_MM = 3.0
READING_SD_MM = 0.03  # of the averaged point


def test_at_search_bound_marks_both_ends_and_nothing_between():
    L_mm = np.array([3.0, 3.0 * (1 + 1e-7), 3.1, 3000.0, np.inf, np.nan])
    flags = at_search_bound(L_mm, np.full(6, 3.0), np.full(6, 3000.0))
    assert flags.tolist() == [True, True, False, True, True, False]


@pytest.mark.parametrize(
    ("model", "curve"),
    [("waterbed", models.waterbed_deflection_mm), ("arc", models.arc_deflection_mm)],
)
def test_fits_pushed_to_the_bound_get_intervals_that_cover_the_truth(model, curve):
    # a membrane 0.7 % wider than the farthest point: with readings this noisy about a
    # quarter of the fits want a narrower one and end on the bound L = max(x).  Their
    # interval must still reach the true L 95 % of the time; a likelihood interval cut
    # off by the sum of squares' slope at the bound is microns wide and covers ~30 %.
    rng = np.random.default_rng(20261125)
    L_true_mm, depth_mm, n_trials = 3.02, 1.0, 400
    truth = curve(DISTANCE_MM, depth_mm, L_true_mm)
    readings = [truth + rng.normal(0.0, READING_SD_MM, truth.size) for _ in range(n_trials)]
    # each side's reading error, so that the mean of two sides has READING_SD_MM
    noise = NoiseModel(reading_sd_mm=READING_SD_MM * np.sqrt(2.0))
    fit = fit_windowed(
        [DISTANCE_MM] * n_trials, readings, depth_mm, WINDOW_MM, models=(model,), noise=noise
    )[model]
    bound = fit.at_bound
    low, high = fit.params["L_ci_low_mm"], fit.params["L_ci_high_mm"]
    assert 0.05 * n_trials < bound.sum() < 0.6 * n_trials
    assert np.all(low[bound] == DISTANCE_MM.max())  # one-sided: from the bound up
    covered = (low <= L_true_mm) & (L_true_mm <= high)
    # binomial: 95 % of ~100 fits on the bound; 0.85 is 3 SD below
    assert covered[bound].mean() >= 0.85
    assert covered[~bound].mean() >= 0.9
    # an interior truth far from the bound: no fit flagged
    far = [models.waterbed_deflection_mm(DISTANCE_MM, depth_mm, 10.0)] * 3
    assert not fit_windowed([DISTANCE_MM] * 3, far, depth_mm, WINDOW_MM, noise=noise)[
        "waterbed"
    ].at_bound.any()


def test_a_membrane_narrower_than_the_window_is_flagged_in_the_fit_table():
    # the skin flat beyond 1.8 mm, fitted on 3 mm: every waterbed fit wants L < 3 mm
    depth_mm = 1.5
    flat_beyond = np.where(
        DISTANCE_MM < 1.8, models.waterbed_deflection_mm(DISTANCE_MM, depth_mm, 1.8), 0.0
    )
    noise = NoiseModel(reading_sd_mm=0.01, shared_offset_sd_mm=0.02, depth_sd_mm=0.02)
    row = fit_trials([DISTANCE_MM], [flat_beyond], [depth_mm], WINDOW_MM, noise=noise)[0]
    for model in ("waterbed", "shifted", "arc"):
        assert row[f"{model}_L_at_bound"] is True
    assert row["waterbed_L_mm"] == pytest.approx(3.0)
    # the readings miss the model by far more than their noise: the interval on the
    # bound widens with that misfit instead of reading it as precision (a tenth of a mm
    # and more, where the sum of squares' slope alone gives microns)
    assert row["waterbed_L_ci_high_mm"] - 3.0 > 0.1
    fits = pd.DataFrame(
        [{"subject": "A", "species": "human", **row}, _interior_row()], columns=FIT_COLUMNS
    )
    text = fits_markdown(fits)
    assert text.count(AT_BOUND_MARK) == 2  # the marked cell and the caption
    assert "1 of 2 rows" in text
    summary = summarise_fits(fits)
    assert summary["waterbed_n_at_bound"].tolist() == [1]
    assert f"(1{AT_BOUND_MARK})" in summary_markdown(summary)
    assert "nan" not in text.lower()


def _interior_row():
    depth_mm = 1.5
    w = models.waterbed_deflection_mm(DISTANCE_MM, depth_mm, 12.0)
    row = fit_trials([DISTANCE_MM], [w], [depth_mm], WINDOW_MM)[0]
    assert row["waterbed_L_at_bound"] is False
    return {"subject": "B", "species": "human", **row}


def _fit_row(subject, L_mm, half_mm, on_bound):
    row = dict.fromkeys(FIT_COLUMNS, np.nan)
    row.update(
        subject=subject,
        species="human",
        depth_mm=1.0,
        fit_window_mm=3.0,
        n_points=20,
        max_distance_mm=3.0,
    )
    for model in ("waterbed", "shifted", "arc"):
        row.update(
            {
                f"{model}_L_mm": L_mm,
                f"{model}_L_ci_low_mm": L_mm - half_mm,
                f"{model}_L_ci_high_mm": L_mm + half_mm,
                f"{model}_L_at_bound": on_bound,
            }
        )
    return row


def test_c5_does_not_take_a_fit_on_its_bound_as_a_measurement():
    settings = ClaimSettings(noise_mm=0.01, large_depth_mm=1.5)
    inside = [_fit_row("A", 12.0, 0.1, False)]
    assert CLAIM_FUNCTIONS["C5"](pd.DataFrame(inside), None, settings)["verdict"] == "holds"
    # the same narrow interval inside the range, but the fit ended on a bound
    bounded = CLAIM_FUNCTIONS["C5"](
        pd.DataFrame([*inside, _fit_row("B", 12.0, 0.1, True)]), None, settings
    )
    assert bounded["verdict"] == UNTESTABLE
    assert "B at 1 mm" in bounded["reason"] and "bound" in bounded["reason"]
    assert "1 of them with L on a bound" in bounded["our_value"]


def test_c6_leaves_out_fits_on_a_bound_and_counts_them():
    settings = ClaimSettings(noise_mm=0.01, large_depth_mm=1.5)
    averaged = pd.DataFrame(
        {
            "subject": "A",
            "depth_mm": 1.0,
            "distance_mm": DISTANCE_MM,
            "deflection_mm": models.waterbed_deflection_mm(DISTANCE_MM, 1.0, 3.0),
            "n_sides": 2,
        }
    )
    row = CLAIM_FUNCTIONS["C6"](pd.DataFrame([_fit_row("A", 3.0, 0.01, True)]), averaged, settings)
    assert row["verdict"] == UNTESTABLE
    assert "left out: A at 1 mm" in row["our_value"]


def test_the_arc_supplement_says_when_the_shifted_curve_does_not_exist():
    # L < sqrt(6) W0: the shifted parabola has no point; no 'nan' in the panel's text
    fits = pd.DataFrame([_fit_row("A", 6.0, 0.5, False)]).assign(depth_mm=3.0)
    figure = supplements.figure_arc_vs_parabola(fits)
    texts = [t.get_text() for ax in figure.axes for t in ax.texts]
    assert texts and not any("nan" in t.lower() for t in texts)
    assert any("shifted: none" in t for t in texts)
