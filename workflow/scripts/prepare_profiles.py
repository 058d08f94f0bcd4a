"""Entry point of rule prepare_profiles: raw readings -> tissue mm -> left/right mean.

Handles one batch of subjects (one subject unless the config asks for more
per job); the outputs hold every subject of the batch, in subject-sheet order.
"""

import argparse

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.averaging import AVERAGED_COLUMNS, CONVERTED_COLUMNS, average_sides, to_tissue_mm
from lineload.io import load_schema, write_csv
from lineload.validation import check_no_duplicate_readings, read_table


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--subject",
        nargs=3,
        action="append",
        required=True,
        metavar=("ID", "MAGNIFICATION", "PROFILE"),
        help="a subject of the batch, its magnification and its raw profiles/<id>.csv",
    )
    parser.add_argument("--converted", required=True, help="output: readings in tissue mm")
    parser.add_argument("--averaged", required=True, help="output: left/right mean per distance")
    args = parser.parse_args()

    schema = load_schema("profiles")
    converted, averaged = [], []
    for subject, magnification, path in args.subject:
        profile = read_table(path, schema)
        check_no_duplicate_readings(profile, path)
        readings = to_tissue_mm(profile, subject, float(magnification))
        means = average_sides(readings)
        converted.append(readings)
        averaged.append(means)
        print(
            f"{subject}: {len(readings)} readings -> {len(means)} averaged points "
            f"({int((means['n_sides'] == 1).sum())} one-sided) at "
            f"{means['depth_mm'].nunique()} depths"
        )
    write_csv(pd.concat(converted, ignore_index=True), args.converted, CONVERTED_COLUMNS)
    write_csv(pd.concat(averaged, ignore_index=True), args.averaged, AVERAGED_COLUMNS)


if __name__ == "__main__":
    main()
