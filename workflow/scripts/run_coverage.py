"""Rule coverage: do the intervals cover?  Simulated datasets, fitted as the workflow fits."""

from lineload.io import output_to, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.coverage import (
    COVERAGE_COLUMNS,
    TRIAL_COLUMNS,
    coverage_study,
    summarise_coverage,
)
from lineload.simulation.reports import calibration_command, coverage_markdown


def coverage(outputs, seed, datasets):
    """Run the coverage study; write every trial, the summary and its Markdown."""
    rows = coverage_study(seed, datasets)
    summary = summarise_coverage(rows)
    write_rows(rows, TRIAL_COLUMNS, outputs.trials)
    write_rows(summary, COVERAGE_COLUMNS, outputs.summary)
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
        coverage(snakemake.output, **given(snakemake.params))
