"""Rule coverage: the scenarios' blocks gathered; the coverage summary and its Markdown."""

from lineload.io import output_to, read_rows, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.coverage import (
    COVERAGE_STUDY_COLUMNS,
    TRIAL_COLUMNS,
    described,
    summarise_coverage,
)
from lineload.simulation.reports import calibration_command, coverage_markdown


def _read_block(path):
    """A block's rows: text as written, but the columns the summary groups and counts by."""
    rows = read_rows(path)
    for row in rows:
        row["depth_mm"] = float(row["depth_mm"])
        row["dataset"] = int(row["dataset"])
        row["covered"] = row["covered"] == "True"
    return rows


def coverage(outputs, blocks, seed, datasets):
    """Gather the blocks (in scenario order); write every trial, the summary and its Markdown."""
    rows = [row for path in blocks for row in _read_block(path)]
    summary = described(summarise_coverage(rows))
    write_rows(rows, TRIAL_COLUMNS, outputs.trials)
    write_rows(summary, COVERAGE_STUDY_COLUMNS, outputs.summary)
    command = calibration_command(seed, datasets=datasets)
    write_text(coverage_markdown(summary, command), outputs.markdown)
    for row in summary:
        if row["species"] == "all":
            print(
                f"{row['scenario']}, {row['model']} {row['parameter']}: "
                f"{row['n_covered']}/{row['n_trials']} = {row['coverage']:.3f}"
            )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        coverage(snakemake.output, list(snakemake.input.blocks), **given(snakemake.params))
