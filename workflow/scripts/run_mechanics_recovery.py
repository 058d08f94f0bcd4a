"""Rule mechanics_recovery: N0, E and pre-strain recovered when the forces follow the
law the fit inverts and when they follow another."""

from lineload.io import output_to, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.mechanics_coverage import (
    RECOVERY_COLUMNS,
    RECOVERY_SUMMARY_COLUMNS,
    recovery_study,
    summarise_recovery,
)
from lineload.simulation.reports import calibration_command, recovery_markdown


def mechanics_recovery(outputs, seed, datasets, window_mm, priors, max_trials, force_sd_N):
    """Run the recovery check in both force worlds; write every subject, the summary, Markdown."""
    rows = recovery_study(seed, datasets, window_mm, priors, max_trials, force_sd_N)
    summary = summarise_recovery(rows)
    write_rows(rows, RECOVERY_COLUMNS, outputs.subjects)
    write_rows(summary, RECOVERY_SUMMARY_COLUMNS, outputs.summary)
    command = calibration_command(seed, scenario_datasets=datasets)
    write_text(recovery_markdown(summary, command), outputs.markdown)
    for row in summary:
        print(
            f"{row['world']}, {row['parameter']}: {row['n_covered']}/{row['n']}, "
            f"median estimate/truth {row['median_ratio']:.3f}"
        )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        mechanics_recovery(snakemake.output, **given(snakemake.params))
