"""Shared fixtures: small raw datasets written to temporary folders."""

from __future__ import annotations

import ast
import fcntl
import json
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


def imported_after(statement, watched):
    """Which of the modules ``watched`` a fresh interpreter has loaded after running
    ``statement`` in the package's folder, sorted."""
    code = (
        f"import sys\n{statement}\nprint(sorted(m for m in {tuple(watched)!r} if m in sys.modules))"
    )
    process = subprocess.run(
        [sys.executable, "-c", code],
        cwd=REPO / "workflow",
        capture_output=True,
        text=True,
        check=True,
    )
    return ast.literal_eval(process.stdout.strip())  # the list printed


def batch_of(subject, subject_ids, photographs=False):
    """The name of the batch (the files of the per-batch rules) a subject falls in
    under the default ``subjects_per_job`` (``photographs``: the dataset has some)."""
    from lineload.runtime import batches

    split = batches.batches(subject_ids, photographs=photographs)
    return next(name for name, members in split.items() if subject in members)


#: The small dataset's batch (write_small_dataset's subjects, default split).
SMALL_BATCH = batch_of("MK", ["MK", "HU"])


#: Modules whose tests run longest (a real cluster, builds killed and resumed, a copied
#: checkout built whole): collected first, so that pytest-xdist starts them first and
#: the short tests fill the other workers meanwhile.  That needs ``--maxschedchunk=1``
#: (pyproject.toml): by default xdist 3.8 first hands each worker a quarter of its share
#: of consecutive tests (83 of 1007 on three workers), so one worker got every long test
#: in a row.
LONGEST_FIRST = ("test_slurm.py", "test_cluster.py", "test_portable.py", "test_determinism.py")


def pytest_xdist_auto_num_workers(config):
    """Workers for ``-n auto`` (set in pyproject.toml): one per core, and one more.

    Several end-to-end tests spend most of their time waiting, not computing: the real
    SLURM test on the cluster's polling (about a third of its time is CPU), the killed
    builds on their moments.  A worker more than the cores keeps both cores busy then.
    """
    return (os.cpu_count() or 1) + 1


def pytest_collection_modifyitems(items):
    """Run the longest modules' tests first (see :data:`LONGEST_FIRST`)."""

    def rank(item):
        name = item.path.name
        return LONGEST_FIRST.index(name) if name in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: the order within each group stays


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
        # the jobs and their files, which the default profile keeps off the console:
        # tests read which jobs ran
        "--quiet",
        "reason",
        "--cores",
        "2",
        *args,
        "--config",
        f"raw_data={raw}",
        f"results={results}",
        *config,
    ]
    if Path(cwd) == REPO:
        # Runs of other tests share this working folder; Snakemake 9.27 removes the whole
        # lock folder (.snakemake/locks) when a run ends, other runs' locks with it, and a
        # run starting at that moment fails on a missing lock file.  Tests of locking
        # (killed builds) run in folders of their own, with locks.
        command.insert(command.index("--cores"), "--nolock")
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
    """Files a refused run left under the results folder, besides the check's log and
    the diagnostic images (PNG) of refused photograph pairs that its lines name."""
    log = results / "logs" / "check_raw_data.log"
    said = log.read_text() if log.is_file() else ""
    return sorted(
        str(p)
        for p in results.rglob("*")
        if p.is_file() and p != log and not (p.suffix == ".png" and f" {p} (panel" in said)
    )


def refused_run(raw, results, config=()):
    """Run the default target on a raw folder that must be refused: a non-zero exit, no
    traceback, nothing written but the check's log.  Returns the process, its whole
    output and its ``Error: `` lines."""
    process = run_snakemake(raw=str(raw), results=str(results), config=config)
    output = process.stdout + process.stderr
    assert process.returncode != 0, output
    assert not TRACEBACK.search(without_failed_check(output)), output
    assert leftovers(results) == [], "partial output written"
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    return process, output, errors


def build_outputs(results):
    """Every output of a build but logs and timings, by path, with the folder's own name
    (which the provenance record and the jobs' params hold, as a results folder outside the
    working folder is named, never given by its path) written as <results>, so builds
    in two folders compare byte for byte.  The run crate states each log's size and
    hash; logs name the folders as the build was given them, and are left out here: so
    are those two values of theirs (:func:`without_log_hashes`), nothing else."""
    outputs = {
        path.relative_to(results).as_posix(): path.read_bytes().replace(
            f'"{results.name}"'.encode(), b'"<results>"'
        )
        for path in sorted(results.rglob("*"))
        if path.is_file() and path.relative_to(results).parts[0] not in ("logs", "benchmarks")
    }
    if "ro-crate-metadata.json" in outputs:
        outputs["ro-crate-metadata.json"] = without_log_hashes(outputs["ro-crate-metadata.json"])
    return outputs


def without_log_hashes(crate_bytes):
    """A crate's JSON with the size and SHA-256 of each log file removed."""
    crate = json.loads(crate_bytes)
    for entity in crate["@graph"]:
        if entity["@id"].startswith("logs/"):
            entity.pop("contentSize")
            entity.pop("sha256")
    return json.dumps(crate, indent=2).encode()


# ------------------------------------------------------------------ builds shared by tests
#
# A full build takes 10-20 s; tests that only read its outputs share one per test
# session, across pytest-xdist's workers: the first worker to ask builds it under a
# file lock, the others wait for it and read the same folder.  A test that changes
# files (deletes an intermediate, edits a raw file) works on a copy of its own
# (:func:`copy_build`), never on the shared folder.

#: The NOTICE.txt of the shared builds that carry one.
SHARED_NOTICE = "Invented readings, for a test."


def outline_rows(magnification=20):
    """A resting and a deformed outline at 1 mm (image units), for Figure 1."""
    lines = ["depth_mm,state,x_image_mm,z_image_mm"]
    for state, dip in (("resting", 0.0), ("deformed", 1.0)):
        for x in range(-100, 101, 5):  # image mm at magnification 20: -5 to 5 tissue mm
            z = -((x / magnification) ** 2) / 16
            z -= dip * max(0.0, 1 - abs(x / magnification) / 4) ** 2
            lines.append(f"1,{state},{x},{magnification * z:.3f}")
    return "\n".join(lines) + "\n"


def write_shared_dataset(raw_dir, notice=""):
    """The small dataset (MK at 1 and 2 mm, HU at 1 mm), with MK's outlines and,
    if given, a NOTICE.txt: what the shared builds are made from."""
    write_small_dataset(raw_dir)
    (raw_dir / "outlines").mkdir()
    (raw_dir / "outlines" / "MK.csv").write_text(outline_rows())
    if notice:
        (raw_dir / "NOTICE.txt").write_text(notice + "\n")
    return raw_dir


def _shared_root(tmp_path_factory):
    """The folder all workers of this session share (pytest-xdist gives each worker a
    base folder of its own inside it)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def shared(tmp_path_factory, name, make):
    """What ``make(folder)`` builds in a folder of its own, once per session, whichever
    worker asks first; ``make`` returns ``(raw, results, completed_process)``.  Returns
    ``(raw, results)``.  A build that failed is not tried again by the next test: each
    fails with its output.
    """
    root = _shared_root(tmp_path_factory)
    folder = root / f"shared-{name}"
    record = folder / "build.json"
    with open(root / f"shared-{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not record.exists():
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir()
            raw, results, done = make(folder)
            outcome = {"raw": str(raw), "results": str(results)}
            outcome.update(returncode=done.returncode, stderr=done.stderr[-4000:])
            record.write_text(json.dumps(outcome))
    outcome = json.loads(record.read_text())
    assert outcome["returncode"] == 0, outcome["stderr"]
    return Path(outcome["raw"]), Path(outcome["results"])


def shared_build(tmp_path_factory, name, write_raw, outputs=(), in_copy=False):
    """Build ``outputs`` (paths under the results folder; default: everything) of the
    raw folder ``write_raw(folder)`` writes, once per session (:func:`shared`); return
    ``(raw, results)``.

    ``in_copy``: from a copy of the checkout (:func:`copy_checkout`), as another lab's
    copy would be: no git history there.
    """

    def make(folder):
        raw, results = write_raw(folder / "raw"), folder / "results"
        targets = [str(results / output) for output in outputs]
        if not in_copy:
            return raw, results, run_snakemake(*targets, raw=raw, results=results)
        checkout = copy_checkout(folder / "checkout")
        return raw, results, run_in_checkout(checkout, *targets, raw=raw, results=results)

    return shared(tmp_path_factory, name, make)


def run_in_checkout(checkout, *args, raw, results):
    """:func:`run_snakemake` in a copy of the checkout, with that copy's own package."""
    env = {"PYTHONPATH": str(checkout / "workflow")}
    return run_snakemake(*args, raw=raw, results=results, cwd=checkout, env=env)


def copy_checkout(destination):
    """The repository's files as git sees them (tracked and new, not ignored) copied to
    ``destination``, as a clone would have them."""
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=REPO,
        capture_output=True,
        check=True,
    ).stdout.split(b"\0")
    for name in filter(None, (n.decode() for n in listed)):
        source = REPO / name
        if source.is_file():
            target = destination / name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)
    return destination


def copy_build(raw, results, destination):
    """A copy of a build's raw and results folders (times kept) for a test to change."""
    destination.mkdir(parents=True, exist_ok=True)
    raw_copy, results_copy = destination / raw.name, destination / "results"
    shutil.copytree(raw, raw_copy)
    shutil.copytree(results, results_copy)
    return raw_copy, results_copy


@pytest.fixture(scope="session")
def small_build(tmp_path_factory):
    """Everything built from the small dataset without a notice: ``(raw, results)``."""
    return shared_build(tmp_path_factory, "small", write_shared_dataset)


@pytest.fixture(scope="session")
def small_build_with_notice(tmp_path_factory):
    """The same with a NOTICE.txt (:data:`SHARED_NOTICE`), built in a copy of the
    checkout: ``(raw, results)``."""
    return shared_build(
        tmp_path_factory,
        "small-notice",
        lambda folder: write_shared_dataset(folder, SHARED_NOTICE),
        in_copy=True,  # then test_determinism.py compares it with test_portable.py's build
    )


@pytest.fixture(scope="session")
def shipped_build(tmp_path_factory):
    """The fits, claims and mechanics of the shipped data, and their article (whose pages
    are laid out for these data): ``(raw, results)``."""

    def shipped(folder):
        return REPO / "data" / "raw"  # read, never written

    outputs = [f"tables/{name}" for name in ("fits.csv", "claims.csv", "mechanics.csv")]
    outputs.append("article/reproduction.pdf")
    return shared_build(tmp_path_factory, "shipped", shipped, outputs)


@pytest.fixture(scope="session")
def photograph_build(tmp_path_factory):
    """The photograph example (``data/photographs``, which test_photographs.py shows is
    the generator's, byte for byte, with ``config/photographs.yaml``) built whole, from
    images to article: ``(raw, results)``."""

    def make(folder):
        raw, results = REPO / "data" / "photographs", folder / "results"  # raw: read only
        config = ("--configfile", str(REPO / "config" / "photographs.yaml"))
        return raw, results, run_snakemake(*config, raw=raw, results=results)

    return shared(tmp_path_factory, "photographs", make)


@pytest.fixture(scope="session")
def checkout_build(tmp_path_factory):
    """A copy of the checkout with the small dataset (the notice, outlines) in its folder
    ``raw`` and its results in ``results``, both named relative to it, built whole from
    there, once per session: ``(checkout, results)``."""

    def make(folder):
        checkout = copy_checkout(folder / "checkout")
        write_shared_dataset(checkout / "raw", SHARED_NOTICE)
        done = run_in_checkout(checkout, raw="raw", results="results")
        return checkout / "raw", checkout / "results", done

    raw, results = shared(tmp_path_factory, "checkout", make)
    return raw.parent, results


def job_params(log):
    """The values a job was given (its ``params``), from the first line of its log."""
    for line in Path(log).read_text().splitlines():
        if line.startswith("params: "):
            return json.loads(line.removeprefix("params: "))
    raise AssertionError(f"{log}: no params line")
