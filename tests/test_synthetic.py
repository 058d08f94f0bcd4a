"""The synthetic reconstruction: reproducible, faithful to the study's numbers, and honest.

Thresholds come from the specification of the dataset (the paper's numbers and
the digitising noise), never from numbers the generator printed.
"""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from lineload.fitting import batch as fitting
from lineload.simulation import synthetic

ROOT = Path(__file__).resolve().parents[1]
RAW = ROOT / "data" / "raw"
SCRIPT = ROOT / "workflow" / "scripts" / "make_synthetic_data.py"
README = ROOT / "data" / "README.md"

MAG = synthetic.MAGNIFICATION
NOISE = synthetic.NOISE_SD_MM
EXTENT_RANGE_MM = {"monkey": (3.0, 7.0), "human": (6.0, 12.0)}
ALL_DEPTHS = {0.5, 1.0, 1.5, 2.0}


def files_under(folder):
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def shipped_trials():
    return [
        (s, synthetic.trial_parameters(s, d))
        for s in synthetic.shipped_subjects()
        for d in s.depths_mm
    ]


@pytest.fixture(scope="module")
def subjects():
    return pd.read_csv(RAW / "subjects.csv", dtype={"subject": str})


@pytest.fixture(scope="module")
def readings(subjects):
    """All shipped readings in tissue mm, one frame."""
    frames = []
    for row in subjects.itertuples():
        table = pd.read_csv(RAW / "profiles" / f"{row.subject}.csv")
        table["subject"], table["species"] = row.subject, row.species
        table["distance_mm"] = table["distance_image_mm"] / row.magnification
        table["deflection_mm"] = table["deflection_image_mm"] / row.magnification
        frames.append(table)
    return pd.concat(frames, ignore_index=True)


# --- reproducibility -------------------------------------------------------------------------


def test_cli_rebuilds_shipped_data_byte_for_byte(tmp_path):
    out = tmp_path / "raw"
    subprocess.run(
        [sys.executable, str(SCRIPT), "--out", str(out)], check=True, capture_output=True
    )
    shipped, rebuilt = files_under(RAW), files_under(out)
    assert sorted(rebuilt) == sorted(shipped)
    for name, content in shipped.items():
        assert rebuilt[name] == content, f"{name} differs from the regenerated file"


def test_files_use_fixed_format_and_unix_newlines():
    for name, content in files_under(RAW).items():
        text = content.decode("utf-8")
        assert "\r" not in text and text.endswith("\n"), name
        assert "nan" not in text.lower() and "-0.0," not in text and not text.count("e-"), name


def test_scale_datasets_have_no_forces_and_shipped_ones_do():
    scale = synthetic.build_dataset(n_monkeys=2, n_humans=1)
    assert "forces.csv" not in scale
    assert "contact_length_mm" not in scale["subjects.csv"].splitlines()[0]
    shipped = synthetic.build_dataset()
    assert shipped["forces.csv"].splitlines()[0] == "subject,depth_mm,force_N"
    assert shipped["subjects.csv"].splitlines()[0].endswith(",contact_length_mm")


def test_subject_stream_does_not_depend_on_dataset_size():
    small = synthetic.build_dataset(n_monkeys=2, n_humans=1)
    large = synthetic.build_dataset(n_monkeys=6, n_humans=4)
    for name in ("profiles/M1.csv", "profiles/M2.csv", "profiles/H1.csv", "outlines/H1.csv"):
        assert small[name] == large[name]
    assert (
        synthetic.build_dataset(seed=7, n_monkeys=2, n_humans=1)["profiles/M1.csv"]
        != small["profiles/M1.csv"]
    )


def test_shuffle_changes_order_only():
    plain = synthetic.build_dataset(n_monkeys=1, n_humans=1)
    shuffled = synthetic.build_dataset(n_monkeys=1, n_humans=1, shuffle=True)
    for name in ("profiles/M1.csv", "profiles/H1.csv"):
        a, b = plain[name].splitlines(), shuffled[name].splitlines()
        assert a[0] == b[0] and a != b and sorted(a[1:]) == sorted(b[1:])


def test_scale_mode_cli(tmp_path):
    subprocess.run(
        [sys.executable, str(SCRIPT), "--out", str(tmp_path), "--monkeys", "3", "--humans", "2"],
        check=True,
        capture_output=True,
    )
    sheet = pd.read_csv(tmp_path / "subjects.csv")
    assert list(sheet["subject"]) == ["M1", "M2", "M3", "H1", "H2"]
    assert {p.stem for p in (tmp_path / "profiles").glob("*.csv")} == set(sheet["subject"])
    files = synthetic.build_dataset(n_monkeys=40, n_humans=35)
    assert sum(name.startswith("profiles/") for name in files) == 75


def test_cli_refuses_stale_profiles(tmp_path):
    stale = tmp_path / "profiles" / "OLD.csv"
    stale.parent.mkdir(parents=True)
    stale.write_text("x\n")
    run = subprocess.run(
        [sys.executable, str(SCRIPT), "--out", str(tmp_path)], capture_output=True, text=True
    )
    assert run.returncode != 0 and "OLD.csv" in run.stderr
    subprocess.run(
        [sys.executable, str(SCRIPT), "--out", str(tmp_path), "--clean"],
        check=True,
        capture_output=True,
    )
    assert not stale.exists()


# --- the true profile ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("subject", "trial"),
    shipped_trials(),
    ids=lambda v: getattr(v, "subject", None) or f"{v.depth_mm:g}mm",
)
def test_true_profile_shape(subject, trial):
    for side in ("left", "right"):
        extent = trial.extent_mm(side)
        x = np.linspace(0.0, extent, 4001)
        w = synthetic.true_deflection_mm(
            x, trial.depth_mm, extent, trial.exponent, trial.near_fraction, trial.near_exponent
        )
        assert w[0] == pytest.approx(trial.depth_mm, abs=1e-12)
        assert w[-1] == pytest.approx(0.0, abs=1e-12)
        assert np.all(np.diff(w) < 0), "not strictly decreasing"
        beyond = synthetic.true_deflection_mm(
            extent + np.array([0.1, 1.0, 5.0]),
            trial.depth_mm,
            extent,
            trial.exponent,
            trial.near_fraction,
        )
        assert np.all(beyond == 0.0), "no bulge, no lift beyond the edge"
        # meets the resting surface smoothly (no kink at the edge)
        assert trial.exponent > 1
    assert trial.extent_left_mm != trial.extent_right_mm


@pytest.mark.parametrize(
    ("subject", "trial"),
    shipped_trials(),
    ids=lambda v: getattr(v, "subject", None) or f"{v.depth_mm:g}mm",
)
def test_true_profile_is_neither_fitted_model(subject, trial):
    for side in ("left", "right"):
        x = synthetic.reading_distances_mm(trial.extent_mm(side))
        w = synthetic.true_deflection_mm(
            x,
            trial.depth_mm,
            trial.extent_mm(side),
            trial.exponent,
            trial.near_fraction,
            trial.near_exponent,
        )
        # not the same function: the best fit of either family misses somewhere
        for fit in (fitting.fit_waterbed(x, w, trial.depth_mm), fitting.fit_boussinesq(x, w)):
            assert fit.max_abs_residual_mm > 1e-3 * trial.depth_mm, fit.model
        # and at the deepest indentation the miss within 3 mm is far above the noise
        if trial.depth_mm == max(subject.depths_mm):
            near = x <= 3.0
            for fit in (
                fitting.fit_waterbed(x[near], w[near], trial.depth_mm),
                fitting.fit_boussinesq(x[near], w[near]),
            ):
                assert fit.max_abs_residual_mm > 5 * NOISE, fit.model


def test_sides_differ_by_a_few_percent():
    for subject, trial in shipped_trials():
        x = np.linspace(0.0, max(trial.extent_left_mm, trial.extent_right_mm), 2001)
        left, right = (
            synthetic.true_deflection_mm(
                x, trial.depth_mm, trial.extent_mm(side), trial.exponent, trial.near_fraction
            )
            for side in ("left", "right")
        )
        gap = np.max(np.abs(left - right)) / trial.depth_mm
        assert 0.005 < gap < 0.10, (subject.subject, trial.depth_mm, gap)


# --- the shipped files -----------------------------------------------------------------------


def test_subject_sheet(subjects):
    assert list(subjects.columns[:3]) == ["subject", "species", "magnification"]
    assert "label" in subjects.columns
    assert subjects["subject"].str.fullmatch(r"[A-Za-z0-9_-]+").all()
    assert subjects["subject"].is_unique
    assert (subjects["species"] == "monkey").sum() == 4
    assert (subjects["species"] == "human").sum() == 3
    assert (subjects["magnification"] == 20).all()
    for row in subjects.itertuples():
        assert (RAW / "profiles" / f"{row.subject}.csv").is_file()


def test_trials_and_depths(readings):
    depths = readings.groupby("subject")["depth_mm"].agg(lambda d: set(d.round(6)))
    assert sum(len(d) for d in depths) == 26
    assert depths["H3"] == {1.0, 2.0}
    for subject in ("M1", "M2", "M3", "M4", "H1", "H2"):
        assert depths[subject] == ALL_DEPTHS
    assert (readings.groupby(["subject", "depth_mm"])["side"].nunique() == 2).all()


def test_values_are_valid(readings):
    assert readings[["depth_mm", "distance_image_mm", "deflection_image_mm"]].notna().all().all()
    assert (readings["depth_mm"] > 0).all()
    assert (readings["distance_image_mm"] >= 0).all()
    assert set(readings["side"]) == {"left", "right"}
    assert not readings.duplicated(["subject", "depth_mm", "side", "distance_image_mm"]).any()
    # no reading lies above the depth by more than the digitising error allows
    assert (readings["deflection_mm"] <= readings["depth_mm"] + 5 * NOISE).all()
    # readings are on the 0.1 mm resolution of the enlargement
    for column in ("distance_image_mm", "deflection_image_mm"):
        tenths = readings[column] / synthetic.IMAGE_RESOLUTION_MM
        assert np.allclose(tenths, np.round(tenths), atol=1e-6)


def test_reading_grid(readings):
    first_seen, last_seen = set(), []
    for (subject, species, depth, side), g in readings.groupby(
        ["subject", "species", "depth_mm", "side"]
    ):
        x = np.sort(g["distance_mm"].to_numpy())
        first_seen.add(round(x[0], 6))
        assert 0.05 - 1e-9 <= x[0] <= 0.1 + 1e-9
        lo, hi = EXTENT_RANGE_MM[species]
        assert lo <= x[-1] <= hi, (subject, depth, side, x[-1])
        # at the edge the reading is the registration error alone (a few hundredths of a mm)
        assert abs(g.loc[g["distance_mm"].idxmax(), "deflection_mm"]) < 0.05
        steps = np.diff(x)
        inner_ends = x[1:-1]  # the step into each reading but the edge
        expected = np.where(
            inner_ends <= 0.5 + 1e-9, 0.05, np.where(inner_ends <= 3.0 + 1e-9, 0.25, 0.5)
        )
        assert np.allclose(steps[:-1], expected, atol=1e-9), (subject, depth, side)
        assert 0 < steps[-1] <= 0.5 + 1e-9
        last_seen.append((subject, depth, side, x[-1]))
    assert first_seen == {0.05, 0.1}, "both glare limits should occur"
    lasts = pd.DataFrame(last_seen, columns=["subject", "depth", "side", "last"])
    firsts = readings.groupby(["subject", "depth_mm", "side"])["distance_mm"].min().unstack()
    assert (firsts["left"] != firsts["right"]).any(), "sides never start differently"
    per_trial = lasts.pivot_table(index=["subject", "depth"], columns="side", values="last")
    assert (per_trial["left"] != per_trial["right"]).all(), "each side has its own edge"


def side_readings(readings, subject, depth_mm, side):
    """Distances and deflections (tissue mm) of one side of one trial, edge left out."""
    rows = readings[
        (readings["subject"] == subject.subject)
        & (readings["depth_mm"] == depth_mm)
        & (readings["side"] == side)
    ]
    x = rows["distance_mm"].round(6).to_numpy()
    return x[:-1], rows["deflection_mm"].to_numpy()[:-1]


def reading_errors(readings):
    """Each side's own errors: reading minus what the truth and the trial's shared errors give.

    One array per side of a trial (the edge, which carries no reading error, left out).
    """
    errors = []
    for subject in synthetic.shipped_subjects():
        registration = synthetic.registration_error_mm(subject)
        shared = synthetic.trial_errors(subject)
        for depth_mm in subject.depths_mm:
            trial = synthetic.trial_parameters(subject, depth_mm)
            offset, tilt = registration[float(depth_mm)]
            for side in ("left", "right"):
                x, read = side_readings(readings, subject, depth_mm, side)
                true = synthetic.true_reading_mm(x, trial, side, shared[float(depth_mm)])
                signed = -x if side == "left" else x
                errors.append(read - true - offset - tilt * signed)
    return errors


def test_reading_errors_are_symmetric_not_clipped_and_of_the_stated_size(readings):
    errors = reading_errors(readings)
    every = np.concatenate(errors)
    rounding = synthetic.IMAGE_RESOLUTION_MM / MAG
    # each side: independent reading error, tracing error and an offset of its trace,
    # then rounded to 0.005 mm of tissue (0.1 mm on the enlargement)
    sd = math.sqrt(
        NOISE**2 + synthetic.TRACING_SD_MM**2 + synthetic.SIDE_OFFSET_SD_MM**2 + rounding**2 / 12
    )
    assert np.all(np.abs(every) <= 6 * sd)
    # the mean of a trace's errors varies by its offset and its tracing error (the latter
    # correlated over a fraction of the trace): bound the grand mean by the traces' spread
    trace_means = np.array([e.mean() for e in errors])
    assert abs(trace_means.mean()) < 4 * trace_means.std(ddof=1) / math.sqrt(trace_means.size)
    # 52 traces of correlated errors: the SD of all errors agrees with the stated size
    # within the spread a handful of independent draws per trace leaves (20 %)
    assert np.std(every) == pytest.approx(sd, rel=0.2)
    # where the skin barely moves, readings fall on both sides of zero
    assert (readings["deflection_mm"] < 0).sum() > 10


def test_reading_errors_are_correlated_along_a_trace(readings):
    # neighbours 0.05 mm apart share the tracing error: their errors correlate; readings
    # of different traces do not
    errors = reading_errors(readings)
    pairs = np.concatenate([np.column_stack([e[:9], e[1:10]]) for e in errors if e.size > 10])
    within = np.corrcoef(pairs.T)[0, 1]
    shuffled = np.corrcoef(pairs[:, 0], np.roll(pairs[:, 1], 10))[0, 1]
    expected = (
        synthetic.TRACING_SD_MM**2 * math.exp(-0.05 / synthetic.TRACING_LENGTH_MM)
        + synthetic.SIDE_OFFSET_SD_MM**2
    ) / (NOISE**2 + synthetic.TRACING_SD_MM**2 + synthetic.SIDE_OFFSET_SD_MM**2)
    assert within > 0.5 * expected
    assert abs(shuffled) < within / 2


def test_registration_error_is_shared_by_a_trace_and_cancels_its_tilt(readings):
    # at distances read on both sides, the left/right mean minus the truth (with the
    # trial's shared errors) is the trial's offset (the tilt cancels) up to the sides' own
    # errors; half the difference grows with distance as the tilt does
    rounding = synthetic.IMAGE_RESOLUTION_MM / MAG
    own_sd = math.hypot(NOISE, rounding)
    n_checked = 0
    for subject in synthetic.shipped_subjects():
        registration = synthetic.registration_error_mm(subject)
        shared = synthetic.trial_errors(subject)
        offsets = np.array([o for o, _ in registration.values()])
        assert np.unique(offsets).size == offsets.size  # one draw per trial
        for depth_mm, (offset, tilt) in registration.items():
            trial = synthetic.trial_parameters(subject, depth_mm)
            sides = {}
            for side in ("left", "right"):
                x, read = side_readings(readings, subject, depth_mm, side)
                true = synthetic.true_reading_mm(x, trial, side, shared[float(depth_mm)])
                sides[side] = dict(zip(x, read - true, strict=True))
            common = sorted(set(sides["left"]) & set(sides["right"]) - {0.0})
            left = np.array([sides["left"][x] for x in common])
            right = np.array([sides["right"][x] for x in common])
            # the mean of n points: independent part over n, tracing and side offsets whole
            sd = math.sqrt(
                own_sd**2 / (2 * len(common))
                + (synthetic.TRACING_SD_MM**2 + synthetic.SIDE_OFFSET_SD_MM**2) / 2
            )
            assert np.mean((left + right) / 2) == pytest.approx(offset, abs=4 * sd)
            half_difference = (right - left) / 2  # = tilt * x + the sides' own errors
            slope = np.polyfit(np.array(common), half_difference, 1)[0]
            spread = 4 * math.hypot(own_sd, synthetic.TRACING_SD_MM) / np.ptp(common)
            assert slope == pytest.approx(tilt, abs=spread)
            n_checked += 1
    assert n_checked == 26


def test_deformed_region_wider_in_humans(readings):
    edge = readings.groupby(["species", "depth_mm", "subject"])["distance_mm"].max()
    for depth in ALL_DEPTHS:
        assert edge["human"][depth].min() > edge["monkey"][depth].max()
    # and it grows with depth for every finger
    for subject, by_depth in readings.groupby("subject"):
        edges = by_depth.groupby("depth_mm")["distance_mm"].max().to_numpy()
        assert np.all(np.diff(edges) > 0), subject


def test_outlines():
    assert sorted(p.name for p in (RAW / "outlines").glob("*.csv")) == ["H1.csv", "M1.csv"]
    radius = {}
    for name in ("M1", "H1"):
        table = pd.read_csv(RAW / "outlines" / f"{name}.csv")
        assert set(table["state"]) == {"resting", "deformed"}
        assert set(table["depth_mm"]) == {1.0, 2.0}
        for depth, g in table.groupby("depth_mm"):
            rest = g[g["state"] == "resting"].sort_values("x_image_mm")
            bent = g[g["state"] == "deformed"].sort_values("x_image_mm")
            assert np.array_equal(rest["x_image_mm"].to_numpy(), bent["x_image_mm"].to_numpy())
            x = rest["x_image_mm"].to_numpy() / MAG
            assert np.allclose(np.diff(x), 0.1, atol=1e-9)
            at_wedge = np.flatnonzero(np.isclose(x, 0.0))
            assert rest["z_image_mm"].to_numpy()[at_wedge] == 0.0
            assert bent["z_image_mm"].to_numpy()[at_wedge] / MAG == pytest.approx(-depth)
            drop = (rest["z_image_mm"].to_numpy() - bent["z_image_mm"].to_numpy()) / MAG
            assert np.all(drop >= -1e-9) and drop.max() == pytest.approx(depth)
            assert drop[0] == 0.0 and drop[-1] == 0.0, "outline ends outside the deformed region"
            # circle through the top: x^2 + z^2 + 2 z R = 0, from the outermost point
            z = rest["z_image_mm"].to_numpy() / MAG
            radius[name] = -(x[0] ** 2 + z[0] ** 2) / (2 * z[0])
    assert 6.0 <= radius["M1"] <= 9.0, "monkey 1 should be markedly curved at rest"
    assert radius["H1"] >= 40.0, "human 1 should be nearly flat at rest"


def test_shipped_data_pass_the_contract(subjects):
    validation = pytest.importorskip("lineload.rawdata.validation")
    io = pytest.importorskip("lineload.io")
    sheet = validation.read_table(RAW / "subjects.csv", io.load_schema("subjects"))
    validation.check_subjects(sheet, "subjects.csv", str(RAW / "profiles"))
    for subject in sheet["subject"]:
        path = RAW / "profiles" / f"{subject}.csv"
        profile = validation.read_table(path, io.load_schema("profiles"))
        validation.check_no_duplicate_readings(profile, str(path))
    for path in sorted((RAW / "outlines").glob("*.csv")):
        validation.read_table(path, io.load_schema("outlines"))
    depths = {
        s: sorted(
            set(
                validation.read_table(RAW / "profiles" / f"{s}.csv", io.load_schema("profiles"))[
                    "depth_mm"
                ]
            )
        )
        for s in sheet["subject"]
    }
    forces = validation.check_forces(str(RAW), io.load_schema("forces"), sheet, depths)
    assert len(forces) == sum(len(d) for d in depths.values())  # a force for every trial


def test_readme_documents_the_generator():
    text = README.read_text(encoding="utf-8")
    shipped = synthetic.shipped_subjects()
    assert synthetic.subject_markdown(shipped) in text
    assert synthetic.parameter_markdown(shipped) in text
    assert synthetic.membrane_markdown(shipped) in text
    assert synthetic.force_markdown(shipped) in text
    assert "make_synthetic_data.py --out data/raw" in text
    assert str(synthetic.DEFAULT_SEED) in text
    assert "snakemake --cores 2 --config raw_data=" in text


def test_the_committed_list_of_built_in_verdicts_is_the_generators():
    committed = json.loads((ROOT / "data" / "built_in_verdicts.json").read_text())
    assert committed == synthetic.built_in_verdicts()
    assert [v["claim"] for v in committed] == [f"C{i}" for i in range(1, 14)]
    # data/README.md names every claim's verdict as the list gives it
    text = README.read_text()
    for verdict in committed:
        assert f"**{verdict['claim']}**" in text, verdict["claim"]


def test_circle_fraction_blends_in_the_circle_through_depth_and_edge():
    # c = 1: every point on the circle of radius (e^2 + W0^2) / (2 W0) centred above the
    # edge, so w(0) = W0 and w(e) = 0 with zero slope; c = 0: the power-law profile
    x = np.linspace(0.0, 6.0, 61)
    depth_mm, extent_mm = 1.5, 5.0
    circle = synthetic.true_deflection_mm(x, depth_mm, extent_mm, 2.4, 0.3, 10.0, 1.0)
    radius_mm = (extent_mm**2 + depth_mm**2) / (2 * depth_mm)
    inside = x <= extent_mm
    assert np.allclose(
        (x[inside] - extent_mm) ** 2 + (circle[inside] - radius_mm) ** 2, radius_mm**2
    )
    assert circle[0] == pytest.approx(depth_mm) and np.all(circle[~inside] == 0.0)
    power = synthetic.true_deflection_mm(x, depth_mm, extent_mm, 2.4, 0.3, 10.0)
    assert np.array_equal(
        synthetic.true_deflection_mm(x, depth_mm, extent_mm, 2.4, 0.3, 10.0, 0.0), power
    )
    half = synthetic.true_deflection_mm(x, depth_mm, extent_mm, 2.4, 0.3, 10.0, 0.5)
    assert np.allclose(half, 0.5 * (power + circle))


def test_no_lab_script_depends_on_the_generator():
    """A lab's jobs run without the generator: only the generator's own script and the
    calibration's scripts (run_*) import it; the others at most read the committed
    calibration's rates and the notice that marks a synthetic folder."""
    from lineload.runtime.codedeps import script_dependencies

    allowed = {"__init__.py", "rates.py", "notices.py"}
    scripts = sorted((ROOT / "workflow" / "scripts").glob("*.py"))
    checked = 0
    for script in scripts:
        if script.name == "make_synthetic_data.py" or script.name.startswith("run_"):
            continue
        used = {
            Path(path).name
            for path in script_dependencies(script)
            if Path(path).parent.name == "simulation"
        }
        assert used <= allowed, f"{script.name} imports the generator: {sorted(used - allowed)}"
        checked += 1
    assert checked > 10
    # the check can fail: the generator's own script is caught
    generator = script_dependencies(SCRIPT)
    assert any(Path(path).name == "subjects.py" for path in generator)
