"""Rule prepare_profiles: a batch's raw readings -> tissue mm -> left/right mean.

The outputs hold every subject of the batch, in subject-sheet order.
"""

import pandas as pd

from lineload.averaging import AVERAGED_COLUMNS, CONVERTED_COLUMNS, average_sides, to_tissue_mm
from lineload.io import load_schema, output_to, read_json, write_csv
from lineload.validation import check_no_duplicate_readings, read_table


def prepare_profiles(profiles, subjects, converted_path, averaged_path):
    """Convert and average each subject's readings; write both tables."""
    schema = load_schema("profiles")
    converted, averaged = [], []
    for path, (subject, about) in zip(profiles, subjects.items(), strict=True):
        profile = read_table(path, schema)
        check_no_duplicate_readings(profile, path)
        readings = to_tissue_mm(profile, subject, about["magnification"])
        means = average_sides(readings)
        converted.append(readings)
        averaged.append(means)
        print(
            f"{subject}: {len(readings)} readings -> {len(means)} averaged points "
            f"({int((means['n_sides'] == 1).sum())} one-sided) at "
            f"{means['depth_mm'].nunique()} depths"
        )
    write_csv(pd.concat(converted, ignore_index=True), converted_path, CONVERTED_COLUMNS)
    write_csv(pd.concat(averaged, ignore_index=True), averaged_path, AVERAGED_COLUMNS)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        prepare_profiles(
            snakemake.input.profiles,
            read_json(snakemake.input.spec)["subjects"],
            snakemake.output.converted,
            snakemake.output.averaged,
        )
