"""Shared fixtures: small raw datasets written to temporary folders."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]


def reading_grid_mm(extent_mm, first_mm=0.05):
    """Distances of the readings (tissue mm): 0.05 steps to 0.5, 0.25 to 3, 0.5 beyond."""
    near = np.arange(first_mm, 0.5 + 1e-9, 0.05)
    mid = np.arange(0.75, min(3.0, extent_mm) + 1e-9, 0.25)
    far = np.arange(3.5, extent_mm + 1e-9, 0.5)
    return np.round(np.concatenate([near, mid, far]), 6)


def write_small_dataset(raw_dir, subjects=None, magnification=20.0, seed=7):
    """Write a contract-conforming raw folder made from a simple known profile.

    Each subject/depth profile is ``depth * (1 - x / extent)**2``: smooth,
    monotone, zero at the extent, with 0.005 mm noise.  Returns the raw folder.

    Parameters
    ----------
    raw_dir : pathlib.Path
        Folder to create.
    subjects : dict, optional
        ``{subject: (species, [depths], extent_mm)}``.
    """
    subjects = subjects or {
        "MK": ("monkey", [1.0, 2.0], 5.0),
        "HU": ("human", [1.0], 9.0),
    }
    rng = np.random.default_rng(seed)
    (raw_dir / "profiles").mkdir(parents=True, exist_ok=True)
    lines = ["subject,species,magnification,label"]
    for subject, (species, depths, extent_mm) in subjects.items():
        lines.append(f"{subject},{species},{magnification:g},{species} {subject}")
        rows = ["depth_mm,side,distance_image_mm,deflection_image_mm"]
        for depth_mm in depths:
            for side in ("left", "right"):
                x = reading_grid_mm(extent_mm)
                w = depth_mm * (1 - x / extent_mm) ** 2 + rng.normal(0, 0.005, x.size)
                for xi, wi in zip(x, np.clip(w, 0, None), strict=True):
                    rows.append(
                        f"{depth_mm:g},{side},{xi * magnification:.3f},{wi * magnification:.3f}"
                    )
        (raw_dir / "profiles" / f"{subject}.csv").write_text("\n".join(rows) + "\n")
    (raw_dir / "subjects.csv").write_text("\n".join(lines) + "\n")
    return raw_dir


@pytest.fixture
def small_raw(tmp_path):
    """A two-subject raw folder (monkey MK at 1 and 2 mm, human HU at 1 mm)."""
    return write_small_dataset(tmp_path / "raw")


def run_snakemake(*args, raw, results, config=(), cwd=REPO, timeout=600, env=None):
    """Run snakemake on a Snakefile (the repository's, or ``cwd``'s copy) with other folders.

    ``args`` (targets and options) go before ``--config``, which takes every
    word after it as a KEY=VALUE; ``config`` adds more KEY=VALUE settings;
    ``env`` adds environment variables.
    """
    command = [
        sys.executable,
        "-m",
        "snakemake",
        "--snakefile",
        str(Path(cwd) / "workflow" / "Snakefile")
        if (Path(cwd) / "workflow" / "Snakefile").is_file()
        else str(REPO / "workflow" / "Snakefile"),
        "--directory",
        str(cwd),
        "--cores",
        "2",
        *args,
        "--config",
        f"raw_data={raw}",
        f"results={results}",
        *config,
    ]
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1", **(env or {})}
    return subprocess.run(command, capture_output=True, text=True, timeout=timeout, env=env)


@pytest.fixture(scope="session")
def snakemake_available():
    if (
        shutil.which("snakemake") is None
        and not (Path(sys.executable).parent / "snakemake").exists()
    ):
        pytest.fail("snakemake is not installed in this environment")
    return True


# Signs of a traceback, in Python's or snakemake's own format.
TRACEBACK = re.compile(r"Traceback|^\s*File \".*\", line \d+|\w+(Error|Exception) in file", re.M)


def without_failed_check(output):
    """The output without Snakemake's note that the job check_raw_data failed (a bad raw
    file is refused by that job); no other job may have failed."""
    assert set(re.findall(r"^Error in rule (\w+):", output, re.M)) <= {"check_raw_data"}, output
    return re.sub(r'CalledProcessError in file "[^"]*data\.smk"', "", output)


def leftovers(results):
    """Files a refused run left under the results folder, besides the check's log."""
    log = results / "logs" / "check_raw_data.log"
    return sorted(str(p) for p in results.rglob("*") if p.is_file() and p != log)


def build_outputs(results):
    """Every output of a build but logs and timings, by path, with the folder's own name
    (which the provenance record and the specs hold, as a results folder outside the
    working folder is named, never given by its path) written as <results>, so builds
    in two folders compare byte for byte."""
    return {
        path.relative_to(results).as_posix(): path.read_bytes().replace(
            f'"{results.name}"'.encode(), b'"<results>"'
        )
        for path in sorted(results.rglob("*"))
        if path.is_file() and path.relative_to(results).parts[0] not in ("logs", "benchmarks")
    }
