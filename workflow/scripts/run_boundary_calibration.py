"""Rule boundary_calibration: each claim's verdicts where the claim just stops being true."""

from lineload.calibration import (
    BOUNDARY_COLUMNS,
    BOUNDARY_SUMMARY_COLUMNS,
    BOUNDARY_WORLDS,
    boundary_markdown,
    boundary_study,
    summarise_boundary,
)
from lineload.coverage import calibration_command
from lineload.io import output_to, write_rows, write_text
from lineload.jobparams import given


def boundary_calibration(outputs, seed, datasets, window_mm, priors, max_trials, claims):
    """Run every boundary world; write its datasets' verdicts, the summary and its Markdown."""
    rows = []
    for world in BOUNDARY_WORLDS:
        found = boundary_study(world, seed, datasets, window_mm, priors, max_trials, claims)
        print(f"{world}: boundary at t = {found[0]['effect']:.6g}")
        rows.extend(found)
    summary = summarise_boundary(rows)
    write_rows(rows, BOUNDARY_COLUMNS, outputs.datasets)
    write_rows(summary, BOUNDARY_SUMMARY_COLUMNS, outputs.summary)
    command = calibration_command(seed, verdict_datasets=datasets)
    write_text(boundary_markdown(summary, command), outputs.markdown)
    for row in summary:
        print(
            f"{row['world']} ({row['claim']}): truth {row['truth']}, {row['n_wrong']} wrong "
            f"of {row['n_datasets']} ({row['wrong_rate']:.3f})"
        )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        boundary_calibration(snakemake.output, **given(snakemake.params))
