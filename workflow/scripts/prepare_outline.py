"""Rule prepare_outline: a traced outline (image mm) -> tissue mm.

Keeps the image-unit columns beside the tissue values, as prepare_profiles does,
and sorts the points by depth, state and position so they can be drawn as lines.
"""

import pandas as pd

from lineload.io import load_schema, output_to, read_json, write_csv
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


def prepare_outline(outline_path, subject, magnification, output_path):
    """Convert one subject's outlines to tissue mm and write them."""
    outline = read_table(outline_path, load_schema("outlines"))
    converted = pd.DataFrame(
        {
            "subject": subject,
            "depth_mm": outline["depth_mm"].astype(float).to_numpy(),
            "state": outline["state"].to_numpy(),
            "x_image_mm": outline["x_image_mm"].astype(float).to_numpy(),
            "z_image_mm": outline["z_image_mm"].astype(float).to_numpy(),
            "magnification": magnification,
        }
    )
    converted["x_mm"] = converted["x_image_mm"] / magnification
    converted["z_mm"] = converted["z_image_mm"] / magnification
    converted = converted.sort_values(["depth_mm", "state", "x_mm"], kind="stable")
    write_csv(converted.reset_index(drop=True), output_path, OUTLINE_COLUMNS)
    print(
        f"{subject}: {len(converted)} outline points at "
        f"{converted['depth_mm'].nunique()} depths -> {output_path}"
    )


with output_to(snakemake.log[0]):
    prepare_outline(snakemake.input.outline, **read_json(snakemake.input.spec), output_path=snakemake.output[0])
