"""Settings: nested keys from the command line (numbers stay numbers), a lab's config
file, and the workflow run from any folder with -s or --directory."""

import json
import os
import re
import subprocess
import sys
import textwrap

import pandas as pd
import pytest

from conftest import REPO, job_params, run_snakemake, write_small_dataset
from lineload.runtime import batches
from lineload.runtime.settings import apply_command_line, typed_value


def snakemake_config(entries):
    """What Snakemake 9's own --config parser makes of KEY=VALUE words."""
    from snakemake.cli import parse_config

    return parse_config(entries)


@pytest.mark.parametrize(
    ("entries", "expected"),
    [
        (["figures={example_depth_mm: 1.25}"], {"figures": {"example_depth_mm": 1.25}}),
        (['figures={"example_depth_mm": 1.25}'], {"figures": {"example_depth_mm": 1.25}}),
        (["figures__example_depth_mm=1.25"], {"figures": {"example_depth_mm": 1.25}}),
        (["figures__outline_depth_mm=null"], {"figures": {"outline_depth_mm": None}}),
        (
            ["sensitivity={windows_mm: [2, 3.5, null]}"],
            {"sensitivity": {"windows_mm": [2, 3.5, None]}},
        ),
        (["figures__example_subjects=[M1, H2]"], {"figures": {"example_subjects": ["M1", "H2"]}}),
        (["data_notice=null"], {"data_notice": None}),
        (["fit_window_mm=2"], {"fit_window_mm": 2}),
        (["data_notice=Sample #3: a {draft}"], {"data_notice": "Sample #3: a {draft}"}),
        (["data_notice=Note: synthetic"], {"data_notice": "Note: synthetic"}),
        (["results=/tmp/out"], {"results": "/tmp/out"}),
    ],
)
def test_command_line_values_are_typed_as_in_a_config_file(entries, expected):
    config = snakemake_config(entries)
    assert apply_command_line(config, entries) == expected


def test_a_nested_value_keeps_the_other_keys_of_the_config_file():
    config = {"figures": {"example_depth_mm": None, "png_dpi": 300}, "results": "results"}
    entries = ["figures={example_depth_mm: 1.25}"]
    for key, value in snakemake_config(entries).items():  # as Snakemake merges them
        config[key] = {**config[key], **value}
    assert config["figures"]["example_depth_mm"] == "1.25"  # Snakemake's own reading
    apply_command_line(config, entries)
    assert config == {"figures": {"example_depth_mm": 1.25, "png_dpi": 300}, "results": "results"}
    apply_command_line(config, ["figures__png_dpi=600"])  # not in config as a flat key: kept
    assert config["figures"]["png_dpi"] == 300


def test_typed_value_keeps_text_that_is_not_a_mapping_or_list():
    assert typed_value("{a: [1, x]}", "as read") == {"a": [1, "x"]}
    assert typed_value("[unclosed", "as read") == "as read"
    assert typed_value("~", "~") is None
    assert typed_value("yes", "yes") == "yes"  # not YAML 1.1's True


@pytest.mark.e2e
@pytest.mark.parametrize(
    "setting",
    [
        "figures={example_depth_mm: 2, example_subjects: [MK]}",
        'figures={"example_depth_mm": 2, "example_subjects": ["MK"]}',
        "figures__example_depth_mm=2",
    ],
)
def test_nested_settings_reach_the_jobs_as_numbers(tmp_path, setting, snakemake_available):
    raw = write_small_dataset(tmp_path / "raw")
    out = tmp_path / "out"
    process = run_snakemake("figure_fits", raw=raw, results=out, config=[setting])
    assert process.returncode == 0, process.stderr[-3000:]
    spec = job_params(out / "logs" / "figure_fits.log")
    assert spec["settings"]["example_depth_mm"] == 2
    assert isinstance(spec["settings"]["example_depth_mm"], (int, float))
    # as configured: a list given is kept, none given stays empty (the job chooses then)
    assert spec["settings"]["example_subjects"] == (["MK"] if "MK" in setting else [])
    assert spec["dpi"] == 300  # the config file's other keys are kept


def snakemake_in(folder, *args):
    # the jobs printed (the default profile keeps the console quiet about them)
    command = [sys.executable, "-m", "snakemake", "--quiet", "reason", "--cores", "1", *args]
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run(command, cwd=folder, capture_output=True, text=True, env=env)


@pytest.mark.e2e
def test_the_workflow_runs_from_another_folder_with_s(tmp_path, snakemake_available):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    snakefile = str(REPO / "workflow" / "Snakefile")
    process = snakemake_in(elsewhere, "-s", snakefile, "-n")
    assert process.returncode == 0, process.stderr[-3000:]
    # the workflow's own config and shipped data are found: the fit jobs of its batches
    job = r"^rule fit_models:\n(?:    .*\n)*?    wildcards: batch=(\S+)$"
    found = re.findall(job, process.stdout + process.stderr, re.M)
    subjects = pd.read_csv(REPO / "data" / "raw" / "subjects.csv")["subject"].tolist()
    assert sorted(found) == sorted(batches.batches(subjects))
    # results go where it runs; the job's values never hold the checkout's path
    process = snakemake_in(elsewhere, "-s", snakefile, "check")
    assert process.returncode == 0, process.stderr[-3000:]
    check = job_params(elsewhere / "results" / "logs" / "check_raw_data.log")
    assert check["window_mm"] == 3.0 and str(REPO) not in json.dumps(check)


def readme_lab_config():
    """The lab config file shown in data/README.md's "Start here" steps."""
    text = (REPO / "data" / "README.md").read_text()
    block = re.search(
        r"```yaml\n(.+?)\n *```", text[text.index("Write a small config file") :], re.S
    )
    return textwrap.dedent(block.group(1))  # the block is indented under a list item


@pytest.mark.e2e
@pytest.mark.parametrize("how", ["-s from the lab folder", "--directory from the repository"])
def test_the_readme_lab_config_runs(tmp_path, how, snakemake_available):
    """data/README.md's steps: a small --configfile next to the lab's raw folder."""
    lab = tmp_path / "mylab"
    write_small_dataset(
        lab / "raw",
        subjects={
            "S-01": ("monkey", [0.75, 1.25, 1.75], 5.0),
            "S-02": ("human", [0.75, 1.25, 1.75], 9.0),
        },
    )
    (lab / "lab.yaml").write_text(readme_lab_config())
    snakefile = str(REPO / "workflow" / "Snakefile")
    if how.startswith("-s"):
        folder, args = lab, ["-s", snakefile, "--configfile", "lab.yaml"]
    else:
        folder = tmp_path
        args = ["--directory", "mylab", "--configfile", "mylab/lab.yaml", "-s", snakefile]
    process = snakemake_in(folder, "fits", "figure_fits", *args)
    assert process.returncode == 0, process.stderr[-3000:]
    assert (lab / "results" / "tables" / "fits.csv").is_file()
    # the jobs were given the config as the lab wrote it, the rest from the workflow's
    logs = lab / "results" / "logs"
    check = (logs / "check_raw_data.log").read_text()
    assert "\nraw: 2 subjects" in check  # relative to the lab folder, where it runs
    assert job_params(logs / "check_raw_data.log")["input_checks"]["depth_max_mm"] == 3.0
    figures = job_params(logs / "figure_fits.log")
    assert figures["settings"]["example_subjects"] == ["S-01", "S-02"]
    assert figures["dpi"] == 300  # the rest from the workflow's config
