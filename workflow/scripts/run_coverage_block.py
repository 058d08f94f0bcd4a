"""Rule coverage_block: the coverage study in one scenario of errors, every model."""

from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given
from lineload.simulation.coverage import SCENARIOS, TRIAL_COLUMNS, coverage_study


def coverage_block(output, scenario, seed, datasets):
    """Run scenario ``scenario`` (its index in SCENARIOS); write every trial's row."""
    rows = coverage_study(seed, datasets, only=(scenario,))
    write_rows(rows, TRIAL_COLUMNS, output)
    print(f"{SCENARIOS[scenario].name}: {datasets} datasets per model, {len(rows)} rows")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        coverage_block(snakemake.output[0], **given(snakemake.params))
