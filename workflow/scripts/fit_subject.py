"""Entry point of rule fit_subject: fit the three models to each depth of one subject."""

import argparse

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.fitting import FIT_COLUMNS, fit_trial
from lineload.io import write_csv


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--subject", required=True)
    parser.add_argument("--species", required=True)
    parser.add_argument("--window-mm", type=float, required=True)
    parser.add_argument("--averaged", required=True, help="input: averaged profile")
    parser.add_argument("--output", required=True, help="output: one row per depth")
    args = parser.parse_args()

    averaged = pd.read_csv(args.averaged)
    rows = []
    for depth_mm, trial in averaged.groupby("depth_mm", sort=True):
        row = fit_trial(trial["distance_mm"], trial["deflection_mm"], depth_mm, args.window_mm)
        rows.append({"subject": args.subject, "species": args.species, **row})
        print(
            f"{args.subject} {depth_mm:g} mm: {row['n_points']} points, "
            f"waterbed L = {row['waterbed_L_mm']:.3f} mm, "
            f"RMSE waterbed/arc/Boussinesq = {row['waterbed_rmse_mm']:.4f}/"
            f"{row['arc_rmse_mm']:.4f}/{row['boussinesq_rmse_mm']:.4f} mm"
        )
    write_csv(pd.DataFrame(rows, columns=FIT_COLUMNS), args.output)


if __name__ == "__main__":
    main()
