"""Entry point of rule fit_models: the three models for each subject and depth of a batch."""

import argparse

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.fitting import FIT_COLUMNS, fit_trials
from lineload.io import read_trials, write_rows


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--subject", nargs=2, action="append", required=True, metavar=("ID", "SPECIES")
    )
    parser.add_argument("--window-mm", type=float, required=True)
    parser.add_argument("--averaged", required=True, help="input: averaged profiles")
    parser.add_argument("--output", required=True, help="output: one row per subject and depth")
    args = parser.parse_args()

    trials = read_trials(args.averaged)  # numpy only: this job runs once per batch
    keys = [
        (subject, species, depth_mm, x, y)
        for subject, species in args.subject
        for depth_mm, (x, y) in trials.get(subject, {}).items()
    ]
    # every trial of the batch in one call: the fits run for all of them at once
    fitted = fit_trials(
        [key[3] for key in keys], [key[4] for key in keys], [key[2] for key in keys], args.window_mm
    )
    rows = []
    for (subject, species, depth_mm, _, _), row in zip(keys, fitted, strict=True):
        rows.append({"subject": subject, "species": species, **row})
        print(
            f"{subject} {depth_mm:g} mm: {row['n_points']} points, "
            f"waterbed L = {row['waterbed_L_mm']:.3f} mm, "
            f"RMSE waterbed/arc/Boussinesq = {row['waterbed_rmse_mm']:.4f}/"
            f"{row['arc_rmse_mm']:.4f}/{row['boussinesq_rmse_mm']:.4f} mm"
        )
    write_rows(rows, FIT_COLUMNS, args.output)


if __name__ == "__main__":
    main()
