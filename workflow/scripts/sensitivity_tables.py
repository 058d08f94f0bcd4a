"""Rule sensitivity_tables: collect the refits and per-trial checks; summarise them."""

import pandas as pd

from lineload.fitting.sensitivity import CHECK_COLUMNS, SENSITIVITY_COLUMNS
from lineload.io import output_to, read_results_csv, write_csv, write_text
from lineload.publishing.tables import sensitivity_markdown
from lineload.runtime.jobparams import given


def sensitivity_tables(inputs, outputs, notice):
    """Concatenate the batches' refits and checks; write them and the Markdown summary."""
    sensitivity = pd.concat([read_results_csv(p) for p in inputs.sensitivity], ignore_index=True)
    checks = pd.concat([read_results_csv(p) for p in inputs.checks], ignore_index=True)
    write_csv(sensitivity, outputs.sensitivity, SENSITIVITY_COLUMNS)
    write_csv(checks, outputs.checks, CHECK_COLUMNS)
    write_text(sensitivity_markdown(sensitivity, checks, notice), outputs.markdown)
    print(f"{len(sensitivity)} refits and {len(checks)} trial checks collected")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        sensitivity_tables(snakemake.input, snakemake.output, **given(snakemake.params))
