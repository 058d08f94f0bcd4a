"""Rule fit_sensitivity: refit a batch's trials under other choices; per-trial checks."""

import math

import numpy as np

from lineload.io import output_to, read_json, read_trials, write_rows
from lineload.sensitivity import CHECK_COLUMNS, SENSITIVITY_COLUMNS, sensitivity_rows, trial_checks


def fit_sensitivity(averaged, sensitivity, checks, subjects, window_mm, windows_mm, reach_fraction):
    """Refit every trial in each window (null: the whole profile) and check U and reach."""
    windows_mm = [math.inf if w is None else float(w) for w in windows_mm]
    trials = read_trials(averaged)  # numpy only: this job runs once per batch
    rows, check_rows = [], []
    for subject, about in subjects.items():
        species = about["species"]
        for depth_mm, columns in trials.get(subject, {}).items():
            x, y = (np.asarray(values) for values in columns)
            for row in sensitivity_rows(x, y, depth_mm, windows_mm):
                rows.append({"subject": subject, "species": species, **row})
            check = trial_checks(x, y, depth_mm, window_mm, reach_fraction)
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
            **read_json(snakemake.input.spec),
        )
