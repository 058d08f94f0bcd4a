"""Entry point of rule prepare_profile: raw readings -> tissue mm -> left/right mean."""

import argparse

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.averaging import AVERAGED_COLUMNS, CONVERTED_COLUMNS, average_sides, to_tissue_mm
from lineload.io import load_schema, write_csv
from lineload.validation import check_no_duplicate_readings, read_table


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--subject", required=True)
    parser.add_argument("--magnification", type=float, required=True)
    parser.add_argument("--profile", required=True, help="raw profiles/<subject>.csv")
    parser.add_argument("--converted", required=True, help="output: readings in tissue mm")
    parser.add_argument("--averaged", required=True, help="output: left/right mean per distance")
    args = parser.parse_args()

    profile = read_table(args.profile, load_schema("profiles"))
    check_no_duplicate_readings(profile, args.profile)
    converted = to_tissue_mm(profile, args.subject, args.magnification)
    averaged = average_sides(converted)
    write_csv(converted, args.converted, CONVERTED_COLUMNS)
    write_csv(averaged, args.averaged, AVERAGED_COLUMNS)
    one_sided = int((averaged["n_sides"] == 1).sum())
    print(
        f"{args.subject}: {len(converted)} readings -> {len(averaged)} averaged points "
        f"({one_sided} one-sided) at {averaged['depth_mm'].nunique()} depths"
    )


if __name__ == "__main__":
    main()
