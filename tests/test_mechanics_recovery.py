"""The membrane's recovery check: forces from the law the fit inverts and from another."""

import math

import pytest
from scipy.stats import binomtest

from lineload.io import config_defaults
from lineload.simulation import readings, subjects
from lineload.simulation.mechanics_coverage import (
    RECOVERY_WORLDS,
    STIFFENING,
    recovery_study,
    summarise_recovery,
)

PRIORS = {k: v for k, v in config_defaults("noise").items() if k != "max_trials"}
MAX_TRIALS = config_defaults("noise")["max_trials"]
FORCE_SD_N = config_defaults("mechanics")["force_sd_N"]
SUBJECT = next(s for s in subjects.shipped_subjects() if s.contact_length_mm is not None)


def test_the_stiffening_law_is_the_linear_one_at_rest_and_stiffer_beyond():
    linear = readings.trial_forces(SUBJECT, 3)
    stiff = readings.trial_forces(SUBJECT, 3, stiffening=STIFFENING)
    for a, b in zip(linear, stiff, strict=True):
        assert a["strain"] == b["strain"] and a["load_angle_rad"] == b["load_angle_rad"]
        # N = N0 + E (exp(b eps) - 1) / b against N0 + E eps, at the same arc
        ratio = (SUBJECT.pretension_N_per_mm + SUBJECT.stiffness_N_per_mm
                 * math.expm1(STIFFENING * a["strain"]) / STIFFENING) / (
            SUBJECT.pretension_N_per_mm + SUBJECT.stiffness_N_per_mm * a["strain"])  # fmt: skip
        assert b["true_force_N"] / a["true_force_N"] == pytest.approx(ratio, rel=1e-12)
        assert b["true_force_N"] > a["true_force_N"]
    # the default is the shipped law
    assert readings.trial_forces(SUBJECT, 3, stiffening=0.0) == linear


def test_forces_from_another_law_make_the_stiffness_fall_out_of_its_intervals():
    summary = summarise_recovery(recovery_study(17, 2, 3.0, PRIORS, MAX_TRIALS, FORCE_SD_N))
    by = {(r["world"], r["parameter"]): r for r in summary}
    (linear, _), (stiff, _) = RECOVERY_WORLDS
    for world, falls in ((linear, False), (stiff, True)):
        row = by[(world, "stiffness_N_per_mm")]
        p = binomtest(row["n_covered"], row["n"], 0.95, alternative="less").pvalue
        assert bool(p < 1e-3) == falls, (world, row["n_covered"], row["n"])
    # the linear fit reads a secant stiffness: above the stiffness at rest
    assert by[(stiff, "stiffness_N_per_mm")]["median_ratio"] > 1.2
