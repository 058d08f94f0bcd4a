"""The calibration's figure: coverage against the priors' true/stated size, per family."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from lineload.figures.calibration import NOMINAL, SHOWN, figure_coverage_misspecified
from lineload.simulation.coverage import CHECKED, SCENARIOS, described, summarise_coverage


def _summary(seed=3, n_datasets=30):
    """A coverage summary from trial rows with known coverage per scenario and model:
    the chance of covering falls with the priors' ratio."""
    rng = np.random.default_rng(seed)
    rows = []
    for scenario in SCENARIOS:
        chance = 0.95 if scenario.prior_ratio <= 1 else 0.95 / scenario.prior_ratio
        for model, parameters in CHECKED.items():
            for parameter in parameters:
                for k in range(n_datasets):
                    rows.append(
                        {
                            "scenario": scenario.name,
                            "model": model,
                            "parameter": parameter,
                            "species": "monkey",
                            "depth_mm": 1.0,
                            "dataset": k,
                            "covered": bool(rng.random() < chance),
                        }
                    )
    return pd.DataFrame(described(summarise_coverage(rows)))


def _line(fig, gid):
    found = [line for ax in fig.axes for line in ax.get_lines() if line.get_gid() == gid]
    assert len(found) == 1, gid
    return found[0]


def test_each_family_is_drawn_at_every_ratio_with_the_tables_coverage():
    summary = _summary()
    fig = figure_coverage_misspecified(summary)
    pooled = summary[summary["species"] == "all"]
    scaled = pooled[pooled["misspecified"].isin(["none", "shared errors' sizes"])]
    for model, parameter, _ in SHOWN:
        line = _line(fig, f"coverage:{model}:{parameter}")
        mine = scaled[(scaled["model"] == model) & (scaled["parameter"] == parameter)]
        mine = mine.sort_values("prior_ratio")
        # the x positions are the ratios, nudged apart by at most 7 % (a log offset)
        np.testing.assert_allclose(line.get_xdata(), mine["prior_ratio"], rtol=0.07)
        np.testing.assert_allclose(line.get_ydata(), 100 * mine["coverage"], rtol=1e-12)
        assert sorted(mine["prior_ratio"]) == [0.5, 1.0, 2.0, 3.0]
        # every other world once, beside the assumed one
        other = _line(fig, f"other:{model}:{parameter}")
        assert len(other.get_xdata()) == 1 + sum(
            s.misspecified not in ("none", "shared errors' sizes") for s in SCENARIOS
        )
    nominal = [line for ax in fig.axes for line in ax.get_lines() if line.get_gid() == "nominal"]
    assert nominal and all(line.get_ydata()[0] == pytest.approx(100 * NOMINAL) for line in nominal)


def test_a_table_without_the_misspecified_worlds_says_so():
    old = _summary().drop(columns=["misspecified", "prior_ratio"])
    fig = figure_coverage_misspecified(old, notice="n")
    texts = [t.get_text() for t in fig.findobj(lambda a: a.get_gid() == "message")]
    assert texts and "calibration" in texts[0]
