"""Entry point of rule prepare_outline: a traced outline (image mm) -> tissue mm.

Keeps the image-unit columns beside the tissue values, as prepare_profiles does,
and sorts the points by depth, state and position so they can be drawn as lines.
"""

import argparse

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.io import load_schema, write_csv
from lineload.validation import read_table

OUTLINE_COLUMNS = [
    "subject",
    "depth_mm",
    "state",
    "x_image_mm",
    "z_image_mm",
    "magnification",
    "x_mm",
    "z_mm",
]


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--subject", required=True)
    parser.add_argument("--magnification", type=float, required=True)
    parser.add_argument("--outline", required=True, help="raw outlines/<subject>.csv")
    parser.add_argument("--output", required=True, help="output: outline in tissue mm")
    args = parser.parse_args()
    if not args.magnification > 0:
        parser.error(f"magnification must be > 0, got {args.magnification}")

    outline = read_table(args.outline, load_schema("outlines"))
    converted = pd.DataFrame(
        {
            "subject": args.subject,
            "depth_mm": outline["depth_mm"].astype(float).to_numpy(),
            "state": outline["state"].to_numpy(),
            "x_image_mm": outline["x_image_mm"].astype(float).to_numpy(),
            "z_image_mm": outline["z_image_mm"].astype(float).to_numpy(),
            "magnification": args.magnification,
        }
    )
    converted["x_mm"] = converted["x_image_mm"] / args.magnification
    converted["z_mm"] = converted["z_image_mm"] / args.magnification
    converted = converted.sort_values(["depth_mm", "state", "x_mm"], kind="stable")
    write_csv(converted.reset_index(drop=True), args.output, OUTLINE_COLUMNS)
    print(
        f"{args.subject}: {len(converted)} outline points at "
        f"{converted['depth_mm'].nunique()} depths -> {args.output}"
    )


if __name__ == "__main__":
    main()
