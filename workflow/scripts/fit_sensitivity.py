"""Rule fit_sensitivity: refit a batch's trials under other choices; per-trial checks."""

import math

import numpy as np

from lineload.fitting.sensitivity import (
    CHECK_COLUMNS,
    SENSITIVITY_COLUMNS,
    sensitivity_rows_batch,
    trial_checks_batch,
)
from lineload.io import output_to, read_trials, write_rows
from lineload.runtime.jobparams import given


def fit_sensitivity(averaged, sensitivity, checks, subjects, window_mm, windows_mm, reach_fraction):
    """Refit every trial in each window (null: the whole profile) and check U and reach."""
    windows_mm = [math.inf if w is None else float(w) for w in windows_mm]
    trials = read_trials(averaged)  # numpy only: this job runs once per batch
    keys = [
        (subject, about["species"], depth_mm, np.asarray(x), np.asarray(y))
        for subject, about in subjects.items()
        for depth_mm, (x, y) in trials.get(subject, {}).items()
    ]
    # every trial of the batch at once: each refit runs for all of them together
    distance, deflection, depth = ([key[k] for key in keys] for k in (3, 4, 2))
    refits = sensitivity_rows_batch(distance, deflection, depth, windows_mm)
    trial_rows = trial_checks_batch(distance, deflection, depth, window_mm, reach_fraction)
    rows, check_rows = [], []
    for (subject, species, depth_mm, _, _), refit, check in zip(
        keys, refits, trial_rows, strict=True
    ):
        rows.extend({"subject": subject, "species": species, **row} for row in refit)
        check_rows.append({"subject": subject, "species": species, **check})
        print(
            f"{subject} {depth_mm:g} mm: reach {check['reach_mm']:g} mm, "
            f"U/X at L/3 = {check['shift_fraction_at_third']:.3f}"
        )
    write_rows(rows, SENSITIVITY_COLUMNS, sensitivity)
    write_rows(check_rows, CHECK_COLUMNS, checks)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_sensitivity(
            snakemake.input.averaged,
            snakemake.output.sensitivity,
            snakemake.output.checks,
            **given(snakemake.params),
        )
