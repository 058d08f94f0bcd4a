"""Settings: nested keys from the command line (numbers stay numbers), a lab's config
file, and the workflow run from any folder with -s or --directory."""

import json
import os
import subprocess
import sys

import pytest
import yaml

from conftest import REPO, run_snakemake, write_small_dataset
from lineload.settings import apply_command_line, typed_value


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
    process = run_snakemake("figure_fits", "-n", raw=raw, results=out, config=[setting])
    assert process.returncode == 0, process.stderr[-3000:]
    spec = json.loads((out / "specs" / "figure_fits" / "all.json").read_text())
    assert spec["settings"]["example_depth_mm"] == 2
    assert isinstance(spec["settings"]["example_depth_mm"], (int, float))
    assert spec["settings"]["example_subjects"] == ["MK"]
    assert spec["dpi"] == 300  # the config file's other keys are kept


def snakemake_in(folder, *args):
    command = [sys.executable, "-m", "snakemake", "--cores", "1", *args]
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run(command, cwd=folder, capture_output=True, text=True, env=env)


@pytest.mark.e2e
def test_the_workflow_runs_from_another_folder_with_s(tmp_path, snakemake_available):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    process = snakemake_in(elsewhere, "-s", str(REPO / "workflow" / "Snakefile"), "-n", "fits")
    assert process.returncode == 0, process.stderr[-3000:]
    # the workflow's own config and shipped data are found; results go where it runs
    specs = sorted(p.name for p in (elsewhere / "results" / "specs" / "fit_models").iterdir())
    assert specs == sorted(f"{s}.json" for s in ("M1", "M2", "M3", "M4", "H1", "H2", "H3"))
    provenance = json.loads(
        (elsewhere / "results" / "specs" / "provenance" / "all.json").read_text()
    )
    assert provenance["raw_dir"] == str(REPO / "data" / "raw")


@pytest.mark.e2e
def test_a_lab_config_file_from_another_folder(tmp_path, snakemake_available):
    """The data/README.md example: a small --configfile next to the lab's raw folder."""
    lab = tmp_path / "lab"
    write_small_dataset(lab / "raw")
    (lab / "lab.yaml").write_text(
        yaml.safe_dump(
            {"raw_data": "raw", "results": "results", "figures": {"example_depth_mm": 2.0}}
        )
    )
    work = tmp_path / "work"
    work.mkdir()
    process = snakemake_in(
        work,
        "fits",
        "-s",
        str(REPO / "workflow" / "Snakefile"),
        "--directory",
        str(lab),
        "--configfile",
        str(lab / "lab.yaml"),
    )
    assert process.returncode == 0, process.stderr[-3000:]
    assert (lab / "results" / "tables" / "fits.csv").is_file()
    assert not (work / "results").exists()
    spec = json.loads((lab / "results" / "specs" / "provenance" / "all.json").read_text())
    assert spec["raw_dir"] == "raw"
    assert spec["config"]["figures"]["example_depth_mm"] == 2.0
    assert spec["config"]["figures"]["png_dpi"] == 300  # the rest from the workflow's config
