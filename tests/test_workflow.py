"""The workflow end to end, on small datasets in temporary folders and on the shipped data."""

import json
import shutil

import numpy as np
import pandas as pd
import pytest

from conftest import REPO, SMALL_BATCH, reading_grid_mm, run_snakemake, write_small_dataset
from lineload import models
from lineload.fitting.batch import FIT_COLUMNS

pytestmark = pytest.mark.e2e  # every test here runs Snakemake


def check_ok(process):
    assert process.returncode == 0, process.stderr[-3000:]
    return process


def test_fits_target_on_a_small_dataset(small_build):
    small_raw, out = small_build  # a whole build, shared; the fits are part of it
    fits = pd.read_csv(out / "tables" / "fits.csv")
    assert list(fits.columns) == FIT_COLUMNS
    # one row per subject and depth, in subject-sheet order, depths ascending
    assert list(zip(fits["subject"], fits["depth_mm"], strict=True)) == [
        ("MK", 1.0),
        ("MK", 2.0),
        ("HU", 1.0),
    ]
    assert list(fits["species"]) == ["monkey", "monkey", "human"]
    for stage in ("converted", "averaged"):  # both subjects in one job's files
        assert (out / "data" / stage / f"{SMALL_BATCH}.csv").is_file()
    assert (out / "logs" / "fit_models" / f"{SMALL_BATCH}.log").is_file()
    assert (fits["n_points"] == len(reading_grid_mm(5.0)[reading_grid_mm(5.0) <= 3.0])).all()
    # nothing to do on a second run
    again = check_ok(run_snakemake("fits", "--dry-run", raw=small_raw, results=out))
    assert "Nothing to be done" in again.stdout + again.stderr


def write_model_dataset(raw_dir, magnification=20.0, seed=11):
    """Subjects whose profiles come from the fitted models themselves (both sides, noise)."""
    truth = {
        "WB": ("human", 1.5, lambda x: models.waterbed_deflection_mm(x, 1.5, 13.0)),
        "BQ": ("monkey", 1.0, lambda x: models.boussinesq_deflection_mm(x, 0.3, 6.0)),
        "ARC": ("monkey", 2.0, lambda x: models.arc_deflection_mm(x, 2.0, 9.0)),
    }
    rng = np.random.default_rng(seed)
    (raw_dir / "profiles").mkdir(parents=True)
    sheet = ["subject,species,magnification"]
    for subject, (species, depth_mm, profile) in truth.items():
        sheet.append(f"{subject},{species},{magnification:g}")
        rows = ["depth_mm,side,distance_image_mm,deflection_image_mm"]
        x = reading_grid_mm(3.0)
        for side in ("right", "left"):
            w = profile(x) + rng.normal(0, 0.005, x.size)
            rows += [
                f"{depth_mm:g},{side},{xi * magnification:.4f},{wi * magnification:.4f}"
                for xi, wi in zip(x, w, strict=True)
            ]
        (raw_dir / "profiles" / f"{subject}.csv").write_text("\n".join(rows) + "\n")
    (raw_dir / "subjects.csv").write_text("\n".join(sheet) + "\n")


def test_workflow_recovers_known_parameters(tmp_path):
    raw, out = tmp_path / "raw", tmp_path / "out"
    write_model_dataset(raw)
    check_ok(run_snakemake("fits", raw=raw, results=out))
    fits = pd.read_csv(out / "tables" / "fits.csv").set_index("subject")
    assert fits.loc["WB", "waterbed_L_mm"] == pytest.approx(13.0, rel=0.03)
    assert fits.loc["ARC", "arc_L_mm"] == pytest.approx(9.0, rel=0.03)
    assert fits.loc["BQ", "boussinesq_A_mm"] == pytest.approx(0.3, rel=0.03)
    assert fits.loc["BQ", "boussinesq_x0_mm"] == pytest.approx(6.0, rel=0.03)
    # each model wins on its own data
    assert fits.loc["WB", "waterbed_aicc"] < fits.loc["WB", "boussinesq_aicc"]
    assert fits.loc["BQ", "boussinesq_aicc"] < fits.loc["BQ", "waterbed_aicc"]
    assert fits.loc["ARC", "arc_aicc"] < fits.loc["ARC", "waterbed_aicc"]


def test_relative_results_folder_and_fit_window(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    out = tmp_path / "narrow"
    check_ok(run_snakemake("fits", raw=raw, results=out, config=["fit_window_mm=1"]))
    fits = pd.read_csv(out / "tables" / "fits.csv")
    assert (fits["max_distance_mm"] <= 1.0).all()
    assert (fits["fit_window_mm"] == 1.0).all()


@pytest.fixture(scope="module")
def shipped_results(shipped_build):
    return shipped_build[1]


@pytest.fixture(scope="module")
def shipped_fits(shipped_results):
    return pd.read_csv(shipped_results / "tables" / "fits.csv")


def test_shipped_verdicts_are_those_the_generator_built_in(shipped_results):
    # data/built_in_verdicts.json, written by the generator, is what data/README.md and
    # the article say the reconstruction holds: the claims table must agree with it
    built_in = json.loads((REPO / "data" / "built_in_verdicts.json").read_text())
    claims = pd.read_csv(shipped_results / "tables" / "claims.csv").set_index("claim")
    # every claim, the later models' (C12, C13) too: their verdicts follow from what the
    # generator lacks (an elastic finger, a bending skin)
    assert {v["claim"]: v["verdict"] for v in built_in} == claims["verdict"].to_dict()
    noise = pd.read_csv(shipped_results / "tables" / "noise.csv").set_index("parameter")
    # the measured reading and tracing errors together are near the generator's
    # (0.008 and 0.005 mm per side, plus the 0.005 mm rounding), within 4 of their SEs
    total = np.hypot(noise.loc["reading_sd_mm", "value"], noise.loc["tracing_sd_mm", "value"])
    se = np.hypot(noise.loc["reading_sd_mm", "se"], noise.loc["tracing_sd_mm", "se"])
    assert abs(total - np.hypot(0.008, 0.005)) < 4 * se + 0.005 / np.sqrt(12)


def test_shipped_data_give_26_trials(shipped_fits):
    assert len(shipped_fits) == 26
    counts = shipped_fits.groupby("species")["subject"].nunique().to_dict()
    assert counts == {"monkey": 4, "human": 3}
    depths = shipped_fits.groupby("subject")["depth_mm"].apply(list).to_dict()
    assert depths.pop("H3") == [1.0, 2.0]
    assert all(d == [0.5, 1.0, 1.5, 2.0] for d in depths.values())
    may_be_nan = [c for c in FIT_COLUMNS if c.startswith("boussinesq_x0")]
    assert shipped_fits[FIT_COLUMNS].drop(columns=may_be_nan).notna().all().all()


def test_batches_of_subjects_give_the_same_results(tmp_path, small_build):
    raw, batched = small_build  # both subjects in one job (shared); here one per job
    single = tmp_path / "single"
    check_ok(run_snakemake("fits", raw=raw, results=single, config=["subjects_per_job=1"]))
    # one file per subject, or per batch of two (named after its first subject)
    assert sorted(p.name for p in (single / "fits").glob("*.csv")) == ["HU.csv", "MK.csv"]
    assert sorted(p.name for p in (batched / "fits").glob("*.csv")) == ["MK+1.csv"]
    batch = pd.read_csv(batched / "data" / "averaged" / "MK+1.csv")
    assert list(dict.fromkeys(batch["subject"])) == ["MK", "HU"]
    same = (single / "tables" / "fits.csv").read_bytes()
    assert (batched / "tables" / "fits.csv").read_bytes() == same


def test_editing_a_science_module_makes_its_jobs_stale(small_raw, tmp_path):
    # a copy of the workflow, its package imported from the copy: the test edits the
    # copy, never the repository's own files (safe beside other tests running at once)
    copy = tmp_path / "checkout"
    for part in ("workflow", "config"):
        shutil.copytree(REPO / part, copy / part, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(REPO / "environment.yml", copy)
    out = tmp_path / "out"
    env = {"PYTHONPATH": str(copy / "workflow")}
    check_ok(run_snakemake("fits", raw=small_raw, results=out, cwd=copy, env=env))
    module = copy / "workflow" / "lineload" / "fitting" / "batch.py"
    # Snakemake compares contents, not only times: make a real (harmless) edit
    module.write_bytes(module.read_bytes() + b"\n# edited by a test\n")
    dry = check_ok(
        run_snakemake("fits", "--dry-run", raw=small_raw, results=out, cwd=copy, env=env)
    )
    text = dry.stdout + dry.stderr
    assert "fit_models" in text and "fits_table" in text
    # the data stage does not use the fitting code
    assert "prepare_profiles" not in text
