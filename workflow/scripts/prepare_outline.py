"""Rule prepare_outline: a traced outline (image mm) -> tissue mm."""

from lineload.averaging import OUTLINE_COLUMNS, outline_to_tissue_mm
from lineload.io import load_schema, output_to, write_csv
from lineload.rawdata.sheets import read_table
from lineload.runtime.jobparams import given


def prepare_outline(outline_path, output_path, subject, magnification):
    """Convert one subject's outlines to tissue mm and write them."""
    outline = read_table(outline_path, load_schema("outlines"))
    converted = outline_to_tissue_mm(outline, subject, magnification)
    write_csv(converted, output_path, OUTLINE_COLUMNS)
    print(
        f"{subject}: {len(converted)} outline points at "
        f"{converted['depth_mm'].nunique()} depths -> {output_path}"
    )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        prepare_outline(snakemake.input.outline, snakemake.output[0], **given(snakemake.params))
