"""The generator in the coverage study's worlds: the verdicts when the priors are wrong."""

import numpy as np
import pandas as pd

from lineload.claims import FAILS, HOLDS
from lineload.simulation import readings, subjects
from lineload.simulation.coverage import SCENARIOS
from lineload.simulation.errors import AS_ASSUMED, TRUE_NOISE, Scenario
from lineload.simulation.reports import verdict_scenarios_markdown
from lineload.simulation.verdicts import SCENARIO_SUMMARY_COLUMNS, summarise_scenario_verdicts

SUBJECT = subjects.shipped_subjects()[0]


def test_the_world_as_stated_is_the_shipped_generator():
    shipped = readings.profile_table(SUBJECT, 1989)
    pd.testing.assert_frame_equal(
        readings.profile_table(SUBJECT, 1989, scenario=AS_ASSUMED), shipped
    )
    pd.testing.assert_frame_equal(
        readings.profile_table(SUBJECT, 1989, scenario=Scenario("same sizes", prior_ratio=1.0)),
        shipped,
    )


def test_a_world_with_other_sizes_scales_the_same_draws():
    # the shared errors are the stated draws times the ratio: at ratio 0 they vanish and
    # the readings move; the per-side errors and the grid are the same draws either way
    stated = readings.trial_errors(SUBJECT, 7)
    none = readings.trial_errors(SUBJECT, 7, Scenario("0x", prior_ratio=0.0).true_noise(TRUE_NOISE))
    assert all(v == (0.0, 0.0, 0.0) for v in none.values())
    assert any(any(x != 0 for x in v) for v in stated.values())
    tripled = Scenario("3x", prior_ratio=3.0)
    read = readings.profile_table(SUBJECT, 7, scenario=tripled)
    plain = readings.profile_table(SUBJECT, 7)
    np.testing.assert_array_equal(read["distance_image_mm"], plain["distance_image_mm"])
    assert not np.array_equal(read["deflection_image_mm"], plain["deflection_image_mm"])


def test_curvature_and_misreads_move_the_readings_only_where_made():
    plain = readings.profile_table(SUBJECT, 7)
    for world in SCENARIOS:
        if world.curvature_sd_per_mm or world.misread_fraction:
            read = readings.profile_table(SUBJECT, 7, scenario=world)
            assert not np.array_equal(read["deflection_image_mm"], plain["deflection_image_mm"])


def test_the_summary_is_per_world_with_its_sizes():
    rows = [
        {"scenario": world.name, "dataset": k, "claim": "C2", "truth": HOLDS, "verdict": verdict,
         "wrong": verdict == FAILS}
        for world in SCENARIOS[3:5]
        for k, verdict in enumerate((HOLDS, FAILS, HOLDS))
    ]  # fmt: skip
    summary = summarise_scenario_verdicts(rows, SCENARIOS)
    assert [r["scenario"] for r in summary] == [w.name for w in SCENARIOS[3:5] for _ in (0, 1)]
    assert all(set(r) == set(SCENARIO_SUMMARY_COLUMNS) for r in summary)
    first = summary[0]
    assert (first["claim"], first["n_datasets"], first["n_wrong"]) == ("C2", 3, 1)
    assert first["prior_ratio"] == SCENARIOS[3].prior_ratio
    text = verdict_scenarios_markdown(summary, "snakemake calibration")
    assert f"| {SCENARIOS[3].name} | C2 | holds | 3 | 2 | 1 | 0 |" in text
