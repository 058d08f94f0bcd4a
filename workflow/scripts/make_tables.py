"""Entry point of rule fit_tables: fit table and species summary as Markdown, LaTeX and CSV."""

import argparse

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.io import read_results_csv, write_csv, write_text
from lineload.tables import (
    SUMMARY_COLUMNS,
    fits_latex,
    fits_markdown,
    summarise_fits,
    summary_latex,
    summary_markdown,
)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--fits", required=True, help="input: results/tables/fits.csv")
    parser.add_argument("--notice", default="", help="data notice for the footers ('' = none)")
    parser.add_argument("--fits-md", required=True)
    parser.add_argument("--fits-tex", required=True)
    parser.add_argument("--summary-csv", required=True)
    parser.add_argument("--summary-md", required=True)
    parser.add_argument("--summary-tex", required=True)
    args = parser.parse_args()

    fits = read_results_csv(args.fits)
    summary = summarise_fits(fits)
    write_text(fits_markdown(fits, args.notice), args.fits_md)
    write_text(fits_latex(fits, args.notice), args.fits_tex)
    write_csv(summary, args.summary_csv, columns=SUMMARY_COLUMNS)
    write_text(summary_markdown(summary, args.notice), args.summary_md)
    write_text(summary_latex(summary, args.notice), args.summary_tex)
    print(f"{args.fits}: {len(fits)} trials -> {len(summary)} species/depth rows")


if __name__ == "__main__":
    main()
