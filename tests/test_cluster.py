"""The workflow through a non-local executor, and resumed after being killed."""

import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import REPO, build_outputs, run_snakemake, write_small_dataset

pytestmark = pytest.mark.e2e  # every test here runs Snakemake

SUBJECTS = {
    "MK": ("monkey", [1.0, 2.0], 5.0),
    "MJ": ("monkey", [1.0], 4.5),
    "HU": ("human", [1.0, 2.0], 9.0),
}


def check_ok(process):
    assert process.returncode == 0, (process.stdout + process.stderr)[-4000:]
    return process


def test_fits_through_a_cluster_executor_equal_a_local_run(tmp_path):
    raw = write_small_dataset(tmp_path / "raw", subjects=SUBJECTS)
    local, cluster = tmp_path / "local", tmp_path / "cluster"
    check_ok(run_snakemake("fits", raw=raw, results=local))
    check_ok(
        run_snakemake(
            "fits",
            "--executor", "cluster-generic",
            "--cluster-generic-submit-cmd", str(REPO / "tests" / "cluster" / "submit.sh"),
            "--jobs", "4",
            "--latency-wait", "10",
            raw=raw,
            results=cluster,
        )
    )  # fmt: skip
    assert (cluster / "tables" / "fits.csv").read_bytes() == (
        local / "tables" / "fits.csv"
    ).read_bytes()
    for subject in SUBJECTS:
        assert (cluster / "data" / "averaged" / f"{subject}.csv").read_bytes() == (
            local / "data" / "averaged" / f"{subject}.csv"
        ).read_bytes()


def own_folder(tmp_path):
    """A working folder of the test's own: the locks a killed build leaves behind, and
    the ``--unlock`` that clears them, stay out of the repository's ``.snakemake``,
    where the builds of other tests running at the same time keep theirs."""
    folder = tmp_path / "work"
    folder.mkdir(exist_ok=True)
    return folder


def start_build(raw, results, workdir):
    command = [
        sys.executable, "-m", "snakemake", "--snakefile", str(REPO / "workflow" / "Snakefile"),
        "--directory", str(workdir), "--cores", "2",
        "--config", f"raw_data={raw}", f"results={results}",
    ]  # fmt: skip
    return subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
    )


def wait_for_files(folder, pattern, count, timeout_s=120):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if len(list(folder.glob(pattern))) >= count:
            return
        time.sleep(0.05)
    raise AssertionError(f"no {count} files {pattern} in {folder} after {timeout_s} s")


#: When to kill a build: after a delay (seconds; early ones fall in the DAG building and
#: the first job selection) or once some file exists (mid-way through each stage).
KILL_MOMENTS = [  # nine moments
    ("after", 0.3),
    ("after", 1.0),
    ("after", 2.0),
    ("file", "data/averaged/*.csv"),
    ("file", "fits/*.csv"),
    ("file", "tables/fits.csv"),
    ("file", "figures/*.pdf"),
    ("file", "tables/claims.csv"),
    ("file", "article/facts.json"),
]


def stop(process, timeout_s=15):
    """Wait for a killed build to exit; if it hangs, kill its whole process group and fail.

    Then nothing of the build may be left: its jobs ran in its process group.
    """
    try:
        process.wait(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait(timeout=30)
        raise AssertionError(f"the build did not stop within {timeout_s} s of SIGTERM") from None
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            os.killpg(process.pid, 0)  # anything left in the build's process group?
        except ProcessLookupError:
            return
        time.sleep(0.1)
    os.killpg(process.pid, signal.SIGKILL)
    raise AssertionError("a job of the killed build was still running 10 s after it stopped")


def test_killed_builds_stop_and_resume_to_the_same_files(tmp_path):
    """`kill` (SIGTERM) at many moments: the build and its jobs stop within seconds, and
    `--rerun-incomplete` then ends with the same files as an uninterrupted build."""
    raw = write_small_dataset(tmp_path / "raw", subjects=SUBJECTS)
    work = own_folder(tmp_path)
    reference = tmp_path / "reference"
    check_ok(run_snakemake(raw=raw, results=reference, cwd=work))
    expected = build_outputs(reference)
    for kind, when in KILL_MOMENTS:
        results = tmp_path / f"killed-{kind}-{str(when).replace('/', '_').replace('*', 'x')}"
        process = start_build(raw, results, work)
        if kind == "after":
            time.sleep(when)
        else:
            wait_for_files(results, when, 1)
        os.kill(process.pid, signal.SIGTERM)
        stop(process)
        resumed = run_snakemake("--rerun-incomplete", raw=raw, results=results, cwd=work)
        check_ok(resumed)
        assert build_outputs(results) == expected, (kind, when)


def test_hard_killed_build_resumes_after_unlock(tmp_path):
    raw = write_small_dataset(tmp_path / "raw", subjects=SUBJECTS)
    results = tmp_path / "results"
    work = own_folder(tmp_path)
    process = start_build(raw, results, work)
    wait_for_files(results, "data/averaged/*.csv", 1)
    os.killpg(process.pid, signal.SIGKILL)  # no chance to clean up: locks stay behind
    process.wait(timeout=60)
    check_ok(run_snakemake("--unlock", raw=raw, results=results, cwd=work))
    check_ok(run_snakemake("--rerun-incomplete", raw=raw, results=results, cwd=work))
    assert (results / "tables" / "claims.md").is_file()
    assert (results / "provenance.json").is_file()
