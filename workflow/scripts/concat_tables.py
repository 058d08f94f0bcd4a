"""Rule fits_table: concatenate the batches' CSV tables in the given order.

Imports no numpy or pandas: it runs once per build over every batch's file, so its
cost should be Python's start-up alone.
"""

from lineload.io import concatenate_csv, output_to

if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        n_rows = concatenate_csv(snakemake.input.tables, snakemake.output[0])
        print(f"{snakemake.output[0]}: {n_rows} rows from {len(snakemake.input.tables)} files")
