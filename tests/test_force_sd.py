"""The force precision measured from the pooled chi-square of the membrane fits: with
forces four times noisier than the config says, the intervals still cover."""

import numpy as np
import pandas as pd
import pytest

from lineload import mechanics

PRIOR_SD_N = 0.005
DEPTHS_MM = np.array([0.5, 1.0, 1.5, 2.0])
LENGTH_MM = 10.0
N0, E = 0.07, 0.2  # N/mm


def _dataset(rng, true_sd_N, n_subjects=7):
    fits, forces = [], []
    for k in range(n_subjects):
        L_mm = rng.uniform(10.0, 14.0) + 0.5 * DEPTHS_MM
        u, v = mechanics.force_terms(DEPTHS_MM, L_mm)
        force = 2 * LENGTH_MM * (N0 * u + E * v) + rng.normal(0.0, true_sd_N, DEPTHS_MM.size)
        for d, L, f in zip(DEPTHS_MM, L_mm, force, strict=True):
            fits.append(
                {
                    "subject": f"S{k}",
                    "species": "human",
                    "depth_mm": d,
                    "arc_L_mm": L,
                    # L known to a micron: the forces' own scatter is what is measured
                    "arc_L_ci_low_mm": L - 0.002,
                    "arc_L_ci_high_mm": L + 0.002,
                }
            )
            forces.append({"subject": f"S{k}", "depth_mm": d, "force_N": f})
    lengths = {f"S{k}": LENGTH_MM for k in range(n_subjects)}
    return pd.DataFrame(fits), pd.DataFrame(forces), lengths


def test_force_sd_four_times_the_prior_is_measured_and_the_intervals_cover():
    rng = np.random.default_rng(4)
    true_sd_N = 4 * PRIOR_SD_N
    covered, covered_prior, estimates = [], [], []
    for _ in range(60):
        fits, forces, lengths = _dataset(rng, true_sd_N)
        table, _ = mechanics.mechanics_tables(fits, forces, lengths, PRIOR_SD_N)
        estimates.append(table["force_sd_N"].iloc[0])
        assert (table["force_sd_dof"] == 7 * 2).all()
        for column, truth in (("stiffness", E), ("pretension", N0)):
            value, se = table[f"{column}_N_per_mm"], table[f"{column}_se_N_per_mm"]
            covered.extend(np.abs(value - truth) <= 1.96 * se)
            # the same fits with the prior's precision: what the tables gave before
            se_prior = se * PRIOR_SD_N / table["force_sd_N"]
            covered_prior.extend(np.abs(value - truth) <= 1.96 * se_prior)
    # 14 degrees of freedom: the SD is measured to about 19 %, so a 1.96 interval
    # covers about 93 %; 840 intervals put the binomial SD near 0.9 %
    assert np.mean(covered) > 0.9
    assert np.mean(covered_prior) < 0.6  # the prior's intervals, a quarter as wide, miss
    assert np.median(estimates) == pytest.approx(true_sd_N, rel=0.1)


def test_a_scatter_below_the_prior_keeps_the_prior_as_a_floor():
    rng = np.random.default_rng(5)
    fits, forces, lengths = _dataset(rng, PRIOR_SD_N / 10)
    table, _ = mechanics.mechanics_tables(fits, forces, lengths, PRIOR_SD_N)
    assert (table["force_sd_N"] == PRIOR_SD_N).all()
    assert (table["force_sd_source"] == "config prior (floor)").all()


def test_without_a_degree_of_freedom_the_prior_is_the_fallback():
    rng = np.random.default_rng(6)
    fits, forces, lengths = _dataset(rng, 4 * PRIOR_SD_N)
    two = fits[fits["depth_mm"].isin([0.5, 2.0])]
    table, _ = mechanics.mechanics_tables(two, forces, lengths, PRIOR_SD_N)
    assert (table["force_sd_N"] == PRIOR_SD_N).all() and (table["force_sd_dof"] == 0).all()
