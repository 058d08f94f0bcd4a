"""Rule fit_sensitivity: refit a batch's trials under other choices; per-trial checks."""

import math

from lineload.fitting.inputs import labelled_rows, read_batch
from lineload.fitting.sensitivity import (
    CHECK_COLUMNS,
    SENSITIVITY_COLUMNS,
    sensitivity_rows_batch,
    trial_checks_batch,
)
from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given


def fit_sensitivity(averaged, sensitivity, checks, subjects, window_mm, windows_mm, reach_fraction):
    """Refit every trial in each window (null: the whole profile) and check U and reach."""
    windows_mm = [math.inf if w is None else float(w) for w in windows_mm]
    batch = read_batch(averaged, subjects, sides=False)  # numpy only: once per batch
    # every trial of the batch at once: each refit runs for all of them together
    distance, deflection, depth = batch.distance_mm, batch.deflection_mm, batch.depth_mm
    refits = sensitivity_rows_batch(distance, deflection, depth, windows_mm)
    trial_rows = trial_checks_batch(distance, deflection, depth, window_mm, reach_fraction)
    check_rows = labelled_rows(batch, trial_rows)
    rows = [
        {"subject": check["subject"], "species": check["species"], **row}
        for check, refit in zip(check_rows, refits, strict=True)
        for row in refit
    ]
    for depth_mm, check in zip(depth, check_rows, strict=True):
        print(
            f"{check['subject']} {depth_mm:g} mm: reach {check['reach_mm']:g} mm, "
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
