"""The linters CI runs: Snakemake's own lint, snakefmt and ruff, all clean."""

import subprocess
import sys
from pathlib import Path

from conftest import REPO

BIN = Path(sys.executable).parent


def run(*command):
    return subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=300)


def test_snakemake_lint_reports_nothing():
    process = run(sys.executable, "-m", "snakemake", "--lint")
    output = process.stdout + process.stderr
    assert process.returncode == 0, output
    assert "Lints for" not in output, output


def test_snakefmt_has_nothing_to_change():
    process = run(str(BIN / "snakefmt"), "--check", "Snakefile", "workflow/rules")
    assert process.returncode == 0, process.stdout + process.stderr


def test_ruff_check_and_format():
    check = run(str(BIN / "ruff"), "check", "workflow", "tests")
    assert check.returncode == 0, check.stdout + check.stderr
    form = run(str(BIN / "ruff"), "format", "--check", "workflow", "tests")
    assert form.returncode == 0, form.stdout + form.stderr


def test_committed_rule_graph_matches_the_workflow():
    # docs/rulegraph.png (shown in the README) is drawn from docs/rulegraph.dot;
    # a rule added or rewired without regenerating them fails here
    from lineload.rulegraph import parse_rulegraph

    process = run(sys.executable, "-m", "snakemake", "--rulegraph", "dot", "--quiet", "all")
    assert process.returncode == 0, process.stderr
    current = parse_rulegraph(process.stdout)
    committed = parse_rulegraph((REPO / "docs" / "rulegraph.dot").read_text())
    regenerate = "snakemake --cores 2 rulegraph; cp results/rulegraph/rulegraph.* docs/"
    assert (sorted(current[0]), current[1]) == (sorted(committed[0]), committed[1]), regenerate
