"""Entry point of rule fit_sensitivity: refit a batch's trials under other choices."""

import argparse

import numpy as np

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.io import read_trials, write_rows
from lineload.sensitivity import (
    CHECK_COLUMNS,
    SENSITIVITY_COLUMNS,
    sensitivity_rows_batch,
    trial_checks_batch,
)


def window(text):
    return float("inf") if text in ("whole", "inf", "null", "None") else float(text)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--subject", nargs=2, action="append", required=True, metavar=("ID", "SPECIES")
    )
    parser.add_argument("--window-mm", type=float, required=True, help="the main fit window")
    parser.add_argument("--windows-mm", type=window, nargs="+", required=True)
    parser.add_argument("--reach-fraction", type=float, required=True)
    parser.add_argument("--averaged", required=True)
    parser.add_argument("--sensitivity", required=True, help="output: fits per window and model")
    parser.add_argument("--checks", required=True, help="output: U shift and reach per trial")
    args = parser.parse_args()

    trials = read_trials(args.averaged)  # numpy only: this job runs once per batch
    keys = [
        (subject, species, depth_mm, np.asarray(x), np.asarray(y))
        for subject, species in args.subject
        for depth_mm, (x, y) in trials.get(subject, {}).items()
    ]
    # every trial of the batch at once: each refit runs for all of them together
    distance, deflection, depth = ([key[k] for key in keys] for k in (3, 4, 2))
    refits = sensitivity_rows_batch(distance, deflection, depth, args.windows_mm)
    trial_rows = trial_checks_batch(
        distance, deflection, depth, args.window_mm, args.reach_fraction
    )
    rows, checks = [], []
    for (subject, species, depth_mm, _, _), refit, check in zip(
        keys, refits, trial_rows, strict=True
    ):
        for row in refit:
            rows.append({"subject": subject, "species": species, **row})
        checks.append({"subject": subject, "species": species, **check})
        print(
            f"{subject} {depth_mm:g} mm: reach {check['reach_mm']:g} mm, "
            f"U/X at L/3 = {check['shift_fraction_at_third']:.3f}"
        )
    write_rows(rows, SENSITIVITY_COLUMNS, args.sensitivity)
    write_rows(checks, CHECK_COLUMNS, args.checks)


if __name__ == "__main__":
    main()
