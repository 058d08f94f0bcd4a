"""Claims C1-C10: each verdict follows its rule, and flips when the inputs break it."""

import numpy as np
import pandas as pd
import pytest

from conftest import reading_grid_mm, run_snakemake, write_small_dataset
from lineload import claims as claims_module
from lineload import models
from lineload.averaging import AVERAGED_COLUMNS
from lineload.claims import (
    CLAIM_COLUMNS,
    CLAIM_FUNCTIONS,
    VERDICTS,
    ClaimSettings,
    circle_fit,
    claims_markdown,
    compute_claims,
    deformed_extent_mm,
    waterbed_zero_crossing_mm,
)
from lineload.fitting import FIT_COLUMNS, fit_trial

HOLDS, FAILS, UNTESTABLE = "holds", "does not hold", "cannot be checked on these data"
SETTINGS = ClaimSettings(noise_mm=0.01, large_depth_mm=1.5, symmetry_tolerance=0.05)
GRID_MM = reading_grid_mm(12.0)


def profile(subject, depth_mm, deflection_mm, distance_mm=GRID_MM, asymmetry_mm=0.0):
    """Averaged points of one trial; left and right differ by +-asymmetry_mm."""
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.broadcast_to(np.asarray(deflection_mm, dtype=float), distance_mm.shape)
    return pd.DataFrame(
        {
            "subject": subject,
            "depth_mm": depth_mm,
            "distance_mm": distance_mm,
            "left_mm": deflection_mm + asymmetry_mm,
            "right_mm": deflection_mm - asymmetry_mm,
            "left_source": "measured",
            "right_source": "measured",
            "deflection_mm": deflection_mm,
            "n_sides": 2,
        }
    )[AVERAGED_COLUMNS]


def fit_row(subject, species, depth_mm, **values):
    """One row of a fit table; unset columns get harmless values."""
    row = dict.fromkeys(FIT_COLUMNS, np.nan)
    row.update(
        subject=subject,
        species=species,
        depth_mm=depth_mm,
        fit_window_mm=3.0,
        n_points=20,
        max_distance_mm=3.0,
        waterbed_L_mm=12.0,
        waterbed_rmse_mm=0.01 * depth_mm,
        waterbed_aicc=-150.0,
        boussinesq_rmse_mm=0.05,
        boussinesq_aicc=-100.0,
    )
    row.update(values)
    return row


def table(rows):
    return pd.DataFrame(rows, columns=FIT_COLUMNS)


def verdict(claim, fits, averaged, settings=SETTINGS):
    return CLAIM_FUNCTIONS[claim](fits, averaged, settings)["verdict"]


def power_profile_mm(depth_mm, edge_mm, power=2.0):
    """depth (1 - x/edge)**power, zero beyond the edge: no bulge, smooth decay."""
    s = np.clip(1.0 - GRID_MM / edge_mm, 0.0, None)
    return depth_mm * s**power


def fitted_dataset(subjects):
    """Fit table and averaged points from power-law profiles, fitted by the workflow's code.

    ``subjects``: {subject: (species, {depth: edge_mm})}.
    """
    rows, frames = [], []
    for subject, (species, edges) in subjects.items():
        for depth_mm, edge_mm in edges.items():
            w = power_profile_mm(depth_mm, edge_mm)
            frames.append(profile(subject, depth_mm, w))
            rows.append(
                {"subject": subject, "species": species, **fit_trial(GRID_MM, w, depth_mm, 3.0)}
            )
    return table(rows), pd.concat(frames, ignore_index=True)


# ------------------------------------------------------------------- the whole table


def test_claims_table_has_c1_to_c10_with_allowed_verdicts():
    fits, averaged = fitted_dataset(
        {
            "MK": ("monkey", {0.5: 4.0, 1.0: 5.0, 2.0: 6.0}),
            "HU": ("human", {1.0: 9.0, 2.0: 10.0}),
        }
    )
    result = compute_claims(fits, averaged, SETTINGS)
    assert list(result.columns) == CLAIM_COLUMNS
    assert list(result["claim"]) == [f"C{i}" for i in range(1, 11)]
    assert set(result["verdict"]) <= set(VERDICTS)
    assert result[CLAIM_COLUMNS].map(lambda cell: isinstance(cell, str) and cell != "").all().all()
    # the same inputs give the same text
    assert compute_claims(fits, averaged, SETTINGS).equals(result)
    md = claims_markdown(result, notice="Synthetic, for testing")
    body = [ln for ln in md.splitlines() if ln.startswith("| C") and not ln.startswith("| Claim")]
    assert [ln.split(" | ")[0] for ln in body] == [f"| C{i}" for i in range(1, 11)]
    assert md.rstrip().endswith("Note: Synthetic, for testing")
    assert "Note" not in claims_markdown(result, notice="")


def test_rules_state_the_configured_thresholds():
    fits, averaged = fitted_dataset({"MK": ("monkey", {1.0: 5.0}), "HU": ("human", {1.0: 9.0})})
    settings = ClaimSettings(noise_mm=0.03, large_depth_mm=0.75, symmetry_tolerance=0.125)
    rules = compute_claims(fits, averaged, settings).set_index("claim")["rule"]
    assert "0.060 mm" in rules["C1"] and "0.060 mm" in rules["C10"]
    assert "0.125" in rules["C2"]
    assert "0.75 mm" in rules["C9"]


# ------------------------------------------------------------------- one claim at a time


def test_c1_extent_is_where_the_profile_crosses_twice_the_noise():
    distance = np.array([0.5, 1.0, 2.0, 3.0, 4.0])
    deflection = 1.0 - distance / 4.0  # straight line: crosses 0.02 at 4 (1 - 0.02)
    assert deformed_extent_mm(distance, deflection, 0.02) == pytest.approx(3.92)
    assert deformed_extent_mm(distance, np.zeros(5), 0.02) == 0.0
    assert deformed_extent_mm(distance, np.full(5, 0.5), 0.02) == 4.0  # readings stop first


def test_c1_flips_when_humans_are_not_wider_and_is_untestable_without_humans():
    def dataset(human_edge_mm):
        fits = table([fit_row("MK", "monkey", 1.0), fit_row("HU", "human", 1.0)])
        averaged = pd.concat(
            [
                profile("MK", 1.0, power_profile_mm(1.0, 5.0)),
                profile("HU", 1.0, power_profile_mm(1.0, human_edge_mm)),
            ]
        )
        return fits, averaged

    assert verdict("C1", *dataset(9.0)) == HOLDS
    assert verdict("C1", *dataset(4.0)) == FAILS
    fits, averaged = dataset(9.0)
    only_monkeys = fits[fits["species"] == "monkey"]
    row = CLAIM_FUNCTIONS["C1"](only_monkeys, averaged, SETTINGS)
    assert row["verdict"] == UNTESTABLE and "no human" in row["our_value"]


def test_c2_follows_the_left_right_difference():
    fits = table([fit_row("MK", "monkey", 1.0)])
    w = power_profile_mm(1.0, 5.0)
    # RMS(left - right) / depth = 2 * asymmetry / depth
    assert verdict("C2", fits, profile("MK", 1.0, w, asymmetry_mm=0.02)) == HOLDS
    assert verdict("C2", fits, profile("MK", 1.0, w, asymmetry_mm=0.03)) == FAILS
    one_sided = profile("MK", 1.0, w).assign(right_source="interpolated")
    assert verdict("C2", fits, one_sided) == UNTESTABLE


def test_c3_needs_the_waterbed_better_in_every_trial():
    good = [fit_row("A", "monkey", 1.0), fit_row("B", "human", 1.0)]
    assert verdict("C3", table(good), None) == HOLDS
    bad = [*good, fit_row("C", "human", 2.0, waterbed_rmse_mm=0.2, waterbed_aicc=-50.0)]
    assert verdict("C3", table(bad), None) == FAILS
    no_boussinesq = [fit_row("A", "monkey", 1.0, boussinesq_rmse_mm=np.nan)]
    assert verdict("C3", table(no_boussinesq), None) == UNTESTABLE


def test_c4_flips_when_the_data_follow_the_predicted_bulge():
    L_mm, depth_mm = 12.0, 1.5
    fits = table([fit_row("HU", "human", depth_mm, waterbed_L_mm=L_mm)])
    curve = models.waterbed_deflection_mm(GRID_MM, depth_mm, L_mm)
    assert curve.min() < -0.02  # the readings reach the bulge
    assert verdict("C4", fits, profile("HU", depth_mm, np.clip(curve, 0, None))) == HOLDS
    assert verdict("C4", fits, profile("HU", depth_mm, curve)) == FAILS
    near = GRID_MM < L_mm / 3
    assert verdict("C4", fits, profile("HU", depth_mm, curve[near], GRID_MM[near])) == UNTESTABLE


def test_c5_range_of_L():
    rows = [fit_row("A", "monkey", 1.0, waterbed_L_mm=10.5), fit_row("B", "human", 1.0)]
    assert verdict("C5", table(rows), None) == HOLDS
    rows.append(fit_row("C", "human", 2.0, waterbed_L_mm=20.0))
    assert verdict("C5", table(rows), None) == FAILS
    assert verdict("C5", table([fit_row("A", "monkey", 1.0, waterbed_L_mm=np.nan)]), None) == (
        UNTESTABLE
    )


def test_c6_shift_fraction_against_its_closed_form():
    depth_mm, L_mm = 1.0, 12.0
    row = CLAIM_FUNCTIONS["C6"](table([fit_row("A", "monkey", depth_mm)]), None, SETTINGS)
    fraction = (8 * depth_mm**2 / (9 * L_mm)) / (L_mm / 3)
    assert row["verdict"] == HOLDS
    assert f"{100 * fraction:.1f} %" in row["our_value"]
    shallow_membrane = table([fit_row("A", "monkey", 2.0, waterbed_L_mm=10.0)])  # 10.7 %
    assert verdict("C6", shallow_membrane, None) == FAILS


@pytest.mark.parametrize(("depth_mm", "L_mm"), [(0.5, 10.0), (1.0, 12.3), (2.0, 14.9), (3.0, 7.0)])
def test_c7_numerical_zero_is_L_over_3(depth_mm, L_mm):
    root = waterbed_zero_crossing_mm(depth_mm, L_mm)
    assert root == pytest.approx(L_mm / 3, rel=1e-12)
    assert abs(float(models.waterbed_deflection_mm(root, depth_mm, L_mm))) < 1e-12


def test_c7_uses_the_curve_not_the_formula(monkeypatch):
    fits = table([fit_row("A", "monkey", 1.0), fit_row("B", "human", 2.0, waterbed_L_mm=14.0)])
    assert verdict("C7", fits, None) == HOLDS

    def curve_with_zero_at_half_L(distance_mm, depth_mm, L_mm):
        return depth_mm * (1.0 - 2.0 * np.asarray(distance_mm, dtype=float) / L_mm)

    monkeypatch.setattr(claims_module, "waterbed_deflection_mm", curve_with_zero_at_half_L)
    assert verdict("C7", fits, None) == FAILS


def test_c8_waterbed_error_must_grow_with_depth_in_every_subject():
    def rows(rmse_by_depth):
        return [fit_row("A", "monkey", d, waterbed_rmse_mm=r) for d, r in rmse_by_depth.items()] + [
            fit_row("B", "human", d, waterbed_rmse_mm=2 * r) for d, r in rmse_by_depth.items()
        ]

    assert verdict("C8", table(rows({0.5: 0.01, 1.0: 0.02, 2.0: 0.05})), None) == HOLDS
    worse = rows({0.5: 0.01, 1.0: 0.02, 2.0: 0.05})
    worse[2]["waterbed_rmse_mm"] = 0.015  # subject A better at 2 mm than at 1 mm
    assert verdict("C8", table(worse), None) == FAILS
    single = table([fit_row("A", "monkey", 1.0), fit_row("B", "human", 2.0)])
    assert verdict("C8", single, None) == UNTESTABLE


def test_c9_data_below_the_curve_at_large_depths():
    L_mm = 12.0
    curve = models.waterbed_deflection_mm(GRID_MM, 2.0, L_mm)
    fits = table([fit_row("A", "monkey", 2.0, waterbed_L_mm=L_mm)])
    assert verdict("C9", fits, profile("A", 2.0, curve - 0.01)) == HOLDS
    assert verdict("C9", fits, profile("A", 2.0, curve + 0.01)) == FAILS
    # only 1 mm trials: nothing at or above large_depth_mm
    shallow = table([fit_row("A", "monkey", 1.0, waterbed_L_mm=L_mm)])
    assert verdict("C9", shallow, profile("A", 1.0, curve / 2)) == UNTESTABLE
    lower = ClaimSettings(large_depth_mm=1.0)
    assert verdict("C9", shallow, profile("A", 1.0, curve / 2 - 0.01), lower) == HOLDS


def test_circle_fit_recovers_a_known_circle():
    angle = np.linspace(0.2, 1.2, 15)
    x, z = 1.5 + 9.0 * np.cos(angle), -7.0 + 9.0 * np.sin(angle)
    circle = circle_fit(x, z)
    assert circle["centre_x_mm"] == pytest.approx(1.5, abs=1e-8)
    assert circle["centre_z_mm"] == pytest.approx(-7.0, abs=1e-8)
    assert circle["radius_mm"] == pytest.approx(9.0, rel=1e-10)
    assert circle["rms_distance_mm"] < 1e-9


def test_c10_circle_holds_for_an_arc_and_fails_for_a_log_profile():
    window = GRID_MM[GRID_MM <= 3.0]
    fits = table([fit_row("A", "monkey", 1.0)])
    # a circle of radius 10 mm through (0, -1): deflection 1 - (10 - sqrt(100 - x^2))
    arc = 1.0 - (10.0 - np.sqrt(100.0 - window**2))
    assert verdict("C10", fits, profile("A", 1.0, arc, window)) == HOLDS
    logarithmic = models.boussinesq_deflection_mm(window, 0.3, 6.0)
    assert verdict("C10", fits, profile("A", 1.0, logarithmic, window)) == FAILS
    assert verdict("C10", fits, profile("A", 1.0, arc[:3], window[:3])) == UNTESTABLE


def test_c10_cannot_judge_a_straight_profile():
    # a line is a circle of infinite radius: it fits a free circle perfectly, yet it says
    # nothing about the curvature the claim is about
    window = GRID_MM[GRID_MM <= 3.0]
    fits = table([fit_row("A", "monkey", 1.0)])
    line = 1.0 - 0.3 * window
    assert verdict("C10", fits, profile("A", 1.0, line, window)) == UNTESTABLE
    # beside a curved trial, the straight one is left out rather than counted for the claim
    arc = 1.0 - (10.0 - np.sqrt(100.0 - window**2))
    both = table([fit_row("A", "monkey", 1.0), fit_row("B", "monkey", 1.0)])
    averaged = pd.concat([profile("A", 1.0, line, window), profile("B", 1.0, arc, window)])
    assert verdict("C10", both, averaged) == HOLDS


# ------------------------------------------------------------------- through snakemake


def test_table_rules_end_to_end(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")  # has no NOTICE.txt: no footer
    out = tmp_path / "out"
    names = ["fits.md", "fits.tex", "summary.csv", "summary.md", "summary.tex"]
    names += ["claims.csv", "claims.md"]
    targets = [str(out / "tables" / name) for name in names]
    process = run_snakemake(*targets, raw=raw, results=out)
    assert process.returncode == 0, process.stderr[-3000:]
    for name in names:
        assert (out / "tables" / name).is_file(), name
    for log in ("fit_tables.log", "claims_table.log"):
        assert (out / "logs" / log).is_file()
    claims = pd.read_csv(out / "tables" / "claims.csv")
    assert list(claims["claim"]) == [f"C{i}" for i in range(1, 11)]
    assert set(claims["verdict"]) <= set(VERDICTS)
    summary = pd.read_csv(out / "tables" / "summary.csv")
    assert list(zip(summary["species"], summary["n_trials"], strict=True)) == [
        ("monkey", 1),
        ("monkey", 1),
        ("human", 1),
    ]
    assert "Note" not in (out / "tables" / "claims.md").read_text()

    # with a notice: footer in Markdown and LaTeX, never in the CSV files
    notice = ["data_notice=Test data only"]
    rerun = ["--forcerun", "fit_tables", "claims_table"]
    process = run_snakemake(*targets, *rerun, raw=raw, results=out, config=notice)
    assert process.returncode == 0, process.stderr[-3000:]
    for name in ("claims.md", "fits.md", "summary.md"):
        assert (out / "tables" / name).read_text().rstrip().endswith("Test data only"), name
    assert r"\emph{Note.} Test data only" in (out / "tables" / "fits.tex").read_text()
    for name in ("claims.csv", "summary.csv"):
        assert "Test data only" not in (out / "tables" / name).read_text()

    # rebuilt from the same inputs, the tables are byte-identical
    before = {name: (out / "tables" / name).read_bytes() for name in names}
    again = run_snakemake(*targets, *rerun, raw=raw, results=out, config=notice)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "claims_table" in again.stderr and "fit_tables" in again.stderr  # really rerun
    assert {name: (out / "tables" / name).read_bytes() for name in names} == before
