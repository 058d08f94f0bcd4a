"""Project plumbing: pinned dependencies, documented columns, CI runs the README's tests."""

import re
from pathlib import Path

import yaml

from lineload.fitting import FIT_COLUMNS

REPO = Path(__file__).resolve().parents[1]


EDITABLE = "-e ."  # the project's own package, installed editable by both routes


def requirement_lines():
    lines = (REPO / "requirements.txt").read_text().splitlines()
    return [line for line in (ln.split("#")[0].strip() for ln in lines) if line]


def pins_from_requirements():
    return dict(line.split("==") for line in requirement_lines() if line != EDITABLE)


def test_requirements_are_all_pinned_and_install_the_package():
    lines = requirement_lines()
    assert EDITABLE in lines
    pins = [ln for ln in lines if ln != EDITABLE]
    assert all(re.fullmatch(r"[A-Za-z0-9_.\-\[\]]+==[0-9][A-Za-z0-9.]*", ln) for ln in pins)


def test_environment_pins_match_requirements():
    environment = yaml.safe_load((REPO / "environment.yml").read_text())
    pip_section = next(d["pip"] for d in environment["dependencies"] if isinstance(d, dict))
    assert EDITABLE in pip_section
    conda_pins = dict(item.split("==") for item in pip_section if item != EDITABLE)
    assert conda_pins == pins_from_requirements()
    assert "python=3.11" in environment["dependencies"]


def readme_block_after(marker):
    text = (REPO / "README.md").read_text()
    after = text[text.lower().index(marker.lower()) :]
    return re.search(r"```bash\n(.+?)\n```", after, re.S).group(1).strip()


def test_ci_runs_the_readme_test_command():
    test_command = readme_block_after("to run the tests")
    command = test_command.split("&&")[-1].strip()
    ci = (REPO / ".ci" / "run").read_text().splitlines()
    assert command in [line.strip() for line in ci]
    assert "-r requirements.txt" in (REPO / ".ci" / "run").read_text()


def test_readme_main_command_installs_and_builds():
    command = readme_block_after("On a fresh machine")
    assert "pip install -r requirements.txt" in command
    assert command.endswith("snakemake --cores 2")


def test_every_fit_column_is_in_the_data_dictionary():
    text = (REPO / "README.md").read_text()
    dictionary = text[text.index("## Data dictionary") :]
    documented = set(re.findall(r"^\| `([A-Za-z0-9_]+)` \|", dictionary, re.M))
    assert set(FIT_COLUMNS) <= documented


def schema_defaults(properties, prefix=""):
    """Every leaf key of the config schema with its default, as (dotted key, default)."""
    for key, rules in properties.items():
        if "properties" in rules:
            yield from schema_defaults(rules["properties"], f"{prefix}{key}.")
        else:
            yield f"{prefix}{key}", rules["default"]


def test_config_readme_documents_every_key_with_its_default():
    schema = yaml.safe_load((REPO / "workflow" / "schemas" / "config.schema.yaml").read_text())
    text = (REPO / "config" / "README.md").read_text()
    rows = dict(re.findall(r"^\| `(\w+)` \| [^|]* \| `([^`]*)` \|", text, re.M))
    for dotted, default in schema_defaults(schema["properties"]):
        key = dotted.split(".")[-1]
        assert key in rows, f"config/README.md does not document {dotted}"
        shown = "null" if default is None else str(default).replace("None", "null")
        assert rows[key] == shown, (dotted, rows[key], default)
    config = yaml.safe_load((REPO / "config" / "config.yaml").read_text())
    assert set(config) == set(schema["properties"])  # the shipped config sets every key


def test_the_species_are_named_once():
    # the schema of subjects.csv is data, so a test ties it to the one list in the package
    from lineload import paper

    schema = yaml.safe_load(
        (REPO / "workflow" / "schemas" / "subjects.schema.yaml").read_text(encoding="utf-8")
    )
    assert tuple(schema["properties"]["species"]["enum"]) == paper.SPECIES
