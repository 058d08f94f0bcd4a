"""A lab deploys the workflow the Snakemake way: as a module of its own Snakefile.

What ``snakedeploy deploy-workflow`` writes (FIELD-NOTES): the lab's folder holds its
config and a Snakefile with ``configfile:``, ``module`` and ``use rule * from``; the
workflow's own files stay where they are.  Inside a module ``workflow.basedir`` is the
lab's folder, so every path to the workflow's scripts, schemas and templates must come
from the workflow's own folder.
"""

import csv
import os
import subprocess
import sys

import pytest

from conftest import REPO, write_small_dataset

DEPLOYING_SNAKEFILE = """\
configfile: "config/config.yaml"


module lineload:
    snakefile:
        "{snakefile}"
    config:
        config


use rule * from lineload
"""


def write_lab(folder):
    """A lab's folder: its raw data, its config (its own window) and its Snakefile."""
    write_small_dataset(folder / "raw")
    (folder / "config").mkdir(parents=True)
    # the lab's own setting: a narrower window than the shipped config's 3 mm
    (folder / "config" / "config.yaml").write_text(
        "raw_data: raw\nresults: out\nfit_window_mm: 2.5\n"
    )
    (folder / "workflow").mkdir()
    (folder / "workflow" / "Snakefile").write_text(
        DEPLOYING_SNAKEFILE.format(snakefile=REPO / "workflow" / "Snakefile")
    )
    return folder


def snakemake_in(folder, *args):
    return subprocess.run(
        [sys.executable, "-m", "snakemake", "--cores", "2", *args],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"},
    )


@pytest.mark.e2e
def test_a_lab_builds_the_fits_through_a_module(tmp_path, snakemake_available):
    lab = write_lab(tmp_path / "lab")
    # a dry run first: it plans every job and writes nothing, not even the results folder
    dry = snakemake_in(lab, "--dry-run", "fits")
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert "fit_models" in dry.stdout + dry.stderr
    assert not (lab / "out").exists()
    run = snakemake_in(lab, "fits")
    assert run.returncode == 0, run.stderr[-3000:]
    with open(lab / "out" / "tables" / "fits.csv", newline="") as table:
        rows = list(csv.DictReader(table))
    # the lab's own subjects, fitted in its own window, in its own results folder
    assert {row["subject"] for row in rows} == {"MK", "HU"}
    assert {float(row["fit_window_mm"]) for row in rows} == {2.5}
    # nothing written into the workflow's checkout or beside the lab's config
    made = sorted(p.name for p in lab.iterdir())
    assert made == [".snakemake", "config", "out", "raw", "workflow"]
