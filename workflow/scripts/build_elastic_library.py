"""Rule elastic_library_species: one species' profiles over the library's grid."""

import time

from lineload.elastic.library import LibraryGrid, library_columns, library_rows
from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given


def build_library(output, species, grid):
    """Solve the finger over the grid (every section, thickness, ratio; the depths on one
    factorisation each) and write the profiles, one row per depth."""
    grid = LibraryGrid.from_config(grid)
    start = time.perf_counter()
    rows = library_rows(species, grid, progress=print)
    seconds = time.perf_counter() - start
    factorisations = len(rows) // len(grid.depths_mm)
    print(
        f"{species}: {len(rows)} profiles from {factorisations} factorisations in "
        f"{seconds:.1f} s ({factorisations / seconds:.2f} factorisations per second)"
    )
    write_rows(rows, library_columns(grid.distances_mm()), output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        build_library(snakemake.output[0], **given(snakemake.params))
