"""Entry point of rule prepare_profiles: raw readings -> tissue mm -> left/right mean.

Handles one batch of subjects (one subject unless the config asks for more
per job); the outputs hold every subject of the batch, in subject-sheet order.
"""

import argparse

import numpy as np

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.averaging import (
    AVERAGED_COLUMNS,
    CONVERTED_COLUMNS,
    average_columns,
    tissue_columns,
)
from lineload.io import load_schema, write_columns
from lineload.validation import check_no_duplicate_readings, read_columns


def joined(parts, names):
    """The subjects' columns (dicts of arrays), one after the other."""
    return {name: np.concatenate([part[name] for part in parts]) for name in names}


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
        # columns of numpy arrays: one DataFrame per output, not several per subject
        profile = read_columns(path, schema)
        check_no_duplicate_readings(profile, path)
        readings = tissue_columns(profile[0], subject, float(magnification))
        means = average_columns(readings)
        converted.append(readings)
        averaged.append(means)
        print(
            f"{subject}: {len(readings['depth_mm'])} readings -> {len(means['depth_mm'])} "
            f"averaged points ({int((means['n_sides'] == 1).sum())} one-sided) at "
            f"{len(set(means['depth_mm']))} depths"
        )
    # the same bytes as write_csv of a DataFrame, without pandas
    write_columns(joined(converted, CONVERTED_COLUMNS), args.converted, CONVERTED_COLUMNS)
    write_columns(joined(averaged, AVERAGED_COLUMNS), args.averaged, AVERAGED_COLUMNS)


if __name__ == "__main__":
    main()
