"""Rule boundary_calibration: the blocks of every boundary world gathered and summarised."""

import csv

from lineload.io import output_to, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.boundary import (
    BOUNDARY_COLUMNS,
    BOUNDARY_SUMMARY_COLUMNS,
    summarise_boundary,
)
from lineload.simulation.reports import boundary_markdown, calibration_command

#: How the gathered rows' columns are read back (the rest are text).
_TYPES = {"effect": float, "dataset": int}
_FLAGS = ("wrong_holds", "wrong_fails")


def _read_block(path):
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        for key, kind in _TYPES.items():
            row[key] = kind(row[key])
        for key in _FLAGS:
            row[key] = row[key] == "True"
    return rows


def boundary_calibration(outputs, blocks, seed, datasets):
    """Gather the blocks; write every dataset's verdict, the summary and its Markdown."""
    rows = [row for path in blocks for row in _read_block(path)]
    rows.sort(key=lambda r: (r["world"], r["side"], r["dataset"]))
    summary = summarise_boundary(rows)
    order = {row["world"]: i for i, row in enumerate(summary)}
    rows.sort(key=lambda r: (order[r["world"]], r["side"] != "holding", r["dataset"]))
    write_rows(rows, BOUNDARY_COLUMNS, outputs.datasets)
    write_rows(summary, BOUNDARY_SUMMARY_COLUMNS, outputs.summary)
    command = calibration_command(seed, verdict_datasets=datasets)
    write_text(boundary_markdown(summary, command), outputs.markdown)
    for row in summary:
        print(
            f"{row['world']} ({row['claim']}, {row['side']} side): truth {row['truth']}, "
            f"'holds' wrong in {row['n_wrong_holds']}, 'does not hold' wrong in "
            f"{row['n_wrong_fails']} of {row['n_datasets']}"
        )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        boundary_calibration(
            snakemake.output, list(snakemake.input.blocks), **given(snakemake.params)
        )
