"""The claims registry: complete, consistent with the code, the schema, the calibration,
the generator's list and the article, and refusing an entry that is not."""

import ast
import inspect
import json
import re
import textwrap
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import REPO, reading_grid_mm
from lineload.averaging import AVERAGED_COLUMNS
from lineload.claims import CLAIM_FUNCTIONS, ClaimSettings, compute_claims, registry
from lineload.claims.registry import (
    CLAIMS,
    FAMILIES,
    SETTINGS,
    check_claims,
    claim_named,
    claims_needing,
    claims_using,
)
from lineload.claims.verdicts import KINDS
from lineload.fitting.batch import FIT_COLUMNS, fit_trial
from lineload.simulation import calibration

#: Claim ids written out in a list ('C2, C3', 'C4 and C9'): only the registry may hold one.
ID_LIST = re.compile(r"\bC\d+'?s?,? (?:and )?C\d+\b")


def settings_read(function):
    """The registry's settings a function (or a source text) reads itself
    (``settings.<name>`` in its body)."""
    source = function if isinstance(function, str) else inspect.getsource(function)
    tree = ast.parse(textwrap.dedent(source))
    read = {
        node.attr
        for node in ast.walk(tree)
        if isinstance(node, ast.Attribute)
        and isinstance(node.value, ast.Name)
        and node.value.id == "settings"
    }
    return read & set(SETTINGS)


@pytest.fixture(scope="module")
def demo_fits_averaged():
    """A fit table and averaged points of two monkey trials (the workflow's own fits)."""
    distance_mm = reading_grid_mm(8.0)
    rows, frames = [], []
    for depth_mm in (0.5, 1.0):
        w = depth_mm * np.clip(1.0 - distance_mm / 5.0, 0.0, None) ** 2
        frame = pd.DataFrame(
            {
                "subject": "MK",
                "depth_mm": depth_mm,
                "distance_mm": distance_mm,
                "left_mm": w,
                "right_mm": w,
                "left_source": "measured",
                "right_source": "measured",
                "deflection_mm": w,
                "n_sides": 2,
            }
        )
        frames.append(frame[AVERAGED_COLUMNS])
        fit = fit_trial(distance_mm, w, depth_mm, 3.0)
        rows.append({"subject": "MK", "species": "monkey", **fit})
    return pd.DataFrame(rows, columns=FIT_COLUMNS), pd.concat(frames, ignore_index=True)


def test_every_claim_has_a_function_kind_text_and_rule():
    check_claims(CLAIMS)  # imports every function
    assert list(CLAIM_FUNCTIONS) == [claim.id for claim in CLAIMS]
    for claim in CLAIMS:
        assert claim.kind in KINDS
        assert claim.statement and claim.location and claim.paper_value
        # the rule in one sentence
        assert claim.rule.endswith(".") and claim.rule.count(". ") == 0, claim.id
        assert CLAIM_FUNCTIONS[claim.id].__name__ == claim.function
        assert CLAIM_FUNCTIONS[claim.id].__module__ == claim.import_path


def test_the_table_has_one_row_per_entry_with_its_text(demo_fits_averaged):
    fits, averaged = demo_fits_averaged
    table = compute_claims(fits, averaged, ClaimSettings(noise_mm=0.005))
    assert table["claim"].tolist() == [claim.id for claim in CLAIMS]
    for claim, (_, row) in zip(CLAIMS, table.iterrows(), strict=True):
        assert (row["statement"], row["paper_location"], row["paper_value"]) == (
            claim.statement,
            claim.location,
            claim.paper_value,
        )
        assert row["kind"] == claim.kind


@pytest.mark.parametrize("claim", CLAIMS, ids=lambda c: c.id)
def test_each_entry_names_the_settings_its_rule_reads(claim):
    assert settings_read(CLAIM_FUNCTIONS[claim.id]) == set(claim.settings)


def test_the_coordinates_figures_caption_names_the_claims_judged_both_ways():
    # a static caption of the report: checked against the registry, not generated
    caption = (REPO / "workflow/report/supplement_coordinates.rst").read_text()
    assert set(re.findall(r"\bC\d+\b", caption)) == set(claims_needing("coordinates"))


def test_the_claims_judged_in_both_coordinates_read_the_fits_in_measured_ones():
    for claim in CLAIMS:
        if "coordinates" in claim.needs:
            source = inspect.getsource(CLAIM_FUNCTIONS[claim.id])
            assert "PAPER_FIT" in source and ("shifted" in source or "CONSISTENT_FITS" in source)


def reads_averaged(function):
    """Whether a function's body uses its ``averaged`` argument."""
    (definition,) = ast.parse(textwrap.dedent(inspect.getsource(function))).body
    return any(
        isinstance(node, ast.Name) and node.id == "averaged"
        for statement in definition.body
        for node in ast.walk(statement)
    )


@pytest.mark.parametrize("claim", CLAIMS, ids=lambda c: c.id)
def test_each_entry_needs_the_averaged_points_exactly_when_its_function_reads_them(claim):
    assert reads_averaged(CLAIM_FUNCTIONS[claim.id]) == ("averaged" in claim.needs)


def test_the_settings_check_can_fail():
    c9 = claim_named("C9")
    assert settings_read(CLAIM_FUNCTIONS["C9"]) != set(
        replace(c9, settings=("significance",)).settings
    )


def test_the_registrys_settings_are_the_schemas_and_the_settings_object():
    schema = yaml.safe_load((REPO / "workflow/schemas/config.schema.yaml").read_text())
    claims_keys = schema["properties"]["claims"]["properties"]
    in_schema = {
        **claims_keys,
        "force_sd_N": schema["properties"]["mechanics"]["properties"]["force_sd_N"],
    }
    assert set(SETTINGS) <= set(in_schema)
    assert set(SETTINGS) <= {f.name for f in fields(ClaimSettings)}
    for setting in SETTINGS:
        users = claims_using(setting)
        assert users, f"{setting} is read by no claim"
        text = in_schema[setting]["description"]
        named = set(re.findall(r"\bC\d+\b", text))
        if len(users) == 1:
            # a setting of one claim names it
            assert users[0] in named, setting
        else:
            # a setting of many names none of them: the registry lists them
            assert not named, (setting, named)


def test_no_list_of_claim_ids_is_typed_outside_the_registry():
    for path in (
        "workflow/schemas/config.schema.yaml",
        "workflow/article/reproduction.typ",
        "workflow/lineload/claims/settings.py",
        "workflow/lineload/claims/table.py",
        "workflow/lineload/claims/__init__.py",
        "workflow/lineload/claims/rows.py",
    ):
        found = ID_LIST.findall((REPO / path).read_text())
        assert not found, (path, found)
    # the pattern finds a list where there is one
    assert ID_LIST.findall("the tests of C2, C3, C5 and C11") == ["C2, C3", "C5 and C11"]
    assert ID_LIST.findall("the thresholds of C4 and C9") == ["C4 and C9"]


def test_the_calibrations_worlds_are_the_registrys():
    worlds = {world: entry[0] for world, entry in calibration.BOUNDARY_WORLDS.items()}
    assert worlds == {c.boundary_world: c.id for c in CLAIMS if c.boundary_world}
    # the verdict calibration judges every claim but those needing the elastic finger's
    # fits (C12: its rates come from its own study); the bending skin's (C13) because it
    # fits the bending skin too
    assert calibration.UNCALIBRATED_CLAIMS == tuple(c.id for c in CLAIMS if "elastic" in c.needs)
    assert calibration.UNCALIBRATED_CLAIMS  # C12
    # the later models' claims (C12, C13): the generator's list gives their verdicts (it
    # has no elastic finger and no bending skin) but not their noise-free truth, which
    # the calibration's analysis, making no such fits, does not compute
    later = set(calibration.BENDING_CLAIMS) | set(calibration.UNCALIBRATED_CLAIMS)
    assert later == {c.id for c in CLAIMS if c.built_in.truth == registry.TRUTH_NOT_COMPUTED}
    assert calibration.BENDING_CLAIMS == tuple(c.id for c in CLAIMS if "bending" in c.needs)


def test_the_generators_list_states_every_claim():
    # the article's "built in" statement covers a claim only if the list has it: the
    # later models' claims too, whose verdicts follow from what the generator lacks
    listed = {row["claim"]: row for row in registry.built_in_verdicts()}
    assert set(listed) == set(registry.CLAIM_IDS)
    for claim, lacks in (("C12", "elastic finger"), ("C13", "bending skin")):
        assert listed[claim]["how"] == "by construction"
        assert f"the generator has no {lacks}" in listed[claim]["why"]
        # the calibration's noise-free world makes no elastic or bending fits
        assert listed[claim]["truth"] == registry.TRUTH_NOT_COMPUTED


def test_the_committed_built_in_verdicts_come_from_the_registry():
    committed = json.loads((REPO / "data" / "built_in_verdicts.json").read_text())
    assert committed == registry.built_in_verdicts()
    assert [row["claim"] for row in committed] == [c.id for c in CLAIMS if c.built_in]


def test_the_article_lists_the_claims_of_each_setting_from_the_registry():
    from lineload.publishing.tables import join_words

    template = (REPO / "workflow/article/reproduction.typ").read_text()
    assert "#facts.claims_using.significance" in template
    assert "#facts.claims_using.large_depth_mm" in template
    assert "#facts.claims_needing.coordinates" in template
    assert join_words(claims_using("large_depth_mm")) == "C9"
    assert "C7" not in claims_using("significance")  # an identity tests nothing


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda c: replace(c, function="claim_c99"), "no function 'claim_c99'"),
        (lambda c: replace(c, kind="a hunch"), "kind 'a hunch'"),
        (lambda c: replace(c, statement=" "), "no statement"),
        (lambda c: replace(c, family="elsewhere"), "family 'elsewhere'"),
        (lambda c: replace(c, settings=("patience",)), "settings ['patience']"),
        (lambda c: replace(c, needs=("fits", "averaged", "noise", "forces")), "keyword forces"),
    ],
)
def test_a_faulty_entry_is_refused(change, message):
    faulty = tuple(change(c) if c.id == "C2" else c for c in CLAIMS)
    with pytest.raises(ValueError, match=re.escape(message)):
        check_claims(faulty)


def test_a_registry_with_a_claim_twice_or_a_world_twice_is_refused():
    with pytest.raises(ValueError, match="given twice"):
        check_claims((*CLAIMS, CLAIMS[0]), functions=False)
    shared = replace(claim_named("C3"), boundary_world=claim_named("C2").boundary_world)
    with pytest.raises(ValueError, match="boundary world 'sides-unequal' given twice"):
        check_claims(tuple(shared if c.id == "C3" else c for c in CLAIMS), functions=False)
    forces_dropped = replace(claim_named("C11"), needs=("fits",))
    with pytest.raises(ValueError, match="takes the keyword forces"):
        check_claims(tuple(forces_dropped if c.id == "C11" else c for c in CLAIMS))


def test_an_unknown_claim_id_names_the_known_ones():
    with pytest.raises(KeyError, match="C1, C2"):
        claim_named("C99")


def test_the_worked_example_of_adding_a_claim_runs(monkeypatch):
    # docs/adding-a-claim.md: its entry, function and test, run as the page shows them
    import test_claims
    from lineload.claims import registry as claims_registry
    from lineload.claims import verdicts

    page = (REPO / "docs" / "adding-a-claim.md").read_text()
    entry_code, function_code, test_code = re.findall(r"```python\n(.*?)```", page, re.S)
    entry = eval(entry_code, {**vars(claims_registry), **vars(verdicts)})
    check_claims((*CLAIMS, entry), functions=False)
    functions = {}
    exec(function_code, functions)
    claim_c14 = functions[entry.function]
    assert settings_read(function_code) == set(entry.settings)
    # what the entry gives the table once it stands in the registry
    monkeypatch.setitem(
        claims_registry.CLAIM_TEXT, "C14", (entry.statement, entry.location, entry.paper_value)
    )
    monkeypatch.setitem(claims_registry.CLAIM_KINDS, "C14", entry.kind)
    monkeypatch.setitem(test_claims.CLAIM_FUNCTIONS, "C14", claim_c14)
    tests = {}
    exec(test_code, vars(test_claims), tests)
    (test,) = tests.values()
    test()


def test_every_family_module_is_a_code_dependency_of_the_jobs_that_judge_claims():
    # the registry imports the families by name at run time; the workflow reads a job's
    # modules from import statements, so a rule changed in a family must still be seen
    from lineload.runtime import codedeps

    scripts = REPO / "workflow" / "scripts"
    for script in ("make_claims.py", "run_verdict_calibration.py"):
        found = codedeps.script_dependencies(scripts / script, ())
        modules = {p.relative_to(REPO / "workflow").as_posix() for p in map(Path, found)}
        missing = {f"lineload/claims/{family}.py" for family in FAMILIES} - modules
        assert not missing, (script, missing)
