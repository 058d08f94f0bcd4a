"""Membrane mechanics: the exact geometry from its identities, pre-tension, stiffness and
pre-strain recovered from forces made with known values, and forces.csv refused with one
line when it breaks the contract."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import refused_run, run_snakemake, write_small_dataset
from lineload import mechanics, models
from lineload.io import load_schema
from lineload.rawdata.validation import InputError, check_dataset, check_forces, read_forces
from lineload.simulation import synthetic

SCHEMAS = {name: load_schema(name) for name in ("subjects", "profiles", "outlines", "forces")}
DEPTHS_MM = np.array([0.5, 1.0, 1.5, 2.0])
L_MM = np.array([10.5, 11.5, 12.2, 12.6])


def forces_of(depth_mm, L_mm, pretension, stiffness, contact_mm=10.0):
    """F = 2 l (N0 + E eps) sin(theta0) with the exact arc (N)."""
    u, v = mechanics.force_terms(depth_mm, L_mm)
    return 2.0 * contact_mm * (pretension * u + stiffness * v)


# ------------------------------------------------------------------ exact geometry


def arc_points(depth_mm, L_mm, n=200_001):
    """Points along the exact arc from the load to the wall, by arc angle (z downward)."""
    g = models.arc_geometry(depth_mm, L_mm)
    cx, cz, R = (float(g[k]) for k in ("centre_x_mm", "centre_z_mm", "radius_mm"))
    start = math.atan2(-depth_mm - cz, -cx)
    end = math.atan2(0.0 - cz, L_mm - cx)
    angle = np.linspace(start, end, n)
    return cx + R * np.cos(angle), -(cz + R * np.sin(angle))


@pytest.mark.parametrize(("depth_mm", "L_mm"), [(0.5, 10.0), (2.0, 12.7), (2.0, 5.0), (1.0, 14.3)])
def test_stretch_is_arc_length_over_rest_length(depth_mm, L_mm):
    x, w = arc_points(depth_mm, L_mm)
    assert (x[0], w[0]) == pytest.approx((0.0, depth_mm), abs=1e-9)
    assert (x[-1], w[-1]) == pytest.approx((L_mm, 0.0), abs=1e-9)
    length = np.sum(np.hypot(np.diff(x), np.diff(w)))
    assert float(mechanics.arc_stretch(depth_mm, L_mm)) == pytest.approx(length / L_mm, rel=1e-9)


@pytest.mark.parametrize(("depth_mm", "L_mm"), [(0.5, 10.0), (2.0, 12.7), (2.0, 5.0)])
def test_load_angle_is_the_tangent_of_the_arc_at_the_load(depth_mm, L_mm):
    g = models.arc_geometry(depth_mm, L_mm)
    # the tangent is perpendicular to the radius through the load point (0, -W0)
    radius_x, radius_z = -float(g["centre_x_mm"]), -depth_mm - float(g["centre_z_mm"])
    expected = math.atan2(abs(radius_x), abs(radius_z))
    assert float(mechanics.arc_load_angle_rad(depth_mm, L_mm)) == pytest.approx(expected, rel=1e-12)
    # and the deflection curve itself leaves the load at that slope
    step = 1e-6
    slope = (models.arc_deflection_mm(step, depth_mm, L_mm) - depth_mm) / step
    assert math.atan(-float(slope)) == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize(("depth_mm", "L_mm"), [(0.5, 10.0), (2.0, 12.7), (2.0, 6.0)])
def test_strain_is_the_green_strain_of_eq_8_for_a_uniform_stretch(depth_mm, L_mm):
    """Map each material point X to the arc at arc length lambda X; eq. 8 at every X."""
    stretch = float(mechanics.arc_stretch(depth_mm, L_mm))
    x, w = arc_points(depth_mm, L_mm)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(w)))])
    X = s / stretch  # material coordinate of each arc point
    assert X[-1] == pytest.approx(L_mm, rel=1e-9)  # U = x - X = 0 at the wall: eq. 9a
    U, W = x - X, w
    dU, dW = np.gradient(U, X), np.gradient(W, X)
    green = dU + (dU**2 + dW**2) / 2.0  # eq. 8
    inner = slice(10, -10)
    assert green[inner] == pytest.approx(float(mechanics.arc_strain(depth_mm, L_mm)), rel=1e-6)
    # the engineering strain differs at second order
    assert (stretch - 1) - float(mechanics.arc_strain(depth_mm, L_mm)) == pytest.approx(
        -((stretch - 1) ** 2) / 2, rel=1e-9
    )


@pytest.mark.parametrize("ratio", [1e-3, 1e-2, 0.05])
def test_small_slope_limits(ratio):
    """theta0 = 4 delta (1 - 1.73 delta^2 + ...) against arctan(4 delta) = 4 delta (1 -
    5.33 delta^2 + ...): the angle differs at relative order delta^2, as does the strain."""
    L_mm = 12.0
    depth_mm = ratio * L_mm
    angle = float(mechanics.arc_load_angle_rad(depth_mm, L_mm))
    strain = float(mechanics.arc_strain(depth_mm, L_mm))
    angle_ratio = angle / float(models.waterbed_load_angle_rad(depth_mm, L_mm))
    strain_ratio = strain / float(models.waterbed_strain(depth_mm, L_mm))
    assert angle_ratio - 1 == pytest.approx(3.6 * ratio**2, rel=0.05)
    assert strain_ratio - 1 == pytest.approx(-1.2 * ratio**2, rel=0.05)


def test_small_slope_formulas_are_off_by_more_than_a_force_reading_at_2_mm():
    # the reason the exact arc supplies the geometry: at 2 mm, L = 12.7 mm
    exact = float(np.sin(mechanics.arc_load_angle_rad(2.0, 12.7)))
    small = float(np.sin(models.waterbed_load_angle_rad(2.0, 12.7)))
    assert exact / small - 1 > 0.05  # a 1 N force is read to 0.005 N (0.5 %)


def test_invalid_geometry_gives_nan():
    values = mechanics.arc_strain([1.0, -1.0, 1.0, np.nan], [10.0, 10.0, np.inf, 10.0])
    assert np.isfinite(values[0]) and np.isnan(values[1:]).all()
    assert np.isnan(mechanics.arc_load_angle_rad(1.0, 0.0))


# ------------------------------------------------------------------ the force fit


def test_noise_free_forces_give_back_n0_e_and_the_prestrain_exactly():
    pretension, stiffness, contact = 0.08, 0.25, 9.0
    force = forces_of(DEPTHS_MM, L_MM, pretension, stiffness, contact)
    fit = mechanics.fit_membrane(DEPTHS_MM, L_MM, force, force_sd_N=0.005)
    N0, _, E, _ = fit.per_length(contact)
    assert (N0, E) == pytest.approx((pretension, stiffness), rel=1e-9)
    assert fit.prestrain == pytest.approx(pretension / stiffness, rel=1e-9)
    assert fit.chi2 == pytest.approx(0.0, abs=1e-12) and fit.dof == 2
    assert fit.fitted_force_N == pytest.approx(list(force), rel=1e-12)


def test_recovery_from_noisy_forces_with_calibrated_errors():
    """Forces of a pre-tensioned membrane plus the stated noise: estimates unbiased within a
    few percent, and the reported standard errors match the spread over repeats."""
    pretension, stiffness, contact, sd = 0.08, 0.25, 9.0, 0.005
    rng = np.random.default_rng(11)
    true = forces_of(DEPTHS_MM, L_MM, pretension, stiffness, contact)
    draws = []
    for _ in range(400):
        fit = mechanics.fit_membrane(DEPTHS_MM, L_MM, true + rng.normal(0, sd, 4), sd)
        N0, N0_se, E, E_se = fit.per_length(contact)
        draws.append((N0, N0_se, E, E_se, fit.prestrain, fit.prestrain_se))
    N0, N0_se, E, E_se, p, p_se = np.array(draws).T
    assert np.mean(N0) == pytest.approx(pretension, rel=0.01)
    assert np.mean(E) == pytest.approx(stiffness, rel=0.03)
    assert np.median(p) == pytest.approx(pretension / stiffness, rel=0.03)
    assert np.std(N0) == pytest.approx(np.mean(N0_se), rel=0.15)
    assert np.std(E) == pytest.approx(np.mean(E_se), rel=0.15)
    assert np.std(p) == pytest.approx(np.median(p_se), rel=0.25)
    inside = np.abs(N0 - pretension) <= 1.96 * N0_se
    assert 0.9 <= inside.mean() <= 0.99


@pytest.mark.parametrize("prestrain", [0.0, 0.05, 0.3])
def test_small_slope_forces_at_small_slopes(prestrain):
    """Forces made with the paper's small-slope formulas, fitted with the exact arc, at
    small slopes (W0/L <= 0.05): N0, and E of a stress-free membrane, agree within a few
    percent.  With a tension at rest E does not: the small-slope angle is short by
    3.6 (W0/L)^2 = 1.8 eps of itself, so N0 sin(theta0) loses 1.8 N0 eps, which reads as
    E - 1.8 N0 at any slope.  Hence the exact geometry."""
    depth_mm = np.array([0.15, 0.3, 0.45, 0.6])
    L_mm = np.full(4, 12.0)
    stiffness, contact = 0.2, 10.0
    pretension = prestrain * stiffness
    theta = models.waterbed_load_angle_rad(depth_mm, L_mm)
    strain = models.waterbed_strain(depth_mm, L_mm)
    force = 2 * contact * (pretension + stiffness * strain) * np.sin(theta)
    fit = mechanics.fit_membrane(depth_mm, L_mm, force, force_sd_N=1e-4)
    N0, _, E, _ = fit.per_length(contact)
    assert N0 == pytest.approx(pretension, rel=0.03, abs=1e-4)
    assert E == pytest.approx(stiffness - 1.8 * pretension, rel=0.05)
    if prestrain == 0.0:
        assert E == pytest.approx(stiffness, rel=0.03)
    # the same forces made with the exact arc come back exactly
    exact = forces_of(depth_mm, L_mm, pretension, stiffness, contact)
    N0, _, E, _ = mechanics.fit_membrane(depth_mm, L_mm, exact, 1e-4).per_length(contact)
    assert (N0, E) == pytest.approx((pretension, stiffness), rel=1e-8, abs=1e-12)


def test_stress_free_special_case():
    stiffness, contact, sd = 0.3, 10.0, 0.002
    rng = np.random.default_rng(5)
    force = forces_of(DEPTHS_MM, L_MM, 0.0, stiffness, contact) + rng.normal(0, sd, 4)
    free = mechanics.fit_membrane(DEPTHS_MM, L_MM, force, sd, stress_free=True)
    assert free.tension_N == 0.0 and free.prestrain == 0.0 and free.dof == 3
    assert free.per_length(contact)[2] == pytest.approx(stiffness, rel=0.02)
    assert free.p_value > 0.01
    full = mechanics.fit_membrane(DEPTHS_MM, L_MM, force, sd)
    assert abs(full.prestrain) < 3 * full.prestrain_se
    # forces of a pre-tensioned membrane reject it
    tensioned = forces_of(DEPTHS_MM, L_MM, 0.05, stiffness, contact) + rng.normal(0, sd, 4)
    assert mechanics.fit_membrane(DEPTHS_MM, L_MM, tensioned, sd, stress_free=True).p_value < 1e-6


def test_uncertainty_of_L_widens_the_errors_and_the_fit_stays_put_without_noise():
    force = forces_of(DEPTHS_MM, L_MM, 0.08, 0.25)
    exact = mechanics.fit_membrane(DEPTHS_MM, L_MM, force, 0.005)
    loose = mechanics.fit_membrane(DEPTHS_MM, L_MM, force, 0.005, L_sd_mm=0.02 * L_MM)
    assert loose.prestrain == pytest.approx(exact.prestrain, rel=1e-9)
    assert loose.prestrain_se > 2 * exact.prestrain_se
    assert min(loose.force_variance_N2) > 0.005**2


def test_fit_refuses_what_it_cannot_fit():
    with pytest.raises(ValueError, match="at least 2"):
        mechanics.fit_membrane([1.0], [12.0], [0.5], 0.005)
    with pytest.raises(ValueError, match="finite"):
        mechanics.fit_membrane([1.0, 2.0], [12.0, np.nan], [0.5, 1.0], 0.005)
    with pytest.raises(ValueError, match="force_sd_N"):
        mechanics.fit_membrane([1.0, 2.0], [12.0, 12.0], [0.5, 1.0], 0.0)


# ------------------------------------------------------------------ ratios and C11's numbers


def test_reconciling_prestrain_brings_the_ratio_exactly_to_the_bound():
    small = tuple(float(t) for t in mechanics.force_terms(0.5, 10.1))
    large = tuple(float(t) for t in mechanics.force_terms(2.0, 12.1))
    allowed = mechanics.allowed_force_ratio()
    assert allowed == pytest.approx(1.0 / 0.3)
    p = mechanics.reconciling_prestrain(small, large, allowed)
    assert 0 < p < math.inf
    ratio = (large[1] + p * large[0]) / (small[1] + p * small[0])
    assert ratio == pytest.approx(allowed, rel=1e-12)
    # stress-free already within: none needed; tension alone beyond: none can
    assert mechanics.reconciling_prestrain(small, large, 100.0) == 0.0
    assert mechanics.reconciling_prestrain(small, large, 2.0) == math.inf


def test_ratio_check_orders_its_bounds_and_grows_about_as_depth_cubed():
    check = mechanics.ratio_check(0.05, (12.0, 11.5, 12.5), 0.2, (12.0, 11.5, 12.5), 10 / 3)
    assert check["stress_free_low"] < check["stress_free"] < check["stress_free_high"]
    assert check["stress_free"] == pytest.approx(4.0**3, rel=0.01)  # (W0/L)^3
    assert check["tension_only"] == pytest.approx(4.0, rel=0.01)  # W0/L
    # the bounds are the ratio at the interval ends that favour and disfavour it
    assert check["stress_free_low"] == pytest.approx(64 * (11.5 / 12.5) ** 3, rel=0.01)
    open_interval = mechanics.ratio_check(0.5, (12.0, 11.5, 12.5), 2.0, (12.0, 11.5, np.inf), 3)
    assert open_interval["stress_free_low"] == 0.0


# ------------------------------------------------------------------ the tables


def fit_table(rows):
    """A fit table with the exact-arc columns: rows of (subject, species, depth, L)."""
    return pd.DataFrame(
        [
            {
                "subject": s,
                "species": sp,
                "depth_mm": d,
                "arc_L_mm": L,
                "arc_L_ci_low_mm": L - 0.2,
                "arc_L_ci_high_mm": L + 0.2,
            }
            for s, sp, d, L in rows
        ]
    )


TRIALS = [("MK", "monkey", d, L) for d, L in zip(DEPTHS_MM, L_MM, strict=True)] + [
    ("HU", "human", 1.0, 14.0),
    ("HU", "human", 2.0, 14.2),
    ("ONE", "human", 1.0, 14.0),
]


def test_tables_with_and_without_contact_lengths():
    fits = fit_table(TRIALS)
    force = forces_of(fits["depth_mm"], fits["arc_L_mm"], 0.07, 0.2)
    forces = fits[["subject", "depth_mm"]].assign(force_N=force)
    subjects, trials = mechanics.mechanics_tables(fits, forces, {"MK": 10.0, "HU": 10.0}, 0.005)
    assert list(subjects.columns) == mechanics.SUBJECT_COLUMNS
    assert list(trials.columns) == mechanics.TRIAL_COLUMNS
    assert list(subjects["subject"]) == ["MK", "HU"]  # ONE has a single depth
    assert list(subjects["n_depths"]) == [4, 2]
    assert subjects["pretension_N_per_mm"].to_numpy() == pytest.approx([0.07, 0.07])
    assert subjects["stiffness_N_per_mm"].to_numpy() == pytest.approx([0.2, 0.2])
    assert subjects["prestrain"].to_numpy() == pytest.approx([0.35, 0.35])
    assert list(subjects["dof"]) == [2, 0]
    assert (trials["waterbed_variant"] == "arc").all()
    mk = trials[trials["subject"] == "MK"]
    assert mk["fitted_force_N"].to_numpy() == pytest.approx(mk["force_N"].to_numpy())
    assert mk["stress_free_force_N"].iloc[0] == pytest.approx(mk["force_N"].iloc[0])
    assert mk["membrane_force_N_per_mm"].to_numpy() == pytest.approx(
        0.07 + 0.2 * mk["strain"].to_numpy()
    )
    # without contact lengths: N0 and E unknown, the pre-strain the same
    bare, bare_trials = mechanics.mechanics_tables(fits, forces, None, 0.005)
    assert bare[["pretension_N_per_mm", "stiffness_N_per_mm"]].isna().all().all()
    assert bare["prestrain"].to_numpy() == pytest.approx(subjects["prestrain"].to_numpy())
    assert bare_trials["force_per_length_N_per_mm"].isna().all()
    # without forces: the geometry per trial, no subject rows
    none, geometry = mechanics.mechanics_tables(fits)
    assert none.empty and len(geometry) == len(fits)
    assert geometry["force_N"].isna().all() and geometry["strain"].notna().all()


# ------------------------------------------------------------------ the shipped reconstruction


def test_generator_forces_come_from_its_pre_tensioned_membrane():
    for subject in synthetic.shipped_subjects():
        rows = synthetic.trial_forces(subject)
        depth = np.array([r["depth_mm"] for r in rows])
        L_mm = np.array([r["L_mm"] for r in rows])
        true = np.array([r["true_force_N"] for r in rows])
        expected = forces_of(
            depth,
            L_mm,
            subject.pretension_N_per_mm,
            subject.stiffness_N_per_mm,
            subject.contact_length_mm,
        )
        assert true == pytest.approx(expected, rel=1e-12)
        read = np.array([r["force_N"] for r in rows])
        assert np.all(np.abs(read - true) <= 5 * synthetic.FORCE_NOISE_SD_N + 0.0005)
        # at the generator's own L the fit recovers its membrane within the errors
        fit = mechanics.fit_membrane(depth, L_mm, read, synthetic.FORCE_NOISE_SD_N)
        N0, N0_se, _, _ = fit.per_length(subject.contact_length_mm)
        assert abs(N0 - subject.pretension_N_per_mm) < 4 * N0_se, subject.subject
        assert abs(fit.prestrain - subject.prestrain) < 4 * fit.prestrain_se, subject.subject
        # forces stay near the paper's 0.3-1 N: the deepest at most 1 N
        assert 0.2 < read.min() and read.max() <= 1.0


def test_shipped_forces_and_contact_lengths_pass_the_contract():
    raw = Path(__file__).resolve().parents[1] / "data" / "raw"
    dataset = check_dataset(str(raw), SCHEMAS)
    assert (dataset["subjects"]["contact_length_mm"] > 0).all()
    forces = read_forces(raw / "forces.csv")
    assert len(forces) == 26 and (forces["force_N"] > 0).all()


# ------------------------------------------------------------------ forces.csv contract


def write_forces(raw, lines):
    (raw / "forces.csv").write_text("\n".join(lines) + "\n")


GOOD = ["subject,depth_mm,force_N", "MK,1,0.41", "MK,2,0.93", "HU,1,0.35"]


def bad_forces(kind):
    """(lines of forces.csv, line reported, columns named, words in the message)."""
    cases = {
        "zero_force": ([*GOOD[:2], "MK,2,0", GOOD[3]], 3, ("force_N",), ("> 0", "'0'")),
        "negative_force": ([*GOOD[:3], "HU,1,-0.2"], 4, ("force_N",), ("> 0",)),
        "text_force": ([*GOOD[:2], "MK,2,heavy", GOOD[3]], 3, ("force_N",), ("number", "heavy")),
        "empty_force": ([*GOOD[:3], "HU,1,"], 4, ("force_N",), ("empty",)),
        "unknown_subject": ([*GOOD, "ZZ,1,0.4"], 5, ("subject",), ("'ZZ'", "subjects.csv")),
        "depth_without_profile": ([*GOOD, "HU,2,0.9"], 5, ("depth_mm",), ("profile", "2 mm")),
        "duplicate_force": ([*GOOD, "MK,1.0,0.42"], 5, ("subject", "depth_mm"), ("line 2",)),
        "missing_column": (["subject,depth_mm", "MK,1"], 1, ("force_N",), ("missing",)),
        "header_only": (GOOD[:1], None, (), ("no data rows",)),
        "empty_file": ([""], None, (), ("empty",)),
        "unsafe_subject": ([*GOOD, "../x,1,0.4"], 5, ("subject",), ("letters",)),
        "force_in_millinewtons": (
            [*GOOD[:2], "MK,2,930", GOOD[3]],
            3,
            ("force_N",),
            ("at most 20 N", "force_max_N", "millinewtons"),
        ),
        "force_beyond_any_unit": ([*GOOD[:3], "HU,1,1e300"], 4, ("force_N",), ("newtons",)),
    }
    return cases[kind]


FORCE_CASES = [
    "zero_force",
    "negative_force",
    "text_force",
    "empty_force",
    "unknown_subject",
    "depth_without_profile",
    "duplicate_force",
    "missing_column",
    "header_only",
    "empty_file",
    "unsafe_subject",
    "force_in_millinewtons",
    "force_beyond_any_unit",
]


def reported_line(message):
    found = re.search(r"\bline (\d+)\b", message)
    return int(found.group(1)) if found else None


def check_message(message, raw_shown, file, line, columns, words):
    assert "\n" not in message
    assert message.startswith(f"{raw_shown}/{file}"), message
    assert reported_line(message) == line, message
    if len(columns) == 1:
        assert f"column '{columns[0]}'" in message, message
    for column in columns:
        assert column in message, message
    for word in words:
        assert word in message, message


def test_clean_forces_pass_and_come_back_typed(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    write_forces(raw, GOOD)
    dataset = check_dataset(str(raw), SCHEMAS)
    forces = check_forces(str(raw), SCHEMAS["forces"], dataset["subjects"], dataset["depths_mm"])
    assert list(forces["force_N"]) == [0.41, 0.93, 0.35]
    assert read_forces(raw / "forces.csv")["subject"].tolist() == ["MK", "MK", "HU"]
    (raw / "forces.csv").unlink()
    assert check_forces(str(raw), SCHEMAS["forces"], dataset["subjects"], {}) is None


@pytest.mark.parametrize("kind", FORCE_CASES)
def test_each_kind_of_bad_forces_file_is_one_input_error(kind, tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    lines, line, columns, words = bad_forces(kind)
    write_forces(raw, lines)
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS, raw_dir_shown="RAW")
    check_message(str(caught.value), "RAW", "forces.csv", line, columns, words)


@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("0", ("> 0",)),
        ("-3", ("> 0",)),
        ("wide", ("> 0",)),
        ("", ("> 0",)),
        ("9500", ("reach_max_mm", "micrometres")),
        ("1e300", ("reach_max_mm", "fingertip")),
    ],
)
def test_bad_contact_length_is_refused(tmp_path, value, words):
    raw = write_small_dataset(tmp_path / "raw")
    sheet = (raw / "subjects.csv").read_text().splitlines()
    sheet[0] += ",contact_length_mm"
    sheet[1] += ",9.5"
    sheet[2] += f",{value}"
    (raw / "subjects.csv").write_text("\n".join(sheet) + "\n")
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS, raw_dir_shown="RAW")
    check_message(str(caught.value), "RAW", "subjects.csv", 3, ("contact_length_mm",), words)


# ------------------------------------------------------------------ through snakemake


#: Through a real run, one case of each kind of rule (a cell, a row against the profiles,
#: a row against the sheet); every case's message: the in-process test above.
FORCE_CASES_END_TO_END = ("text_force", "depth_without_profile", "unknown_subject")


@pytest.mark.e2e
@pytest.mark.parametrize("kind", FORCE_CASES_END_TO_END)
def test_bad_forces_file_stops_the_build_with_one_line(kind, tmp_path, snakemake_available):
    raw = write_small_dataset(tmp_path / "raw")
    lines, line, columns, words = bad_forces(kind)
    write_forces(raw, lines)
    _, output, errors = refused_run(raw, tmp_path / "out")
    assert len(errors) == 1, output
    check_message(errors[0][len("Error: ") :], str(raw), "forces.csv", line, columns, words)


@pytest.mark.e2e
def test_mechanics_tables_and_c11_with_and_without_forces(tmp_path, snakemake_available):
    raw = write_small_dataset(
        tmp_path / "raw", subjects={"MK": ("monkey", [1.0, 2.0], 5.0), "HU": ("human", [1.0], 9.0)}
    )
    out = tmp_path / "out"
    targets = [str(out / "tables" / n) for n in ("mechanics.csv", "mechanics_trials.csv")]
    targets.append(str(out / "tables" / "claims.csv"))
    process = run_snakemake(*targets, raw=str(raw), results=str(out))
    assert process.returncode == 0, process.stderr[-3000:]
    assert pd.read_csv(out / "tables" / "mechanics.csv").empty
    trials = pd.read_csv(out / "tables" / "mechanics_trials.csv")
    assert len(trials) == 3 and trials["force_N"].isna().all()
    claims = pd.read_csv(out / "tables" / "claims.csv").set_index("claim")
    assert "forces of forces.csv" not in claims.loc["C11", "our_value"]
    # adding forces (no contact lengths) reruns the mechanics and the claims
    write_forces(raw, GOOD)
    process = run_snakemake(*targets, raw=str(raw), results=str(out))
    assert process.returncode == 0, process.stderr[-3000:]
    table = pd.read_csv(out / "tables" / "mechanics.csv")
    assert list(table["subject"]) == ["MK"]
    assert table["prestrain"].notna().all() and table["pretension_N_per_mm"].isna().all()
    claims = pd.read_csv(out / "tables" / "claims.csv").set_index("claim")
    assert "forces of forces.csv, 1 subject" in claims.loc["C11", "our_value"]


@pytest.mark.e2e
def test_shipped_data_recover_the_generators_membranes(shipped_build):
    out = shipped_build[1]
    table = pd.read_csv(out / "tables" / "mechanics.csv", dtype={"subject": str})
    truth = {s.subject: s for s in synthetic.shipped_subjects()}
    assert list(table["subject"]) == list(truth)  # a row per subject, sheet order
    for row in table.itertuples():
        true = truth[row.subject]
        assert row.n_depths == len(true.depths_mm)
        assert row.contact_length_mm == true.contact_length_mm
        N0_z = (row.pretension_N_per_mm - true.pretension_N_per_mm) / row.pretension_se_N_per_mm
        assert abs(N0_z) < 3, row.subject
        assert abs(row.prestrain - true.prestrain) < 2 * row.prestrain_se, row.subject
        assert abs(row.stiffness_N_per_mm - true.stiffness_N_per_mm) < 3 * row.stiffness_se_N_per_mm
        assert row.stress_free_p_value < 1e-6  # built in: the forces come from a tension
    claims = pd.read_csv(out / "tables" / "claims.csv").set_index("claim")
    assert claims.loc["C11", "verdict"] == "does not hold"
    assert "stress-free rejected in 7 of 7" in claims.loc["C11", "our_value"]
    # H1 keeps nearly one L at every depth: even tension alone exceeds the paper's ratio
    assert re.search(r"H1 \d+\.\d / none", claims.loc["C11", "our_value"])


def test_a_broken_profile_is_one_line_not_more_about_its_forces(tmp_path):
    # MK's 2 mm rows have a depth no one can read: its forces at 2 mm are not
    # "at a depth without a profile" as well (the lines would all be one mistake)
    raw = write_small_dataset(tmp_path / "raw")
    write_forces(raw, GOOD)
    path = raw / "profiles" / "MK.csv"
    lines = path.read_text().splitlines()
    path.write_text("\n".join("two" + t[1:] if t.startswith("2,") else t for t in lines) + "\n")
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS, raw_dir_shown="RAW")
    assert len(caught.value.problems) == 1, caught.value.problems
    assert caught.value.problems[0].startswith("RAW/profiles/MK.csv")
    # nor when the profile file is missing altogether: one line, about the file
    path.rename(path.with_suffix(".bak"))
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS, raw_dir_shown="RAW")
    assert len(caught.value.problems) == 1, caught.value.problems
    assert "no profile file for subject 'MK'" in caught.value.problems[0]
    path.with_suffix(".bak").rename(path)
    # a force at a depth the (sound) profile lacks is still refused
    write_forces(raw, [*GOOD, "HU,2,0.9"])
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS, raw_dir_shown="RAW")
    assert [p.split(",")[0] for p in caught.value.problems] == ["RAW/forces.csv"]
