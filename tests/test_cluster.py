"""The workflow through a non-local executor, and resumed after being killed."""

import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import REPO, SMALL_BATCH, build_outputs, run_snakemake, write_small_dataset

pytestmark = pytest.mark.e2e  # every test here runs Snakemake


def check_ok(process):
    assert process.returncode == 0, (process.stdout + process.stderr)[-4000:]
    return process


def test_fits_through_a_cluster_executor_equal_a_local_run(tmp_path, small_build):
    raw, local = small_build  # the local run: a build shared with other tests
    cluster = tmp_path / "cluster"
    check_ok(
        run_snakemake(
            "fits",
            "--executor", "cluster-generic",
            "--cluster-generic-submit-cmd", str(REPO / "tests" / "cluster" / "submit.sh"),
            "--jobs", "4",
            "--latency-wait", "10",
            "--seconds-between-status-checks", "1",
            raw=raw,
            results=cluster,
        )
    )  # fmt: skip
    assert (cluster / "tables" / "fits.csv").read_bytes() == (
        local / "tables" / "fits.csv"
    ).read_bytes()
    assert (cluster / "data" / "averaged" / f"{SMALL_BATCH}.csv").read_bytes() == (
        local / "data" / "averaged" / f"{SMALL_BATCH}.csv"
    ).read_bytes()


def own_folder(tmp_path):
    """A working folder of the test's own: the locks a killed build leaves behind, and
    the ``--unlock`` that clears them, stay out of the repository's ``.snakemake``,
    where the builds of other tests running at the same time keep theirs."""
    folder = tmp_path / "work"
    folder.mkdir(exist_ok=True)
    return folder


def start_build(raw, results, workdir, *args):
    command = [
        sys.executable, "-m", "snakemake", "--snakefile", str(REPO / "workflow" / "Snakefile"),
        "--directory", str(workdir), "--cores", "2", *args,
        "--config", f"raw_data={raw}", f"results={results}",
    ]  # fmt: skip
    return subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
    )


def wait_for_new_file(process, folder, pattern, before, timeout_s=120):
    """Wait until a file matching ``pattern`` that was not in ``before`` exists."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if set(folder.glob(pattern)) - before:
            return
        if process.poll() is not None:
            raise AssertionError(f"the build ended before a new file {pattern} appeared")
        time.sleep(0.05)
    raise AssertionError(f"no new file {pattern} in {folder} after {timeout_s} s")


#: When to kill a build: after a delay (seconds; in the first job selection, then in the
#: DAG building) or once a new file exists (mid-way through each stage).  Two chains,
#: each run in order in one results folder: the claims table and the figures are made
#: side by side, so whichever comes first would leave the other uncut.  The longest
#: delay comes first, on the fresh folder: a later build starts where the one before it
#: stopped, and two seconds into it the averaged profiles (started first by the rules'
#: priorities) may already be written, leaving that stage uncut.
KILL_CHAINS = [
    [
        ("after", 2.0),
        ("after", 0.3),
        ("after", 1.0),
        ("file", "data/averaged/*.csv"),
        ("file", "fits/*.csv"),
        ("file", "tables/fits.csv"),
        ("file", "figures/*.pdf"),
        ("file", "article/facts.json"),
    ],
    [("file", "tables/claims.csv")],
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


def test_killed_builds_stop_and_resume_to_the_same_files(tmp_path, small_build):
    """`kill` (SIGTERM) at many moments: the build and its jobs stop within seconds, and
    the plain command then ends with the same files as an uninterrupted build (the
    workflow profile reruns incomplete jobs: no --rerun-incomplete to remember).

    Each chain's results folder goes through its moments in turn, in the order the
    build reaches them: each build starts where the killed one before it stopped and is
    killed at the next moment, a new file of that stage, so every stage is cut once.
    """
    raw, reference = small_build  # the uninterrupted build, shared with other tests
    expected = build_outputs(reference)
    work = own_folder(tmp_path)
    for number, chain in enumerate(KILL_CHAINS):
        results = tmp_path / f"chain-{number}" / "results"  # the reference folder's name
        for kind, when in chain:
            before = set(results.glob(when)) if kind == "file" else set()
            process = start_build(raw, results, work)
            if kind == "after":
                time.sleep(when)
            else:
                wait_for_new_file(process, results, when, before)
            os.kill(process.pid, signal.SIGTERM)
            stop(process)
        resumed = run_snakemake(raw=raw, results=results, cwd=work)
        check_ok(resumed)
        assert build_outputs(results) == expected, chain


def test_hard_killed_build_resumes_after_unlock(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    results = tmp_path / "results"
    work = own_folder(tmp_path)
    process = start_build(raw, results, work)
    wait_for_new_file(process, results, "data/averaged/*.csv", set())
    os.killpg(process.pid, signal.SIGKILL)  # no chance to clean up: locks stay behind
    process.wait(timeout=60)
    check_ok(run_snakemake("--unlock", raw=raw, results=results, cwd=work))
    # the locks are gone: a build gets through (the fit table, the first stages whole)
    check_ok(run_snakemake("fits", raw=raw, results=results, cwd=work))
    assert (results / "tables" / "fits.csv").is_file()
