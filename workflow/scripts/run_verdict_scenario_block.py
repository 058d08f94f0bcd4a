"""Rule verdict_scenario_block: the verdict calibration's datasets in one world whose
errors are not as stated."""

from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given
from lineload.simulation.coverage import SCENARIOS
from lineload.simulation.verdicts import SCENARIO_DATASET_COLUMNS, verdict_study


def verdict_scenario_block(output, scenario, seed, datasets, window_mm, priors, max_trials, claims):
    """Read datasets 0 to ``datasets`` - 1 in world ``scenario`` (its index in SCENARIOS)."""
    world = SCENARIOS[scenario]
    rows = verdict_study(seed, datasets, window_mm, priors, max_trials, claims, scenario=world)
    write_rows(({"scenario": world.name, **row} for row in rows), SCENARIO_DATASET_COLUMNS, output)
    print(f"{world.name}: {datasets} datasets, {sum(r['wrong'] for r in rows)} wrong verdicts")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        verdict_scenario_block(snakemake.output[0], **given(snakemake.params))
