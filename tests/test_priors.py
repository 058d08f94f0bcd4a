"""Verdicts at other priors: the refit reproduces the fit table at the stated priors, a
verdict that rests on the priors changes when they grow, and the claims table says so."""

import numpy as np
import pandas as pd
import pytest

from lineload.claims import CLAIM_FUNCTIONS, ClaimSettings
from lineload.fitting.batch import FIT_COLUMNS, fit_trials
from lineload.models import waterbed_deflection_mm
from lineload.noise import NoiseModel
from lineload.priors import (
    CHANGED_COLUMN,
    changed_claims,
    prior_column,
    refit_at_priors,
    with_prior_verdicts,
)

DISTANCE_MM = np.linspace(0.05, 3.0, 30)
NOISE = NoiseModel(
    reading_sd_mm=0.004,
    shared_offset_sd_mm=0.003,
    depth_sd_mm=0.005,
    shared_tilt_sd=0.0002,
    wedge_position_sd_mm=0.005,
)


def _dataset(L_by_subject):
    rows, frames = [], []
    for subject, L_mm in L_by_subject.items():
        w = waterbed_deflection_mm(DISTANCE_MM, 1.0, L_mm)
        frames.append(
            pd.DataFrame(
                {
                    "subject": subject,
                    "depth_mm": 1.0,
                    "distance_mm": DISTANCE_MM,
                    "deflection_mm": w,
                    "n_sides": 2,
                }
            )
        )
        row = fit_trials([DISTANCE_MM], [w], [1.0], 3.0, noise=NOISE)[0]
        rows.append({"subject": subject, "species": "human", **row})
    return pd.DataFrame(rows, columns=FIT_COLUMNS), pd.concat(frames, ignore_index=True)


def test_the_refit_at_the_stated_priors_is_the_fit_table():
    fits, averaged = _dataset({"A": 10.8, "B": 12.0})
    again = refit_at_priors(fits, averaged, [NOISE, NOISE])
    numbers = [c for c in FIT_COLUMNS if c not in ("subject", "species")]
    pd.testing.assert_frame_equal(
        again[numbers].astype(float), fits[numbers].astype(float), rtol=1e-9
    )


def test_a_range_verdict_that_rests_on_the_priors_changes_when_they_grow():
    # L just inside the paper's 10-15 mm: inside at the stated priors, undecided once
    # the priors, which set most of the interval's width, are three times larger
    fits, averaged = _dataset({"A": 10.2})
    by_multiple = {}
    for multiple in (0.5, 3.0):
        scaled = NOISE.scaled_priors(multiple)
        refitted = refit_at_priors(fits, averaged, [scaled])
        width = refitted["waterbed_L_ci_high_mm"] - refitted["waterbed_L_ci_low_mm"]
        stated = fits["waterbed_L_ci_high_mm"] - fits["waterbed_L_ci_low_mm"]
        assert (width > stated).all() == (multiple > 1)
        settings = ClaimSettings(noise_model=scaled)
        by_multiple[multiple] = pd.DataFrame([CLAIM_FUNCTIONS["C5"](refitted, averaged, settings)])
    claims = pd.DataFrame([CLAIM_FUNCTIONS["C5"](fits, averaged, ClaimSettings(noise_model=NOISE))])
    assert claims["verdict"].tolist() == ["holds"]
    table = with_prior_verdicts(claims, by_multiple)
    assert table[prior_column(0.5)].tolist() == ["holds"]
    assert table[prior_column(3.0)].tolist() == ["cannot be checked on these data"]
    assert table[CHANGED_COLUMN].tolist() == ["x3"]
    assert changed_claims(table) == ["C5"] and changed_claims(table, below=2) == []


@pytest.mark.parametrize(
    ("multiple", "name"), [(0.5, "verdict_prior_x0.5"), (2, "verdict_prior_x2")]
)
def test_prior_columns_name_the_multiple(multiple, name):
    assert prior_column(multiple) == name
