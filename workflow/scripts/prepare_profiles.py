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
    average_subjects,
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
    converted = []
    for subject, magnification, path in args.subject:
        # columns of numpy arrays: one pass over the batch, no DataFrame per subject
        profile = read_columns(path, schema)
        check_no_duplicate_readings(profile, path)
        converted.append(tissue_columns(profile[0], subject, float(magnification)))
    averaged = average_subjects(converted)
    # each subject's rows follow the previous subject's (every subject has some)
    subjects = averaged["subject"]
    starts = np.flatnonzero(np.r_[True, subjects[1:] != subjects[:-1]])
    points = np.diff(np.r_[starts, subjects.size])
    one_sided = np.add.reduceat(averaged["n_sides"] == 1, starts)
    new_depth = np.r_[True, averaged["depth_mm"][1:] != averaged["depth_mm"][:-1]]
    new_depth[starts] = True
    depths = np.add.reduceat(new_depth, starts)
    for readings, start, n, one, d in zip(
        converted, starts, points, one_sided, depths, strict=True
    ):
        print(
            f"{subjects[start]}: {len(readings['depth_mm'])} readings -> {n} averaged points "
            f"({int(one)} one-sided) at {int(d)} depths"
        )
    # the same bytes as write_csv of a DataFrame, without pandas
    write_columns(joined(converted, CONVERTED_COLUMNS), args.converted, CONVERTED_COLUMNS)
    write_columns(averaged, args.averaged, AVERAGED_COLUMNS)


if __name__ == "__main__":
    main()
