"""Entry point of rule claims_table: recompute the paper's claims C1-C10 with verdicts."""

import argparse

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.claims import CLAIM_COLUMNS, ClaimSettings, claims_markdown, compute_claims
from lineload.io import read_results_csv, write_csv, write_text


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--fits", required=True, help="input: results/tables/fits.csv")
    parser.add_argument("--averaged", nargs="+", required=True, help="input: averaged profiles")
    parser.add_argument("--noise-mm", type=float, required=True)
    parser.add_argument("--large-depth-mm", type=float, required=True)
    parser.add_argument("--symmetry-tolerance", type=float, required=True)
    parser.add_argument("--misfit-growth", type=float, required=True)
    parser.add_argument("--significance", type=float, required=True)
    parser.add_argument(
        "--zero-crossing-rtol",
        type=float,
        default=ClaimSettings.zero_crossing_rtol,
        help="C7: relative tolerance on the numerical zero (floating-point accuracy, not data)",
    )
    parser.add_argument("--notice", default="", help="data notice for the footer ('' = none)")
    parser.add_argument("--csv", required=True, help="output: claims table (CSV)")
    parser.add_argument("--md", required=True, help="output: claims table (Markdown)")
    args = parser.parse_args()

    fits = read_results_csv(args.fits)
    averaged = pd.concat([read_results_csv(path) for path in args.averaged], ignore_index=True)
    settings = ClaimSettings(
        noise_mm=args.noise_mm,
        large_depth_mm=args.large_depth_mm,
        symmetry_tolerance=args.symmetry_tolerance,
        misfit_growth=args.misfit_growth,
        significance=args.significance,
        zero_crossing_rtol=args.zero_crossing_rtol,
    )
    claims = compute_claims(fits, averaged, settings)
    write_csv(claims, args.csv, columns=CLAIM_COLUMNS)
    write_text(claims_markdown(claims, args.notice), args.md)
    for _, row in claims.iterrows():
        print(f"{row['claim']}: {row['verdict']} ({row['our_value']})")


if __name__ == "__main__":
    main()
