"""Coverage of the exact arc's 95 % intervals on L on held-out arc-made profiles.

Held out: the profiles are made here, not by the project's generator or its calibration
study, on a reading grid of the paper's design (every 0.05 mm to 0.5 mm, then every
0.25 mm), with digitising errors of sizes stated below that differ from the
reconstruction's.  Each dataset's noise is measured from its own left-right differences
(:func:`lineload.noise.estimate_noise`), the priors are stated as these data have them
(the sizes they were made with), and each trial is fitted with
:func:`lineload.fitting.batch.fit_windowed`.  An interval covers when it holds the L the
profile was made with; the count gets a Clopper-Pearson interval.  Beside it: the SD of
``(L - truth) / SE`` (SE the interval's half-width over 1.96), which is 1 when the
intervals are as wide as the scatter of L says, and the mean share of the variance from
the priors.

Run: ``python docs/calibration/scripts/heldout_arc_coverage.py [n_datasets]``
(writes ``docs/calibration/heldout_arc.md``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.stats import binomtest

from lineload.fitting.batch import fit_windowed
from lineload.io import config_defaults
from lineload.models import arc_deflection_mm
from lineload.noise import PRIORS, NoiseModel, estimate_noise, trial_differences

#: The held-out errors (tissue mm; per side unless shared).  Chosen apart from the
#: reconstruction's: larger reading and correlated errors, a larger depth error.
ERRORS = NoiseModel(
    reading_sd_mm=0.008,
    tracing_sd_mm=0.006,
    tracing_length_mm=0.4,
    side_offset_sd_mm=0.004,
    rotation_sd=0.0005,
    wedge_position_sd_mm=0.008,
    shared_offset_sd_mm=0.008,
    shared_tilt_sd=0.0008,
    depth_sd_mm=0.015,
)
#: Readings rounded to this (mm): 0.1 mm on a 20x print.
RESOLUTION_MM = 0.005
DEPTHS_MM = (0.5, 1.0, 1.5, 2.0)
L_RANGE_MM = (8.0, 16.0)
TRIALS_PER_DEPTH = 8  # a dataset: 32 trials
WINDOW_MM = 3.0
SEED = 31


def reading_grid_mm(reach_mm=WINDOW_MM + 0.5):
    """The paper's reading design: every 0.05 mm to 0.5 mm, then every 0.25 mm."""
    near = np.arange(1, 11) * 0.05
    far = np.arange(0.75, reach_mm + 1e-9, 0.25)
    return np.concatenate([near, far])


def _side_errors_mm(rng, x, noise):
    kernel = np.exp(-np.abs(x[:, None] - x[None, :]) / noise.tracing_length_mm)
    tracing = np.linalg.cholesky(kernel + 1e-12 * np.eye(x.size)) @ rng.normal(size=x.size)
    return (
        rng.normal(0.0, noise.reading_sd_mm, x.size)
        + noise.tracing_sd_mm * tracing
        + rng.normal(0.0, noise.side_offset_sd_mm)
    )


def read_trial(rng, x, depth_mm, L_mm, noise=ERRORS):
    """Both sides of one arc-made trial, read with every error of ``noise``."""
    wedge_mm = rng.normal(0.0, noise.wedge_position_sd_mm)
    scale = 1.0 + rng.normal(0.0, noise.depth_sd_mm) / depth_mm
    shared = rng.normal(0.0, noise.shared_offset_sd_mm) + rng.normal(0.0, noise.shared_tilt_sd) * x
    rotation = rng.normal(0.0, noise.rotation_sd)
    sides = []
    for sign in (1.0, -1.0):
        seen = np.abs(x + sign * wedge_mm)
        w = scale * arc_deflection_mm(seen, depth_mm, L_mm)
        read = w + shared - sign * rotation * x + _side_errors_mm(rng, x, noise)
        sides.append(np.round(read / RESOLUTION_MM) * RESOLUTION_MM)
    return sides


def one_dataset(seed, noise=ERRORS, priors=None):
    """Coverage rows of one dataset: ``(truth, L, low, high, prior_share)`` per trial;
    ``priors`` (by name) stated instead of the sizes the data were made with."""
    rng = np.random.default_rng(seed)
    x = reading_grid_mm()
    trials = []
    for depth_mm in DEPTHS_MM:
        for _ in range(TRIALS_PER_DEPTH):
            L_mm = float(rng.uniform(*L_RANGE_MM))
            left, right = read_trial(rng, x, depth_mm, L_mm, noise)
            trials.append((depth_mm, L_mm, left, right))
    differences = [trial_differences(x, left, right, WINDOW_MM) for _, _, left, right in trials]
    measured = estimate_noise(differences).model
    priors = priors or {name: getattr(noise, name) for name in PRIORS}
    stated = measured.with_priors(**{name: priors[name] for name in PRIORS})
    fits = fit_windowed(
        [x] * len(trials),
        [0.5 * (left + right) for _, _, left, right in trials],
        [depth for depth, *_ in trials],
        WINDOW_MM,
        ("arc",),
        noise=stated,
    )["arc"]
    return np.column_stack(
        [
            [L for _, L, *_ in trials],
            fits.params["L_mm"],
            fits.params["L_ci_low_mm"],
            fits.params["L_ci_high_mm"],
            fits.prior_share,
        ]
    )


def study(n_datasets, noise=ERRORS, seed=SEED, priors=None):
    """All datasets' rows stacked."""
    return np.vstack([one_dataset((seed, k), noise, priors) for k in range(n_datasets)])


def summary(rows):
    """Coverage, its Clopper-Pearson 95 % interval, SD of the z-scores, mean prior share."""
    truth, L, low, high, share = rows.T
    covered = (low <= truth) & (truth <= high)
    ci = binomtest(int(covered.sum()), covered.size).proportion_ci(method="exact")
    se = (high - low) / (2 * 1.959963984540054)
    z = (L - truth) / se
    return {
        "n": covered.size,
        "covered": int(covered.sum()),
        "coverage": covered.mean(),
        "ci": (ci.low, ci.high),
        "z_sd": float(np.std(z, ddof=1)),
        "prior_share": float(np.nanmean(share)),
    }


def _row(label, result):
    low, high = result["ci"]
    return (
        f"| {label} | {result['n']} | {result['covered']} | {100 * result['coverage']:.1f} % | "
        f"{100 * low:.1f}-{100 * high:.1f} % | {result['z_sd']:.2f} | "
        f"{100 * result['prior_share']:.0f} % |"
    )


def markdown(results, n_datasets):
    lines = [
        "# Held-out arc-made profiles: coverage of the arc's L intervals",
        "",
        f"Made by `docs/calibration/scripts/heldout_arc_coverage.py` ({n_datasets} datasets "
        f"of {len(DEPTHS_MM) * TRIALS_PER_DEPTH} trials, seed {SEED}); the errors and the "
        "reading design are stated in the script, apart from the reconstruction's.",
        "",
        "The aim: 90-98.5 % with the priors stated as the data have them.",
        "",
        "| priors stated | trials | covered | coverage | 95 % interval (Clopper-Pearson) "
        "| SD of (L - truth) / SE | prior share of the variance |",
        "|---|---:|---:|---:|---:|---:|---:|",
        *(_row(label, result) for label, result in results.items()),
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 25
    defaults = config_defaults("noise")
    results = {
        "as the data have them": summary(study(n)),
        "the config's defaults (smaller than these data's)": summary(study(n, priors=defaults)),
    }
    text = markdown(results, n)
    Path(__file__).resolve().parents[1].joinpath("heldout_arc.md").write_text(text)
    print(text)
