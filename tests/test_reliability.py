"""After a plain rerun nothing is missing or wrong: deleted intermediates come back, odd
labels and notices build, and a reviewer can check the raw files against the record."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import (
    SMALL_BATCH,
    copy_build,
    job_params,
    run_snakemake,
    without_log_hashes,
    write_small_dataset,
)
from lineload.publishing.provenance import verify

pytestmark = pytest.mark.e2e

NOT_COMPARED = {"logs", "benchmarks"}


def outputs(results):
    """Every output but those NOT_COMPARED; the crate without its logs' hashes (a rerun
    job writes its log anew, naming this copy's folders)."""
    found = {
        path.relative_to(results).as_posix(): path.read_bytes()
        for path in sorted(results.rglob("*"))
        if path.is_file() and path.relative_to(results).parts[0] not in NOT_COMPARED
    }
    if "ro-crate-metadata.json" in found:
        found["ro-crate-metadata.json"] = without_log_hashes(found["ro-crate-metadata.json"])
    return found


def check_ok(process):
    assert process.returncode == 0, (process.stdout + process.stderr)[-4000:]


def test_deleted_intermediates_are_rebuilt_by_a_plain_rerun(tmp_path, small_build):
    # a copy of a whole build (times kept), in a results folder of its own
    raw, results = copy_build(*small_build, tmp_path)
    before = outputs(results)
    # the files the README sends reviewers to, deleted one at a time and together
    intermediates = [
        f"fits/{SMALL_BATCH}.csv",
        f"data/averaged/{SMALL_BATCH}.csv",
        f"data/converted/{SMALL_BATCH}.csv",
        f"fits/sensitivity/{SMALL_BATCH}.csv",
        f"fits/checks/{SMALL_BATCH}.csv",
    ]
    for name in intermediates:
        (results / name).unlink()
    check_ok(run_snakemake(raw=raw, results=results))
    assert outputs(results) == before


LABEL = """{brace} "double" 'single' `tick` $HOME --flag"""
NOTICE = """--notice {x} `y` "z" 'w' $PATH"""


def test_labels_and_notices_with_awkward_characters_build(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    sheet = raw / "subjects.csv"
    lines = sheet.read_text().splitlines()
    # the label column holds text: quote it as a CSV cell (the quotes inside doubled)
    lines[1] = ",".join(lines[1].split(",")[:3]) + ',"' + LABEL.replace('"', '""') + '"'
    sheet.write_text("\n".join(lines) + "\n")
    results = tmp_path / "out"
    check_ok(run_snakemake(raw=raw, results=results, config=[f"data_notice={NOTICE}"]))
    spec = job_params(results / "logs" / "figure_fits.log")
    assert [LABEL] == [label for _, _, label in spec["subjects"] if label == LABEL]
    assert spec["settings"]["notice"] == NOTICE
    for table in ("claims.md", "fits.md", "summary.md"):
        assert (results / "tables" / table).read_text().rstrip().endswith(NOTICE), table
    assert (results / "figures" / "figure6.pdf").read_bytes().startswith(b"%PDF")


def test_verify_lists_raw_files_that_differ_from_the_record(tmp_path, small_build):
    # the raw folder and the record of a build, copied: the test changes raw files
    raw, results = copy_build(*small_build, tmp_path)
    record_path = results / "provenance.json"
    record = json.loads(record_path.read_text())
    # the raw folder lies outside the working folder: the record names it, so say where
    assert record["raw_data"]["folder"] == "raw"
    assert verify(record, raw) == []
    command = [str(Path(sys.executable).parent / "lineload-verify"), str(record_path)]
    command += ["--raw", str(raw)]
    clean = subprocess.run(command, capture_output=True, text=True)
    assert clean.returncode == 0 and "raw files match" in clean.stdout
    # a changed reading, a removed file and an added one are each named
    profile = raw / "profiles" / "MK.csv"
    profile.write_text(profile.read_text().replace("0.", "1.", 1))
    (raw / "profiles" / "HU.csv").unlink()
    (raw / "profiles" / "XX.csv").write_text("depth_mm\n")
    problems = verify(record, raw)
    assert f"differs from the record: {profile}" in problems
    assert f"missing: {raw / 'profiles' / 'HU.csv'}" in problems
    assert f"not in the record: {raw / 'profiles' / 'XX.csv'}" in problems
    changed = subprocess.run(command, capture_output=True, text=True)
    assert changed.returncode == 1 and "MK.csv" in changed.stdout
    elsewhere = subprocess.run(
        [*command[:-2], "--raw", str(tmp_path)], capture_output=True, text=True
    )
    assert elsewhere.returncode == 1 and "missing" in elsewhere.stdout
