"""Rule verdict_scenarios: the worlds' blocks gathered and summarised."""

from lineload.io import output_to, read_rows, write_rows, write_text
from lineload.runtime.jobparams import given
from lineload.simulation.coverage import SCENARIOS
from lineload.simulation.reports import calibration_command, verdict_scenarios_markdown
from lineload.simulation.verdicts import (
    SCENARIO_DATASET_COLUMNS,
    SCENARIO_SUMMARY_COLUMNS,
    summarise_scenario_verdicts,
)


def _read_block(path):
    rows = read_rows(path)
    for row in rows:
        row["dataset"] = int(row["dataset"])
        row["wrong"] = row["wrong"] == "True"
    return rows


def verdict_scenarios(outputs, blocks, seed, datasets):
    """Gather the blocks (in world order); write every verdict, the summary and its Markdown."""
    rows = [row for path in blocks for row in _read_block(path)]
    summary = summarise_scenario_verdicts(rows, SCENARIOS)
    write_rows(rows, SCENARIO_DATASET_COLUMNS, outputs.datasets)
    write_rows(summary, SCENARIO_SUMMARY_COLUMNS, outputs.summary)
    command = calibration_command(seed, scenario_datasets=datasets)
    write_text(verdict_scenarios_markdown(summary, command), outputs.markdown)
    for row in summary:
        if row["claim"] == "any":
            print(
                f"{row['scenario']}: {row['n_wrong']} of {row['n_datasets']} with a wrong verdict"
            )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        verdict_scenarios(snakemake.output, list(snakemake.input.blocks), **given(snakemake.params))
