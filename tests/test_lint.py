"""The linters CI runs: Snakemake's own lint, snakefmt and ruff, all clean."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

BIN = Path(sys.executable).parent


def run(*command):
    return subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)


@pytest.mark.e2e
def test_snakemake_lint_reports_nothing():
    process = run(sys.executable, "-m", "snakemake", "--lint")
    output = process.stdout + process.stderr
    assert process.returncode == 0, output
    assert "Lints for" not in output, output


def test_snakefmt_has_nothing_to_change():
    process = run(str(BIN / "snakefmt"), "--check", "workflow/Snakefile", "workflow/rules")
    assert process.returncode == 0, process.stdout + process.stderr


def test_ruff_check_and_format():
    check = run(str(BIN / "ruff"), "check", "workflow", "tests")
    assert check.returncode == 0, check.stdout + check.stderr
    form = run(str(BIN / "ruff"), "format", "--check", "workflow", "tests")
    assert form.returncode == 0, form.stdout + form.stderr


def rule_graph(dot_text):
    """The rules and arrows of Snakemake's DOT output, as names (its node numbers and the
    order of its lines vary from run to run)."""
    labels = dict(re.findall(r'^\s*(\d+)\[label = "([^"]+)"', dot_text, re.M))
    edges = re.findall(r"^\s*(\d+) -> (\d+)", dot_text, re.M)
    return set(labels.values()), {(labels[a], labels[b]) for a, b in edges}


@pytest.mark.e2e
def test_committed_rule_graph_matches_the_workflow(tmp_path):
    # docs/rulegraph.png (shown in the README) is drawn from docs/rulegraph.dot by
    # docs/rulegraph.sh; a rule added or rewired without redrawing them fails here
    env = {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ['PATH']}"}
    process = subprocess.run(
        ["bash", str(REPO / "docs" / "rulegraph.sh"), str(tmp_path)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert process.returncode == 0, process.stderr
    current = rule_graph((tmp_path / "rulegraph.dot").read_text())
    committed = rule_graph((REPO / "docs" / "rulegraph.dot").read_text())
    assert current == committed, "redraw it: bash docs/rulegraph.sh"
    assert len(current[1]) >= len(current[0]) - 2  # a connected graph, not a list of rules
    assert (tmp_path / "rulegraph.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_github_workflow_is_valid():
    # check-jsonschema validates against GitHub's own workflow schema, shipped with it
    workflows = sorted((REPO / ".github" / "workflows").glob("*.yml"))
    assert workflows
    command = [str(BIN / "check-jsonschema"), "--builtin-schema", "vendor.github-workflows"]
    process = run(*command, *(str(w) for w in workflows))
    assert process.returncode == 0, process.stdout + process.stderr


def test_github_workflow_check_can_fail(tmp_path):
    # the same check on a workflow with a misspelt key fails (the check is not a no-op)
    broken = tmp_path / "broken.yml"
    text = (REPO / ".github" / "workflows" / "ci.yml").read_text()
    broken.write_text(text.replace("runs-on:", "runs_on:"))
    command = [str(BIN / "check-jsonschema"), "--builtin-schema", "vendor.github-workflows"]
    process = run(*command, str(broken))
    assert process.returncode != 0 and "runs-on" in process.stdout + process.stderr


def test_github_workflow_passes_zizmor_offline(tmp_path):
    # zizmor's security audits (no network: --offline): least privilege, pinned actions,
    # no persisted credentials...
    workflows = sorted((REPO / ".github" / "workflows").glob("*.yml"))
    process = run(str(BIN / "zizmor"), "--offline", *(str(w) for w in workflows))
    assert process.returncode == 0, process.stdout + process.stderr
    # ... and it can fail: the same workflow with an action on a movable tag does
    broken = tmp_path / "broken.yml"
    text = (REPO / ".github" / "workflows" / "ci.yml").read_text()
    broken.write_text(re.sub(r"actions/checkout@[0-9a-f]{40}", "actions/checkout@v4", text))
    process = run(str(BIN / "zizmor"), "--offline", str(broken))
    assert process.returncode != 0 and "unpinned" in process.stdout + process.stderr
