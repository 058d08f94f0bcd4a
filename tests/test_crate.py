"""The run as an RO-Crate and the bundle: checked with roc-validator offline, read back
with rocrate, and every hash recomputed from the files themselves."""

import contextlib
import hashlib
import io
import json
import re
import shutil
import subprocess
import zipfile
from pathlib import Path
from urllib.parse import unquote

import pytest
import requests
from requests_cache import CachedSession
from rocrate.rocrate import ROCrate
from urllib3 import HTTPResponse

from conftest import REPO, SMALL_BATCH, copy_build, run_snakemake
from lineload.publishing.bundle import CHECKSUMS, bundle_name, checksums_text, write_bundle
from lineload.publishing.citation import read_citation
from lineload.publishing.crate import (
    MAIN_WORKFLOW,
    build_crate,
    crate_json,
    flat_parameters,
    source_files,
    write_crate,
)

#: The RO-Crate context rocrate writes, and the copy of it the rocrate package carries.
CONTEXT_URL = "https://w3id.org/ro/crate/1.3/context"

#: What the Provenance Run Crate 0.5 profile of roc-validator 0.13 refuses in a crate of
#: RO-Crate 1.3 (the version rocrate 0.16 writes): the profile is built on RO-Crate 1.1 and
#: asks the metadata descriptor to conform to 1.1 by name.  Everything else it requires
#: must pass.
VERSION_ONLY_FAILURES = {"ro-crate-1.1_5.3"}


@pytest.fixture(scope="module")
def offline_cache(tmp_path_factory):
    """roc-validator's HTTP cache holding the RO-Crate 1.3 context, so it needs no network.

    The context document is the one the rocrate package ships
    (``rocrate/data/ro-crate.jsonld``), stored under its URL as a cached response.
    """
    import rocrate

    document = (Path(rocrate.__file__).parent / "data" / "ro-crate.jsonld").read_bytes()
    assert json.loads(document)["@id"] == CONTEXT_URL
    path = tmp_path_factory.mktemp("http-cache") / "http"
    session = CachedSession(cache_name=str(path), backend="sqlite", expire_after=-1)
    response = requests.Response()
    response.status_code, response.url, response.encoding = 200, CONTEXT_URL, "utf-8"
    response.headers["Content-Type"] = "application/ld+json"
    response._content = document
    response.raw = HTTPResponse(
        body=io.BytesIO(document), status=200, preload_content=False, headers=response.headers
    )
    response.request = requests.Request("GET", CONTEXT_URL).prepare()
    session.cache.save_response(response)
    session.close()
    return path


#: SPARQL queries as rdflib prepared them, by (query, base, namespaces): roc-validator's
#: SHACL checks ask the same 43 queries about 100 times per validation, and parsing them
#: again took two thirds of each validation's time (about 10 s of a crate's 15 s).
_PREPARED_QUERIES = {}


@contextlib.contextmanager
def queries_prepared_once():
    """rdflib's SPARQL processor with each query string parsed and translated once.

    A prepared query is rdflib's own means of asking one query many times (its
    ``prepareQuery`` makes the same object); it is evaluated afresh on each graph and
    bindings, so the checks and their verdicts are unchanged.
    """
    from rdflib.plugins.sparql import processor
    from rdflib.plugins.sparql.algebra import translateQuery
    from rdflib.plugins.sparql.parser import parseQuery

    def query(self, query, initBindings=None, initNs=None, base=None, DEBUG=False):
        if isinstance(query, str):
            key = (query, base, tuple(sorted((k, str(v)) for k, v in (initNs or {}).items())))
            if key not in _PREPARED_QUERIES:
                _PREPARED_QUERIES[key] = translateQuery(parseQuery(query), base, initNs)
            query = _PREPARED_QUERIES[key]
        return original(self, query, initBindings, initNs, base, DEBUG)

    original = processor.SPARQLProcessor.query
    processor.SPARQLProcessor.query = query
    try:
        yield
    finally:
        processor.SPARQLProcessor.query = original


def validate(root, cache, profile, severity="REQUIRED"):
    """roc-validator on a crate, offline: (passed, {check id: [messages]})."""
    from rocrate_validator import services
    from rocrate_validator.models import Severity

    settings = services.ValidationSettings(
        rocrate_uri=str(root),
        profile_identifier=profile,
        requirement_severity=Severity[severity],
        offline=True,
        cache_path=str(cache),
    )
    with queries_prepared_once():
        result = services.validate(settings)
    failed = {}
    for issue in result.get_issues():
        failed.setdefault(issue.check.identifier, []).append(issue.message)
    return result.passed(), failed


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


# ---------------------------------------------------------------- a crate of a small tree


def small_run(root):
    """A run of two rules over one raw file, as the crate job sees it (files, rules)."""
    (root / "raw").mkdir(parents=True)
    (root / "raw" / "subjects.csv").write_text("subject,species\nMK,monkey\n")
    (root / "tables").mkdir()
    (root / "tables" / "fits.csv").write_text("subject,L_mm\nMK,10.5\n")
    (root / "figure.pdf").write_bytes(b"%PDF-1.7 not really\n")
    (root / "logs").mkdir()
    (root / "logs" / "fit.log").write_text("MK: 1 trial\n")
    source = root / "source" / "workflow"
    source.mkdir(parents=True)
    (source / "Snakefile").write_text("rule all:\n    input: 'tables/fits.csv'\n")
    (source / "fit.smk").write_text("rule fit:\n    output: 'tables/fits.csv'\n")
    files = [
        {
            "name": "tables/fits.csv",
            "path": str(root / "tables/fits.csv"),
            "rule": "fit",
            "kind": "output",
        },
        {"name": "figure.pdf", "path": str(root / "figure.pdf"), "rule": "draw", "kind": "output"},
        {"name": "logs/fit.log", "path": str(root / "logs/fit.log"), "rule": "fit", "kind": "log"},
        {
            "name": "inputs/subjects.csv",
            "path": str(root / "raw/subjects.csv"),
            "rule": None,
            "kind": "input",
        },
        {"name": MAIN_WORKFLOW, "path": "", "rule": None, "kind": "source"},
        {"name": "source/workflow/fit.smk", "path": "", "rule": None, "kind": "source"},
    ]
    (root / "inputs").mkdir()
    shutil.copyfile(root / "raw" / "subjects.csv", root / "inputs" / "subjects.csv")
    rules = {
        "fit": {"description": "Fit the models.", "source": "source/workflow/fit.smk"},
        "draw": {"description": "Draw the figure.", "source": "source/workflow/fit.smk"},
    }
    return files, rules


RECORD = {
    "config": {"fit_window_mm": 3.0, "claims": {"significance": 0.05, "noise_mm": None}},
    "python": "3.11.7",
    "packages": {"snakemake": "9.27.1", "numpy": "2.4.6"},
    "git": {"commit": "0123456789abcdef0123456789abcdef01234567", "dirty": False},
}


def graph_of(crate):
    return {entity["@id"]: entity for entity in json.loads(crate_json(crate))["@graph"]}


def test_the_crate_states_each_files_hash_size_and_rule(tmp_path):
    files, rules = small_run(tmp_path)
    citation = read_citation(REPO / "CITATION.cff")
    crate, members = build_crate(files, rules, RECORD, citation, tmp_path)
    graph = graph_of(crate)
    for name in (
        "tables/fits.csv",
        "figure.pdf",
        "logs/fit.log",
        "inputs/subjects.csv",
        MAIN_WORKFLOW,
    ):
        entity = graph[name]
        assert entity["sha256"] == sha256(tmp_path / name), name  # recomputed here
        assert entity["contentSize"] == str((tmp_path / name).stat().st_size), name
    assert set(members) == {f["name"] for f in files}
    # the rule that wrote each file: its run's results, and the run's tool is the rule
    fit_run, draw_run = graph["#run/fit"], graph["#run/draw"]
    assert {r["@id"] for r in fit_run["result"]} == {"tables/fits.csv", "logs/fit.log"}
    assert draw_run["result"] == {"@id": "figure.pdf"} or draw_run["result"] == [
        {"@id": "figure.pdf"}
    ]
    assert fit_run["instrument"] == {"@id": "#rule/fit"}
    # the configuration as parameters with their values
    values = {e["name"]: e["value"] for e in graph.values() if e.get("@type") == "PropertyValue"}
    assert values == {
        "claims.noise_mm": "null",
        "claims.significance": "0.05",
        "fit_window_mm": "3.0",
    }
    # the citation file's date, never the clock; its licence; the main workflow
    root = graph["./"]
    assert root["datePublished"] == citation["date-released"]
    assert root["license"] == {"@id": f"https://spdx.org/licenses/{citation['license']}"}
    assert root["mainEntity"] == {"@id": MAIN_WORKFLOW}
    # software with versions, and the engine
    assert graph["https://pypi.org/project/numpy/2.4.6/"]["version"] == "2.4.6"
    assert graph["#snakemake"]["version"] == "9.27.1"


def test_the_crate_is_the_same_bytes_twice_and_reads_back(tmp_path):
    files, rules = small_run(tmp_path)
    citation = read_citation(REPO / "CITATION.cff")
    first = crate_json(build_crate(files, rules, RECORD, citation, tmp_path)[0])
    second = crate_json(build_crate(files, rules, RECORD, citation, tmp_path)[0])
    assert first == second
    # every identifier comes from a name: none is a random one rocrate would make
    ids = [entity["@id"] for entity in json.loads(first)["@graph"]]
    assert not any(re.search(r"[0-9a-f]{8}-[0-9a-f]{4}-", i) for i in ids), ids
    write_crate(build_crate(files, rules, RECORD, citation, tmp_path)[0], tmp_path)
    read = ROCrate(tmp_path)
    assert read.mainEntity.id == MAIN_WORKFLOW
    assert read.root_dataset["datePublished"] == citation["date-released"]
    assert {e.id for e in read.data_entities} >= {
        "tables/fits.csv",
        "figure.pdf",
        "inputs/subjects.csv",
    }


def test_the_bundle_leaves_out_the_logs_and_lists_exactly_its_files(tmp_path):
    files, rules = small_run(tmp_path)
    citation = read_citation(REPO / "CITATION.cff")
    crate, members = build_crate(files, rules, RECORD, citation, tmp_path, logs=False)
    assert "logs/fit.log" not in members and "logs/fit.log" not in graph_of(crate)


def test_flat_parameters_and_source_files(tmp_path):
    assert flat_parameters({"b": {"y": 1, "x": [2, 3]}, "a": None, "c": {}}) == {
        "a": None,
        "b.x": [2, 3],
        "b.y": 1,
        "c": {},
    }
    (tmp_path / "workflow" / "lineload" / "__pycache__").mkdir(parents=True)
    (tmp_path / "workflow" / "lineload" / "__pycache__" / "a.cpython-311.pyc").write_bytes(b"")
    (tmp_path / "workflow" / "lineload.egg-info").mkdir()
    (tmp_path / "workflow" / "lineload.egg-info" / "PKG-INFO").write_text("x")
    (tmp_path / "workflow" / "lineload" / "a.py").write_text("x = 1\n")
    (tmp_path / "workflow" / "Snakefile").write_text("")
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "config.yaml").write_text("")
    (tmp_path / "LICENSE").write_text("MIT")
    assert source_files(tmp_path) == [
        "LICENSE",
        "config/config.yaml",
        "workflow/Snakefile",
        "workflow/lineload/a.py",
    ]


def test_validation_passes_a_whole_crate_and_fails_one_with_a_file_missing(tmp_path, offline_cache):
    files, rules = small_run(tmp_path)
    (tmp_path / "raw" / "subjects.csv").unlink()  # the crate has its copy; the raw is gone
    shutil.rmtree(tmp_path / "raw")
    crate, _ = build_crate(files, rules, RECORD, read_citation(REPO / "CITATION.cff"), tmp_path)
    write_crate(crate, tmp_path)
    passed, failed = validate(tmp_path, offline_cache, "ro-crate-1.3")
    assert passed, failed
    passed, failed = validate(tmp_path, offline_cache, "provenance-run-crate-0.5")
    assert set(failed) == VERSION_ONLY_FAILURES, failed
    # a file the crate lists but does not hold: refused
    (tmp_path / "figure.pdf").unlink()
    passed, failed = validate(tmp_path, offline_cache, "ro-crate-1.3")
    assert not passed and any("figure.pdf" in m for ms in failed.values() for m in ms), failed


# ---------------------------------------------------------------- the bundle's zip


def test_the_bundle_zip_is_reproducible_and_checks_with_sha256sum(tmp_path):
    (tmp_path / "a.csv").write_text("x\n1\n")
    (tmp_path / "b.txt").write_text("b\n")
    members = {"tables/a.csv": tmp_path / "a.csv", "b.txt": tmp_path / "b.txt", "c.json": b"{}\n"}
    sums = write_bundle(members, tmp_path / "one.zip", "2026-11-25")
    write_bundle(dict(reversed(list(members.items()))), tmp_path / "two.zip", "2026-11-25")
    assert (tmp_path / "one.zip").read_bytes() == (tmp_path / "two.zip").read_bytes()
    with zipfile.ZipFile(tmp_path / "one.zip") as archive:
        assert archive.namelist() == ["b.txt", "c.json", "tables/a.csv", CHECKSUMS]
        assert {info.date_time for info in archive.infolist()} == {(2026, 11, 25, 0, 0, 0)}
        archive.extractall(tmp_path / "unpacked")
    assert sums == checksums_text(members)
    checked = subprocess.run(
        ["sha256sum", "-c", CHECKSUMS], cwd=tmp_path / "unpacked", capture_output=True, text=True
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    # a changed file after unpacking is caught
    (tmp_path / "unpacked" / "b.txt").write_text("changed\n")
    checked = subprocess.run(
        ["sha256sum", "-c", CHECKSUMS], cwd=tmp_path / "unpacked", capture_output=True, text=True
    )
    assert checked.returncode != 0 and "b.txt: FAILED" in checked.stdout
    # another date, other bytes
    write_bundle(members, tmp_path / "three.zip", "2027-01-01")
    assert (tmp_path / "three.zip").read_bytes() != (tmp_path / "one.zip").read_bytes()


def test_bundle_names_and_members_are_checked(tmp_path):
    assert bundle_name("lineload", "0.1.0", "ac664e9abcdef") == "lineload-0.1.0-ac664e9.zip"
    assert bundle_name("lineload", "0.1.0", None) == "lineload-0.1.0-nocommit.zip"
    for bad in ("../escape.csv", "/etc/passwd", CHECKSUMS):
        with pytest.raises(ValueError, match="cannot be a member"):
            write_bundle({bad: b"x"}, tmp_path / "bad.zip", "2026-11-25")
    assert not (tmp_path / "bad.zip").exists()


# ---------------------------------------------------------------- the workflow's crate


@pytest.mark.e2e
def test_the_builds_crate_validates_offline_and_holds_every_file(small_build, offline_cache):
    _, results = small_build
    passed, failed = validate(results, offline_cache, "ro-crate-1.3")
    assert passed, failed
    passed, failed = validate(results, offline_cache, "provenance-run-crate-0.5")
    assert set(failed) == VERSION_ONLY_FAILURES, failed
    graph = {
        e["@id"]: e for e in json.loads((results / "ro-crate-metadata.json").read_text())["@graph"]
    }
    files = [e for e in graph.values() if "File" in e["@type"]]
    # an @id is a URI reference: a batch's "+" (M1+124) is written %2B
    for entity in files:
        assert entity["sha256"] == sha256(results / unquote(entity["@id"])), entity["@id"]
    names = {unquote(e["@id"]) for e in files}
    # outputs, logs, the raw inputs' copies and the source; no job timings
    assert {"article/reproduction.pdf", "tables/claims.csv", "provenance.json"} <= names
    assert {"logs/article.log", "inputs/subjects.csv", MAIN_WORKFLOW} <= names
    # the logs of the rules that run per batch or subject too
    assert {f"logs/fit_models/{SMALL_BATCH}.log", "logs/prepare_outline/MK.log"} <= names
    assert "source/workflow/rules/report.smk" in names and "source/CITATION.cff" in names
    assert not any(n.startswith("benchmarks/") for n in names)
    # the article was written by the article rule, the claims by claims_table
    assert {"@id": "article/reproduction.pdf"} in graph["#run/article"]["result"]
    assert {"@id": "tables/claims.csv"} in graph["#run/claims_table"]["result"]
    # read back with rocrate
    crate = ROCrate(results)
    assert crate.mainEntity.id == MAIN_WORKFLOW
    assert "HowTo" in crate.mainEntity.type


@pytest.mark.e2e
def test_the_bundle_is_the_same_bytes_from_two_builds_and_verifies_unpacked(
    tmp_path, small_build, offline_cache
):
    """Two builds of the same data in folders of their own give the same zip; unpacked
    elsewhere, it checks with sha256sum alone, and its crate validates."""
    raw, results = small_build
    zips = []
    for name in ("one", "two"):
        raw_copy, results_copy = copy_build(raw, results, tmp_path / name)
        made = run_snakemake("bundle", raw=raw_copy, results=results_copy)
        assert made.returncode == 0, made.stderr[-3000:]
        (bundle,) = (results_copy / "bundle").iterdir()
        zips.append(bundle)
    assert zips[0].name == zips[1].name
    # named by the citation file's name and version and the commit built
    citation = read_citation(REPO / "CITATION.cff")
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=REPO, capture_output=True, text=True)
    assert zips[0].name == bundle_name("lineload", citation["version"], head.stdout.strip() or None)
    assert zips[0].read_bytes() == zips[1].read_bytes()
    unpacked = tmp_path / "unpacked"
    with zipfile.ZipFile(zips[0]) as archive:
        names = archive.namelist()
        archive.extractall(unpacked)
    assert not any(n.startswith(("logs/", "benchmarks/")) for n in names)
    assert {"ro-crate-metadata.json", CHECKSUMS, "inputs/subjects.csv", MAIN_WORKFLOW} <= set(names)
    checked = subprocess.run(
        ["sha256sum", "-c", CHECKSUMS], cwd=unpacked, capture_output=True, text=True
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    passed, failed = validate(unpacked, offline_cache, "ro-crate-1.3")
    assert passed, failed


@pytest.mark.e2e
def test_the_crate_is_not_remade_when_nothing_it_describes_changed(tmp_path, small_build):
    raw, results = small_build
    raw_copy, results_copy = copy_build(raw, results, tmp_path / "copy")
    before = (results_copy / "ro-crate-metadata.json").stat().st_mtime_ns
    again = run_snakemake(raw=raw_copy, results=results_copy)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "rule crate:" not in again.stderr  # no crate job ran (local or not)
    assert (results_copy / "ro-crate-metadata.json").stat().st_mtime_ns == before
