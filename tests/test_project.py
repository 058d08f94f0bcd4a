"""Project plumbing: pinned dependencies, documented columns, CI runs the README's tests."""

import json
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml

from lineload.fitting.batch import FIT_COLUMNS
from lineload.publishing.citation import read_citation, zenodo_json

REPO = Path(__file__).resolve().parents[1]
#: The test environment's own programs (check-jsonschema), beside its Python.
BIN = Path(sys.executable).parent


EDITABLE = "-e ."  # the project's own package, installed editable by both routes


def requirement_lines(name="requirements.txt"):
    lines = (REPO / name).read_text().splitlines()
    return [line for line in (ln.split("#")[0].strip() for ln in lines) if line]


def pins(lines):
    return dict(line.split("==") for line in lines if "==" in line)


def pins_from_requirements():
    return pins(requirement_lines())


def test_requirements_are_all_pinned_and_install_the_package():
    lines = requirement_lines()
    assert EDITABLE in lines
    dev = requirement_lines("requirements-dev.txt")
    assert dev[0] == "-r requirements.txt"
    for pinned in ([ln for ln in lines if ln != EDITABLE], dev[1:]):
        assert all(re.fullmatch(r"[A-Za-z0-9_.\-\[\]]+==[0-9][A-Za-z0-9.]*", ln) for ln in pinned)


def test_environment_pins_match_requirements():
    environment = yaml.safe_load((REPO / "environment.yml").read_text())
    pip_section = next(d["pip"] for d in environment["dependencies"] if isinstance(d, dict))
    assert EDITABLE in pip_section
    conda_pins = dict(item.split("==") for item in pip_section if item != EDITABLE)
    assert conda_pins == pins_from_requirements()
    assert "python=3.11" in environment["dependencies"]


def test_package_pins_match_requirements():
    # pip install . installs what requirements.txt pins; its extras what requirements-dev.txt adds
    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert pins(project["dependencies"]) == pins_from_requirements()
    extras = project["optional-dependencies"]
    assert "lineload[test]" in extras["dev"]
    assert pins(extras["test"] + extras["dev"]) == pins(requirement_lines("requirements-dev.txt"))
    # a run needs none of the development tools
    development = {"pytest", "ruff", "snakefmt", "playwright", "roc-validator", "zizmor"}
    assert not development & set(pins_from_requirements())


def readme_block_after(marker):
    text = (REPO / "README.md").read_text()
    after = text[text.lower().index(marker.lower()) :]
    return re.search(r"```bash\n(.+?)\n```", after, re.S).group(1).strip()


def test_ci_runs_the_readme_test_command():
    test_command = readme_block_after("to run the tests")
    command = test_command.split("&&")[-1].strip()
    ci = (REPO / ".ci" / "run").read_text().splitlines()
    assert command in [line.strip() for line in ci]
    # CI runs the whole suite: it installs what development needs (the run's pins with it)
    assert "-r requirements-dev.txt" in (REPO / ".ci" / "run").read_text()


def test_readme_main_command_installs_and_builds():
    command = readme_block_after("On a fresh machine")
    assert "pip install -r requirements.txt" in command
    assert command.endswith("snakemake --cores 2")


def test_every_fit_column_is_in_the_data_dictionary():
    text = (REPO / "docs" / "outputs.md").read_text()
    dictionary = text[text.index("## `results/tables/fits.csv`") :]
    documented = set(re.findall(r"^\| `([A-Za-z0-9_]+)` \|", dictionary, re.M))
    assert set(FIT_COLUMNS) <= documented


CONFIG_SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"
#: What the shipped config states although the schema has a default for it: the two
#: folders a run points at, the first keys a lab changes.
POINTED_AT = {"raw_data", "results"}


def schema_defaults(properties, prefix=""):
    """Every leaf key of the config schema with its default, as (dotted key, default)."""
    for key, rules in properties.items():
        if "properties" in rules:
            yield from schema_defaults(rules["properties"], f"{prefix}{key}.")
        else:
            yield f"{prefix}{key}", rules["default"]


def leaves(config, prefix=""):
    """Every leaf of a config as (dotted key, value)."""
    for key, value in config.items():
        if isinstance(value, dict):
            yield from leaves(value, f"{prefix}{key}.")
        else:
            yield f"{prefix}{key}", value


def restated_defaults(config, schema):
    """The keys of ``config`` that only repeat the schema's default (the folders aside)."""
    defaults = dict(schema_defaults(schema["properties"]))
    return sorted(
        key
        for key, value in leaves(config)
        if key not in POINTED_AT and key in defaults and value == defaults[key]
    )


def test_config_readme_tables_are_generated_from_the_schema():
    from lineload.publishing.configdoc import updated_readme

    schema = yaml.safe_load(CONFIG_SCHEMA.read_text())
    text = (REPO / "config" / "README.md").read_text()
    assert updated_readme(text, schema) == text, (
        "config/README.md is out of date: python -m lineload.publishing.configdoc config/README.md"
    )
    # every key is there with the schema's default
    rows = re.findall(r"^\| `(\w+)` \| [^|]* \| `([^`]*)` \|", text, re.M)
    assert len(rows) == len(list(schema_defaults(schema["properties"])))
    shown = dict(rows)
    for dotted, default in schema_defaults(schema["properties"]):
        key = dotted.split(".")[-1]
        expected = "null" if default is None else str(default).replace("None", "null")
        assert shown[key] == expected, (dotted, shown[key], default)
    # and a changed default makes the page out of date
    schema["properties"]["fit_window_mm"]["default"] = 2.5
    assert updated_readme(text, schema) != text


@pytest.mark.parametrize("name", ["config.yaml", "photographs.yaml"])
def test_shipped_configs_state_only_what_the_schema_does_not(name):
    schema = yaml.safe_load(CONFIG_SCHEMA.read_text())
    config = yaml.safe_load((REPO / "config" / name).read_text())
    known = dict(schema_defaults(schema["properties"]))
    assert POINTED_AT <= set(config)
    assert {key for key, _ in leaves(config)} <= set(known)
    assert restated_defaults(config, schema) == []
    # the check can fail: a default typed again is named
    assert restated_defaults({**config, "figures": {"png_dpi": 300}}, schema) == ["figures.png_dpi"]
    assert restated_defaults({**config, "figures": {"png_dpi": 600}}, schema) == []


def test_the_species_are_named_once():
    # the schema of subjects.csv is data, so a test ties it to the one list in the package
    from lineload import paper

    schema = yaml.safe_load(
        (REPO / "workflow" / "schemas" / "subjects.schema.yaml").read_text(encoding="utf-8")
    )
    assert tuple(schema["properties"]["species"]["enum"]) == paper.SPECIES


# ---------------------------------------------------------------- citation metadata


def test_citation_file_follows_the_citation_file_format_schema():
    # check-jsonschema carries the CFF 1.2.0 schema itself: no network
    command = [str(BIN / "check-jsonschema"), "--builtin-schema", "vendor.citation-file-format"]
    done = subprocess.run([*command, str(REPO / "CITATION.cff")], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_citation_check_can_fail(tmp_path):
    broken = tmp_path / "CITATION.cff"
    text = (REPO / "CITATION.cff").read_text()
    broken.write_text(text.replace("date-released: ", "date-released: not-a-date-"))
    command = [str(BIN / "check-jsonschema"), "--builtin-schema", "vendor.citation-file-format"]
    done = subprocess.run([*command, str(broken)], capture_output=True, text=True)
    assert done.returncode != 0 and "date-released" in done.stdout + done.stderr


def test_zenodo_metadata_is_the_citation_files():
    """.zenodo.json is generated from CITATION.cff (python -m lineload.publishing.citation)."""
    citation = read_citation(REPO / "CITATION.cff")
    assert (REPO / ".zenodo.json").read_text() == zenodo_json(citation)
    zenodo = json.loads((REPO / ".zenodo.json").read_text())
    assert zenodo["version"] == citation["version"]
    assert zenodo["publication_date"] == citation["date-released"]
    assert [c["name"] for c in zenodo["creators"]] == [a["name"] for a in citation["authors"]]


def test_zenodo_metadata_follows_a_changed_citation(tmp_path):
    changed = tmp_path / "CITATION.cff"
    text = (REPO / "CITATION.cff").read_text()
    changed.write_text(
        text.replace("version: ", "version: 9.").replace(
            "  - name: The lineload contributors\n",
            "  - family-names: Doe\n    given-names: Ada\n    orcid: https://orcid.org/0000-0002-1825-0097\n",
        )
    )
    zenodo = json.loads(zenodo_json(read_citation(changed)))
    assert zenodo["version"].startswith("9.")
    assert zenodo["creators"] == [{"name": "Doe, Ada", "orcid": "0000-0002-1825-0097"}]
    assert zenodo_json(read_citation(changed)) != (REPO / ".zenodo.json").read_text()


def test_changelog_names_the_citation_files_version_and_date():
    citation = read_citation(REPO / "CITATION.cff")
    changelog = (REPO / "CHANGELOG.md").read_text()
    assert "## [Unreleased]" in changelog
    assert f"## [{citation['version']}] - {citation['date-released']}" in changelog


def test_a_broken_citation_file_is_named(tmp_path):
    broken = tmp_path / "CITATION.cff"
    broken.write_text("title: [unclosed\n")
    with pytest.raises(ValueError, match=r"CITATION\.cff: not valid YAML"):
        read_citation(broken)
    broken.write_text("title: x\n")
    with pytest.raises(ValueError, match="no version"):
        read_citation(broken)


def test_a_copy_without_the_citation_file_names_the_package(tmp_path):
    """A workflow deployed as workflow/ and config/ alone has no CITATION.cff: the
    package's name and version stand in, and no date, licence or author is claimed."""
    from importlib import metadata

    from lineload.publishing.citation import citation_or_default

    fallback = citation_or_default([])
    assert fallback["title"] == "lineload"
    assert fallback["version"] == metadata.version("lineload")
    assert "date-released" not in fallback and "license" not in fallback
    assert not fallback["authors"]
    assert citation_or_default(tmp_path / "CITATION.cff") == fallback  # a path not there
    assert citation_or_default(REPO / "CITATION.cff") == read_citation(REPO / "CITATION.cff")
