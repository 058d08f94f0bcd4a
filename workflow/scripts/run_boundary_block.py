"""Rule boundary_block: one boundary world, both sides, on one block of datasets."""

from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given
from lineload.simulation.boundary import BOUNDARY_COLUMNS, boundary_study


def boundary_block(
    output, block, seed, datasets, block_datasets, window_mm, priors, max_trials, claims
):
    """Read world ``block = '{world}.{first}'`` on datasets first to first + block - 1."""
    world, first = block.rsplit(".", 1)
    count = min(block_datasets, datasets - int(first))
    rows = boundary_study(
        world, seed, count, window_mm, priors, max_trials, claims, first=int(first)
    )
    write_rows(rows, BOUNDARY_COLUMNS, output)
    print(f"{world}: datasets {first} to {int(first) + count - 1}, {len(rows)} rows")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        boundary_block(snakemake.output[0], **given(snakemake.params))
