"""A checkout can move: params and outputs hold values, never the checkout's absolute path."""

import os
import shutil
import subprocess
import sys

import pytest

from conftest import copy_checkout


def snakemake_in(checkout, *args):
    """Snakemake run in ``checkout`` with the science package of that checkout."""
    env = {
        **os.environ,
        "PYTHONPATH": str(checkout / "workflow"),
        "PYTHONDONTWRITEBYTECODE": "1",
    }
    command = [sys.executable, "-m", "snakemake", "--cores", "2", *args]
    return subprocess.run(command, cwd=checkout, capture_output=True, text=True, env=env)


#: The raw and results folders inside the checkout, named relative to it.
CONFIG = ("--config", "raw_data=raw", "results=results")


@pytest.mark.e2e
def test_a_moved_or_copied_checkout_has_nothing_to_rerun(tmp_path, checkout_build):
    first, results = checkout_build
    # no spec and no output names the checkout: folders are relative to the working folder
    for path in results.rglob("*"):
        if path.is_file():
            assert str(first).encode() not in path.read_bytes(), path

    # the whole checkout, build state included, copied with its times (the shared
    # build stays where it is), and that copy moved on
    copied = tmp_path / "elsewhere" / "deeper" / "copy"
    shutil.copytree(first, copied, symlinks=True)
    nothing_to_rerun(copied)
    moved = copied.rename(tmp_path / "moved")
    nothing_to_rerun(moved)


def nothing_to_rerun(checkout):
    dry = snakemake_in(checkout, "--dry-run", *CONFIG)
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert "Nothing to be done" in dry.stdout + dry.stderr, dry.stdout[-3000:]


@pytest.mark.e2e
def test_lint_writes_nothing(tmp_path, snakemake_available):
    fresh = copy_checkout(tmp_path / "fresh")

    def files():
        return {
            p.relative_to(fresh).as_posix()
            for p in fresh.rglob("*")
            if ".snakemake" not in p.relative_to(fresh).parts
        }

    before = files()
    lint = snakemake_in(fresh, "--lint")
    assert lint.returncode == 0, lint.stdout + lint.stderr
    assert files() == before
    # nor does a dry run (the jobs' values are params, no files); a file the run wrote
    # would be seen, as one planted here is
    dry = snakemake_in(fresh, "--dry-run")
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert files() == before
    (fresh / "results").mkdir(exist_ok=True)
    (fresh / "results" / "planted.json").write_text("{}")
    assert files() - before == {"results", "results/planted.json"} - before
