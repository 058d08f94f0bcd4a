"""The README's SLURM command on a real single-node SLURM cluster, against a local run.

The cluster (Debian's slurm-wlm and munge, on localhost, sized by `slurmd -C`, with
its own state folders) is started by tests/cluster/slurm-cluster.sh, which installs
the packages when run as root.  Where no cluster can be started (not root, no package
access) or the executor plugin is missing, the tests are skipped with the reason.
"""

import importlib.util
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest
import yaml

from conftest import REPO, build_outputs, run_snakemake

pytestmark = pytest.mark.e2e

CLUSTER = REPO / "tests" / "cluster" / "slurm-cluster.sh"
PROFILE = REPO / "profiles" / "slurm" / "config.yaml"
#: Longest a build may take before it counts as hung (the profile polls every 5 s).
BUILD_TIMEOUT_S = 900


@pytest.fixture(scope="module")
def cluster():
    """A running single-node cluster for the tests of this module; stopped afterwards.

    Its folder is not under pytest's temporary folder: munged runs as the user munge,
    which must be able to reach it (pytest's folders are private to their owner).
    """
    if importlib.util.find_spec("snakemake_executor_plugin_slurm") is None:
        pytest.skip(
            "the SLURM executor plugin is not installed: pip install -r requirements-slurm.txt"
        )
    folder = Path(tempfile.mkdtemp(prefix="lineload-slurm-"))
    folder.chmod(0o755)
    start = subprocess.run(
        ["bash", str(CLUSTER), "start", str(folder)], capture_output=True, text=True, timeout=600
    )
    if start.returncode == 77:
        pytest.skip(
            f"no SLURM cluster can be started here: {start.stderr.strip().splitlines()[-1]}"
        )
    assert start.returncode == 0, start.stderr[-3000:]
    os.environ["SLURM_CONF"] = str(folder / "etc" / "slurm.conf")
    try:
        yield folder
    finally:
        subprocess.run(
            ["bash", str(CLUSTER), "stop", str(folder)], capture_output=True, timeout=120
        )
        os.environ.pop("SLURM_CONF", None)
        shutil.rmtree(folder, ignore_errors=True)


def profile_for(cluster_folder, destination):
    """The repository's profile with this cluster's partition, the one place the README
    says to set it; nothing else differs."""
    settings = yaml.safe_load(PROFILE.read_text(encoding="utf-8"))
    settings["default-resources"]["slurm_partition"] = "debug"
    destination.mkdir(parents=True)
    (destination / "config.yaml").write_text(yaml.safe_dump(settings), encoding="utf-8")
    return destination


def snakemake(*args, raw, results, timeout_s=BUILD_TIMEOUT_S):
    """Run Snakemake from the repository; on a hang kill its whole process group."""
    command = [  # --nolock: see conftest.run_snakemake (the repository's folder is shared)
        sys.executable, "-m", "snakemake", "--quiet", "reason", "--nolock", *args,
        "--config", f"raw_data={raw}", f"results={results}",
    ]  # fmt: skip
    process = subprocess.Popen(
        command, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True,
    )  # fmt: skip
    start = time.monotonic()
    try:
        output, _ = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        output, _ = process.communicate()
        raise AssertionError(f"no end after {timeout_s} s:\n{output[-3000:]}") from None
    assert process.returncode == 0, output[-4000:]
    return output, time.monotonic() - start


def cluster_jobs(output):
    """How many jobs the executor submitted to SLURM, from its log lines."""
    return len(re.findall(r"submitted with SLURM jobid", output))


def test_readme_slurm_command_gives_the_local_bytes(cluster, tmp_path, small_build):
    raw, local = small_build  # the local build, shared with other tests
    expected = build_outputs(local)
    profile = profile_for(cluster, tmp_path / "profile")
    slurm = tmp_path / "slurm" / "results"  # the local folder's name: outputs compare
    # the profile's polling (5 s, for a shared cluster) made shorter for a test's own one
    polling = ("--seconds-between-status-checks", "1")
    polling += ("--slurm-init-seconds-before-status-checks", "1")
    output, seconds = snakemake("--profile", str(profile), *polling, raw=raw, results=slurm)
    submitted = cluster_jobs(output)
    assert submitted > 0, output[-3000:]  # the jobs really went through SLURM
    assert build_outputs(slurm) == expected
    print(f"default target on SLURM: {seconds:.1f} s, {submitted} SLURM jobs")


def two_pair_photographs(folder):
    """The photograph example's first monkey alone (data/photographs): two pairs, at 1
    and 2 mm, with their truth, so the digitise rule runs."""
    import pandas as pd

    shutil.copytree(REPO / "data" / "photographs", folder)
    for name in ("subjects.csv", "images/images.csv", "images/truth.csv"):
        table = pd.read_csv(folder / name)
        table[table["subject"] == "M1"].to_csv(folder / name, index=False)
    for image in (folder / "images").glob("M2_*"):
        image.unlink()
    return folder


def test_photographs_digitised_on_slurm_give_the_local_bytes(cluster, tmp_path):
    """The digitise rule (never reached by the shipped data, which have no photographs)
    through the SLURM profile: the raw-data check reads both pairs, one digitise job
    reads them again; its readings, quality record and figures equal a local run's."""
    from lineload.runtime.batches import batches

    raw = two_pair_photographs(tmp_path / "photographs")
    config = ("--configfile", str(REPO / "config" / "photographs.yaml"))
    (batch,) = batches(["M1"])  # one subject: one batch, whatever its size
    suffixes = ("csv", "json", "pdf", "png")
    local = tmp_path / "local" / "results"
    targets = [str(local / "digitised" / f"{batch}.{s}") for s in suffixes]
    started = time.monotonic()
    done = run_snakemake(*targets, *config, raw=raw, results=local)  # --configfile: last
    assert done.returncode == 0, done.stderr[-3000:]
    local_seconds = time.monotonic() - started
    profile = profile_for(cluster, tmp_path / "profile")
    slurm = tmp_path / "slurm" / "results"
    polling = ("--seconds-between-status-checks", "1")
    polling += ("--slurm-init-seconds-before-status-checks", "1")
    targets = [str(slurm / "digitised" / f"{batch}.{s}") for s in suffixes]
    output, seconds = snakemake(
        "--profile", str(profile), *polling, *targets, *config, raw=raw, results=slurm
    )
    submitted = cluster_jobs(output)
    assert submitted >= 3, output[-3000:]  # both checks and the digitise job
    expected = build_outputs(local)
    assert any(path.startswith("digitised/") for path in expected)
    assert build_outputs(slurm) == expected
    print(
        f"two photograph pairs digitised on SLURM: {seconds:.1f} s, {submitted} SLURM jobs "
        f"(locally {local_seconds:.1f} s)"
    )
