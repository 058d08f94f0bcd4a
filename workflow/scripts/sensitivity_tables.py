"""Entry point of rule sensitivity_tables: collect the refits and summarise them."""

import argparse

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.io import read_results_csv, write_csv, write_text
from lineload.sensitivity import CHECK_COLUMNS, SENSITIVITY_COLUMNS, summary_markdown


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--notice", default="")
    parser.add_argument("--sensitivity", nargs="+", required=True)
    parser.add_argument("--checks", nargs="+", required=True)
    parser.add_argument("--sensitivity-out", required=True)
    parser.add_argument("--checks-out", required=True)
    parser.add_argument("--markdown", required=True)
    args = parser.parse_args()

    sensitivity = pd.concat([read_results_csv(p) for p in args.sensitivity], ignore_index=True)
    checks = pd.concat([read_results_csv(p) for p in args.checks], ignore_index=True)
    write_csv(sensitivity, args.sensitivity_out, SENSITIVITY_COLUMNS)
    write_csv(checks, args.checks_out, CHECK_COLUMNS)
    write_text(summary_markdown(sensitivity, checks, args.notice), args.markdown)
    print(f"{len(sensitivity)} refits and {len(checks)} trial checks collected")


if __name__ == "__main__":
    main()
