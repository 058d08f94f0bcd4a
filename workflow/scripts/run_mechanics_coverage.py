"""Rule mechanics_coverage: do the membrane's intervals cover its true N0, E, pre-strain?"""

from lineload.io import output_to, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.mechanics_coverage import (
    MECHANICS_COLUMNS,
    MECHANICS_SUMMARY_COLUMNS,
    mechanics_study,
    summarise_mechanics,
)
from lineload.simulation.reports import calibration_command, mechanics_markdown


def mechanics_coverage(outputs, seed, datasets, window_mm, priors, max_trials, force_sd_N):
    """Run the study; write every subject's estimates, the coverage and its Markdown."""
    rows = mechanics_study(seed, datasets, window_mm, priors, max_trials, force_sd_N)
    summary = summarise_mechanics(rows)
    write_rows(rows, MECHANICS_COLUMNS, outputs.subjects)
    write_rows(summary, MECHANICS_SUMMARY_COLUMNS, outputs.summary)
    command = calibration_command(seed, verdict_datasets=datasets)
    write_text(mechanics_markdown(summary, command), outputs.markdown)
    for row in summary:
        print(f"{row['parameter']} ({row['fit']}): {row['n_covered']}/{row['n']}")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        mechanics_coverage(snakemake.output, **given(snakemake.params))
