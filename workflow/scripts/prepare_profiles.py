"""Rule prepare_profiles: a batch's raw readings -> tissue mm -> left/right mean.

The outputs hold every subject of the batch, in subject-sheet order.  Columns of
numpy arrays throughout, one pass over the batch: no DataFrame per subject, and
no pandas at all.
"""

import numpy as np

from lineload.averaging import (
    AVERAGED_COLUMNS,
    CONVERTED_COLUMNS,
    average_subjects,
    tissue_columns,
)
from lineload.io import load_schema, output_to, write_columns
from lineload.rawdata.digitising import subject_profile
from lineload.rawdata.validation import check_no_duplicate_readings, read_columns
from lineload.runtime.jobparams import given


def prepare_profiles(profiles, subjects, converted_path, averaged_path):
    """Convert and average each subject's readings; write both tables."""
    schema = load_schema("profiles")
    converted = []
    read = {}  # a batch's digitised readings are one file for all its subjects: read once
    for path, (subject, about) in zip(profiles, subjects.items(), strict=True):
        if path not in read:
            read = {path: read_columns(path, schema)}
        profile = subject_profile(read[path], subject)
        check_no_duplicate_readings(profile, path)
        converted.append(tissue_columns(profile[0], subject, about["magnification"]))
    averaged = average_subjects(converted)
    # each subject's rows follow the previous subject's (every subject has some)
    names = averaged["subject"]
    starts = np.flatnonzero(np.r_[True, names[1:] != names[:-1]])
    points = np.diff(np.r_[starts, names.size])
    one_sided = np.add.reduceat(averaged["n_sides"] == 1, starts)
    new_depth = np.r_[True, averaged["depth_mm"][1:] != averaged["depth_mm"][:-1]]
    new_depth[starts] = True
    depths = np.add.reduceat(new_depth, starts)
    for readings, start, n, one, d in zip(
        converted, starts, points, one_sided, depths, strict=True
    ):
        print(
            f"{names[start]}: {len(readings['depth_mm'])} readings -> {n} averaged points "
            f"({int(one)} one-sided) at {int(d)} depths"
        )
    joined = {
        name: np.concatenate([part[name] for part in converted]) for name in CONVERTED_COLUMNS
    }
    write_columns(joined, converted_path, CONVERTED_COLUMNS)
    write_columns(averaged, averaged_path, AVERAGED_COLUMNS)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        prepare_profiles(
            snakemake.input.profiles,
            given(snakemake.params)["subjects"],
            snakemake.output.converted,
            snakemake.output.averaged,
        )
