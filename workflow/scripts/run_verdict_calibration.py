"""Rule verdict_calibration: how often each claim's rule reaches the right verdict."""

from lineload.io import output_to, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.reports import calibration_command, verdict_markdown
from lineload.simulation.verdicts import (
    DATASET_COLUMNS,
    SUMMARY_COLUMNS,
    summarise_verdicts,
    verdict_study,
)


def verdict_calibration(outputs, seed, datasets, window_mm, priors, max_trials, claims, wall):
    """Run the verdict study (the bending skin fitted too, with walls ``wall``); write every
    dataset's verdicts, the summary and its Markdown."""
    rows = verdict_study(seed, datasets, window_mm, priors, max_trials, claims, wall=wall)
    summary = summarise_verdicts(rows)
    write_rows(rows, DATASET_COLUMNS, outputs.datasets)
    write_rows(summary, SUMMARY_COLUMNS, outputs.summary)
    command = calibration_command(seed, verdict_datasets=datasets)
    write_text(verdict_markdown(summary, command), outputs.markdown)
    for row in summary:
        print(
            f"{row['claim']}: truth {row['truth'] or '-'}, {row['n_wrong']} wrong of "
            f"{row['n_datasets']} ({row['wrong_rate']:.3f})"
        )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        verdict_calibration(snakemake.output, **given(snakemake.params))
