"""The calibration world of the finite-element finger (lineload.simulation.elastic_world).

A small run of the study's functions gives its scores' structure and passes checks that can
fail; the committed profiles regenerate for one finger.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from lineload.claims import FAILS, HOLDS
from lineload.elastic.library import LibraryGrid
from lineload.fitting.elastic import library_blocks
from lineload.io import config_defaults
from lineload.noise import NoiseModel
from lineload.simulation import elastic_world as world
from lineload.simulation.coverage import CHECKED
from lineload.simulation.errors import IMAGE_RESOLUTION_MM
from lineload.simulation.subjects import MAGNIFICATION

REPO = Path(__file__).resolve().parents[1]
PROFILES = REPO / "docs" / "calibration" / "elastic_world_profiles.csv"
WINDOW_MM = 3.0


@cache
def committed():
    return pd.read_csv(PROFILES)


@cache
def small_solutions():
    """The committed profiles of the first section of each species, homogeneous and at 20."""
    table = committed()
    keep = (table["section"] == 0) & table["modulus_ratio"].isin([1.0, 20.0])
    return world.solutions_from_table(table[keep])


@cache
def blocks():
    return library_blocks(pd.read_csv(REPO / config_defaults("elastic")["library_file"]))


def priors():
    noise = config_defaults("noise")
    return noise, noise.pop("max_trials")


@cache
def small_dataset(ratio):
    noise, max_trials = priors()
    return world.world_dataset(
        small_solutions(),
        ratio,
        (7, 0),
        WINDOW_MM,
        noise,
        max_trials,
        blocks(),
        config_defaults("claims"),
    )


def test_committed_profiles_regenerate_for_one_finger():
    grid = LibraryGrid.from_config(config_defaults("elastic"))
    section = world.world_sections("monkey", grid)[1]
    again = world.solve_world_profiles("monkey", [section], [5.0], grid.depths_mm)
    table = committed()
    kept = table[(table["species"] == "monkey") & (table["section"] == 1)]
    kept = kept[kept["modulus_ratio"] == 5.0].reset_index(drop=True)
    assert len(again) == len(kept)
    assert np.allclose(again["distance_mm"], kept["distance_mm"], rtol=0, atol=1e-6)
    # the solver's own output, rounded to 0.1 nm: equal within a micrometre's thousandth
    assert np.allclose(again["deflection_mm"], kept["deflection_mm"], rtol=0, atol=1e-6)
    assert np.allclose(
        again["force_per_length_N_per_mm"], kept["force_per_length_N_per_mm"], rtol=1e-6
    )


def test_kept_profiles_are_read_as_the_element_reads_them():
    """Between nodes the kept profile is the quadratic element's trace: it passes through
    every node and through the midpoint nodes of each side."""
    solution = small_solutions()[("human", 0, 20.0, 1.0)]
    assert np.allclose(
        solution.deflection_at_mm(solution.distance_mm), solution.deflection_mm, atol=1e-12
    )
    assert solution.distance_mm[-1] >= world.READ_REACH_MM["human"] + world.SHIFT_ROOM_MM


def test_reading_without_errors_is_the_profile_rounded():
    """With every error zero the reading is the true profile rounded to the enlargement's
    resolution; with the default errors it is not."""
    solutions = small_solutions()
    fingers = world.world_fingers(20.0, 1)
    zero = NoiseModel(0.0, 0.0, 0.5, 0.0)
    read, true = world.read_dataset(solutions, fingers, (1.0,), np.random.default_rng(1), zero)
    for (_, _, r), (_, _, t) in zip(read, true, strict=True):
        difference = r["deflection_image_mm"] - t["deflection_image_mm"]
        assert np.abs(difference).max() <= IMAGE_RESOLUTION_MM / 2 + 1e-12
    read, true = world.read_dataset(solutions, fingers, (1.0,), np.random.default_rng(1))
    differences = [
        r["deflection_image_mm"] - t["deflection_image_mm"]
        for (*_, r), (*_, t) in zip(read, true, strict=True)
    ]
    assert max(np.abs(d).max() for d in differences) > 2 * IMAGE_RESOLUTION_MM
    reach = [t["distance_image_mm"].max() / MAGNIFICATION for *_, t in true]
    assert reach == [world.READ_REACH_MM["monkey"], world.READ_REACH_MM["human"]]


def test_scores_have_their_structure():
    scores = small_dataset(20.0)
    trials = 2 * 4  # one section per species, four depths
    parameters = sum(len(names) for names in CHECKED.values())
    assert len(scores["coverage"]) == trials * parameters
    assert len(scores["ratio"]) == trials
    claims = [row["claim"] for row in scores["verdicts"]]
    assert "C12" in claims
    assert not set(claims) & set(world.NOT_JUDGED)
    for row in scores["coverage"]:
        assert set(row) == set(world.COVERAGE_COLUMNS) - {"world", "dataset"}
        assert row["covered"] == (row["low"] <= row["true"] <= row["high"])
    # C12's truth is the finger's own
    (c12,) = [row for row in scores["verdicts"] if row["claim"] == "C12"]
    assert c12["truth"] == HOLDS
    (c12,) = [row for row in small_dataset(1.0)["verdicts"] if row["claim"] == "C12"]
    assert c12["truth"] == FAILS


def test_truth_is_the_best_fit_to_the_error_free_profile():
    """The truth of a trial is the fit to the error-free mean: its value lies
    near the estimate from the read data (the errors are small), and a planted wrong truth
    (the truth times 1.5) is covered far less often."""
    rows = small_dataset(20.0)["coverage"]
    ratios = np.array([r["estimate"] / r["true"] for r in rows])
    assert np.median(np.abs(ratios - 1)) < 0.1
    right = world.summarise_world_coverage([{**r, "world": "w", "dataset": 0} for r in rows])
    wrong = world.summarise_world_coverage(
        [
            {
                **r,
                "world": "w",
                "dataset": 0,
                "true": 1.5 * r["true"],
                "covered": r["low"] <= 1.5 * r["true"] <= r["high"],
            }
            for r in rows
        ]
    )
    pooled = {(s["model"], s["parameter"]): s for s in right if s["species"] == "all"}
    # a truth on the search bound leaves the interior count
    bounded = world.summarise_world_coverage(
        [{**r, "world": "w", "dataset": 0, "true_at_bound": True} for r in rows]
    )
    assert all(s["n_interior"] == 0 for s in bounded)
    planted = {(s["model"], s["parameter"]): s for s in wrong if s["species"] == "all"}
    assert sum(s["k"] for s in planted.values()) < sum(s["k"] for s in pooled.values()) / 2
    for key, summary in pooled.items():
        assert summary["n"] == 8
        assert summary["n_interior"] == summary["n"] - summary["n_true_at_bound"]
        assert summary["ci_low"] <= summary["rate"] <= summary["ci_high"]
        assert planted[key]["rate"] <= summary["rate"]


def test_ratio_recovery_scores_the_truth_it_is_given():
    rows = small_dataset(20.0)["ratio"]
    summary = world.summarise_ratio([{**r, "world": "w", "dataset": 0} for r in rows])
    (pooled,) = [s for s in summary if s["species"] == "all"]
    assert pooled["n_trials"] == 8
    assert pooled["n_covered"] == sum(r["low"] <= 20.0 <= r["high"] for r in rows)
    aimed = sum(r["low"] <= r["error_free_ratio"] <= r["high"] for r in rows)
    assert pooled["n_covers_error_free"] == aimed
    # the error-free fit lands near the finger's ratio (off-library section and mesh)
    assert all(10.0 < r["error_free_ratio"] < 40.0 for r in rows)
    # a layer twenty times stiffer is seen: the interval excludes a homogeneous finger
    assert pooled["n_excludes_1"] >= 6
    # planted: a finger called homogeneous is covered only where the interval reaches 1
    planted = [{**r, "covered": r["low"] <= 1.0 <= r["high"]} for r in rows]
    assert sum(r["covered"] for r in planted) == sum(not r["excludes_1"] for r in rows)


def test_verdict_summary_counts_wrong_verdicts_per_world():
    rows = [{**r, "world": "w", "dataset": 0} for r in small_dataset(20.0)["verdicts"]]
    summary = world.summarise_world_verdicts(rows)
    assert {s["world"] for s in summary} == {"w"}
    assert summary[-1]["claim"] == "any"
    # a planted wrong truth for C12 (homogeneous where the finger is layered) makes its
    # verdict wrong if the rule called the layer
    c12 = [r for r in rows if r["claim"] == "C12"]
    flipped = [
        {**r, "truth": FAILS, "wrong": r["verdict"] == HOLDS} if r["claim"] == "C12" else r
        for r in rows
    ]
    before = {s["claim"]: s for s in summary}
    after = {s["claim"]: s for s in world.summarise_world_verdicts(flipped)}
    assert before["C12"]["n_wrong"] == sum(r["verdict"] == FAILS for r in c12)
    assert after["C12"]["n_wrong"] == sum(r["verdict"] == HOLDS for r in c12)


@pytest.mark.parametrize("ratio", [1.0, 20.0])
def test_world_names(ratio):
    name = world.world_name(ratio)
    assert ("homogeneous" in name) == (ratio == 1.0)


def test_a_seed_repeats_and_wrong_priors_change_the_readings_not_the_truth():
    noise, max_trials = priors()
    again = world.world_dataset(
        small_solutions(),
        1.0,
        (7, 0),
        WINDOW_MM,
        noise,
        max_trials,
        blocks(),
        config_defaults("claims"),
    )
    first = small_dataset(1.0)
    for part in ("coverage", "verdicts", "ratio"):
        assert pd.DataFrame(again[part]).equals(pd.DataFrame(first[part]))
    wrong = world.world_dataset(
        small_solutions(),
        1.0,
        (7, 0),
        WINDOW_MM,
        noise,
        max_trials,
        blocks(),
        config_defaults("claims"),
        prior_ratio=3.0,
    )
    made, stated = pd.DataFrame(wrong["coverage"]), pd.DataFrame(first["coverage"])
    assert np.array_equal(made["true"], stated["true"])
    assert not np.array_equal(made["estimate"], stated["estimate"])
    truths = [r["truth"] for r in wrong["verdicts"]]
    assert truths == [r["truth"] for r in first["verdicts"]]
    assert world.world_name(1.0, 3.0) == "homogeneous, shared errors 3x"
