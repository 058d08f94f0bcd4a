# Config and subject sheet, validated when Snakemake starts; the raw files listed (not
# read: rule check_raw_data checks them); batches; input functions.
import functools
import os
import sys
from pathlib import Path

from snakemake.exceptions import IncompleteCheckpointException, WorkflowError
from snakemake.io import strip_wildcard_constraints
from snakemake.utils import min_version, validate

from lineload.runtime import batches, buildlock, codedeps, settings, startup
from lineload.rawdata import validation
from lineload.runtime.interrupt import stop_on_sigterm
from lineload.runtime.timers import cancel_scheduler_timers
from lineload.io import load_schema
from lineload.rawdata.validation import InputError

min_version("9.0")

# `kill` stops a build as Ctrl-C does, from the start: Snakemake takes its locks before
# its scheduler installs a SIGTERM handler, and the default one would leave them behind
# (onstart: installs it again over the scheduler's own)
stop_on_sigterm()

# One environment for the whole workflow (pip: requirements.txt, or conda, pinned alike).
ENVIRONMENT = "../../environment.yml"

# snakefmt puts a `report(` call at a line start, where Snakemake reads its keyword.
report_item = report

# --config values typed as in a config file; `a__b=value` sets a nested key (settings.py).
# From the words as typed (ConfigSettings.config_args, which Snakemake keeps to pass
# --config on to cluster jobs): `config` and ConfigSettings.config hold Snakemake's
# reading, which has already cut "Sample #3" at the "#" and made every number inside
# '{a: 1.25}' text; --configfile is Snakemake's own way to nested, typed values.
settings.apply_command_line(config, workflow.config_settings.config_args)
try:
    validate(config, "../schemas/config.schema.yaml")  # fills in the defaults
except WorkflowError as error:
    startup.abort(startup.schema_message(error, "config"))
if problem := startup.config_problem(config):  # NaN, infinities, over-long paths
    startup.abort(problem)
RAW = config["raw_data"] = startup.data_folder(config["raw_data"], REPOSITORY)
RES = config["results"]
if problem := startup.folder_problem(RAW, RES):
    startup.abort(problem)

# The checkout the workflow runs from, and its citation file where this copy has one (a
# deployed workflow/ and config/ alone do not: then the package's name and version stand in)
CITATION_FILES = [
    os.path.relpath(path) for path in [REPOSITORY / "CITATION.cff"] if path.is_file()
]

RAW_FILES = startup.list_raw_files(RAW)
try:  # Subject id -> species, magnification, label, contact length; sheet order.
    SUBJECTS = startup.read_subject_sheet(RAW, load_schema("subjects"))
except InputError as error:
    startup.abort_inputs(error)
CONTACT_LENGTH_MM = {s: about.pop("contact_length_mm") for s, about in SUBJECTS.items()}
SUBJECT_IDS = list(SUBJECTS)
# Subject -> its photographs, for subjects read from images/images.csv (the check
# reports anything wrong with that sheet), and their readings, digitised into results/.
# (a photograph that is not there is left for the check to report, in its words)
PHOTOGRAPHS = {
    s: [f for f in files if os.path.isfile(f)]
    for s, files in validation.photograph_files(RAW).items()
    if s in SUBJECTS
}
# Per-subject work runs in batches (Python's start-up paid once per job): see
# lineload.runtime.batches for the split; a batch of one is named after its subject,
# a larger one "M1+124".
BATCHES = batches.batches(
    SUBJECT_IDS, config["subjects_per_job"], photographs=bool(PHOTOGRAPHS)
)
BATCH_IDS = list(BATCHES)
# Subject -> its profile file; a subject without one is the raw-data check's to report.
RAW_PROFILES = {
    s: RAW_FILES["profiles"][f"{s}.csv"]
    for s in SUBJECT_IDS
    if f"{s}.csv" in RAW_FILES["profiles"] and s not in PHOTOGRAPHS
}
# Photographed subjects are digitised batch by batch (the batches above, each with its
# photographed subjects): batch -> its photographed subjects; each one's readings are
# in its batch's file.
DIGITISE_BATCHES = {
    b: [s for s in members if s in PHOTOGRAPHS]
    for b, members in BATCHES.items()
    if any(s in PHOTOGRAPHS for s in members)
}
PROFILES = {
    s: RAW_PROFILES[s] if s in RAW_PROFILES else str(Path(RES, "digitised", f"{b}.csv"))
    for b, members in BATCHES.items()
    for s in members
    if s in RAW_PROFILES or s in PHOTOGRAPHS
}
OUTLINED = [s for s in SUBJECT_IDS if f"{s}.csv" in RAW_FILES["outlines"]]
FORCES = [RAW_FILES["forces"]] if RAW_FILES["forces"] else []  # optional
NOTICE = config["data_notice"] = startup.notice_text(
    config["data_notice"], RAW_FILES["notice"]
)

# Which ready job starts first when the cores are few (Snakemake's `priority:`): the
# chain to the supplementary figures, the longest job of a build, first; then the chain
# to the claims and to the figures of the later model families; the figures nothing but
# the article waits for (priority 0) fill the gaps.  On two cores a clean build ends
# about when the supplements do (docs/speed-and-clusters.md measures it).
PRIORITY = {
    **dict.fromkeys(
        (
            "prepare_profiles",
            "noise",
            "fit_models",
            "fits_table",
            "mechanics",
            "fit_sensitivity",
            "sensitivity_tables",
            "figure_supplements",
        ),
        2,
    ),
    **dict.fromkeys(
        (
            "fit_bending",
            "bending_table",
            "elastic_fits",
            "fit_tables",
            "claims_table",
            "figure_families",
            "figure_fits",
        ),
        1,
    ),
}


def result(*parts):
    """Path of an output under the results folder."""
    return str(Path(RES, *parts))


def batch_subjects(wildcards):
    """The subjects of a batch, each with species, magnification and label."""
    return {s: SUBJECTS[s] for s in BATCHES[wildcards.batch]}


def checked_raw_data(wildcards):
    """The raw-data check's summary, an input of every job that reads raw data.

    When the check must run again (a raw file changed), the jobs after it are decided
    once it has passed (it is a checkpoint), each on its own inputs: ancient() keeps
    the summary's new time from rerunning them all.
    """
    summary = rules.check_raw_data.output[0]
    try:
        checkpoints.check_raw_data.get()
    except IncompleteCheckpointException:
        if not os.path.exists(summary):
            raise
    return ancient(summary)


def profile_files(wildcards):
    """The profile files of a batch."""
    return [PROFILES[s] for s in BATCHES[wildcards.batch] if s in PROFILES]


def code(script, modules=()):
    """The package files a rule's script runs (Snakemake sees the script, not its imports)."""
    return [
        relative_path(path)
        for path in codedeps.script_dependencies(
            WORKFLOW_DIR / "scripts" / script, modules
        )
    ]


@functools.cache
def relative_path(path):
    """A path relative to the working folder, worked out once a path (the rules share
    most of their package files)."""
    return os.path.relpath(path)


def crate_files(wildcards):
    """Input function of the crate rule (report.smk), and of the bundle's through it.

    Every file of the crate: its name in the crate (under results/), the rule that
    wrote it, its kind, and where it comes from: outputs and logs are where they are;
    the raw inputs (under the raw folder) and the source (in the checkout) are copied
    into inputs/ and source/.  No absolute path: the list stays the same wherever the
    folders are."""
    # (the loop variable is "name": a line that starts with the keyword is read as one)
    outputs_of = {
        **OUTPUTS_BY_RULE,
        "provenance": list(rules.provenance.output),
        "provenance_page": list(rules.provenance_page.output),
    }
    files = [
        {"name": os.path.relpath(f, RES), "rule": name, "kind": "output"}
        for name, outputs in outputs_of.items()
        for f in outputs
    ]
    # the logs, where a job keeps one (written before this job runs): one per batch or
    # subject for the jobs that run per batch or subject (JOB_WILDCARDS, report.smk)
    for name in CRATE_RULES:
        for log in getattr(rules, name).rule.log:
            pattern = strip_wildcard_constraints(str(log))
            paths = (
                expand(pattern, **JOB_WILDCARDS[name])
                if name in JOB_WILDCARDS
                else [pattern]
            )
            files += [
                {"name": os.path.relpath(path, RES), "rule": name, "kind": "log"}
                for path in paths
            ]
    files += [
        {
            "name": f"inputs/{os.path.relpath(f, RAW)}",
            "from": os.path.relpath(f, RAW),
            "kind": "input",
        }
        for f in rules.provenance.input.raw
    ]
    files += [
        {"name": f"source/{name}", "from": name, "kind": "source"}
        for name in SOURCE_FILES
    ]
    return files


# The calibration tables kept in the repository (snakemake calibration remakes them);
# the claims table, the article and the calibration's figure read them.
COMMITTED_CALIBRATION = {
    name: os.path.relpath(REPOSITORY / "docs" / "calibration" / f"{name}.csv")
    for name in ("verdicts", "coverage", "boundary", "mechanics_coverage", "bootstrap")
}


def coverage_blocks():
    """Jobs of the coverage study: one per scenario of errors, by its index (the index
    seeds it); the scenarios are imported only when the calibration is asked for."""
    from lineload.simulation.coverage import SCENARIOS

    return [str(i) for i in range(len(SCENARIOS))]


def boundary_blocks():
    """Jobs of the boundary calibration: '{world}.{first}' per world and block of
    datasets (config calibration: verdict_datasets, block_datasets); the worlds are
    imported only when the calibration is asked for."""
    from lineload.simulation.boundary import BOUNDARY_WORLDS

    total = config["calibration"]["verdict_datasets"]
    step = config["calibration"]["block_datasets"]
    return [
        f"{world}.{first}"
        for world in BOUNDARY_WORLDS
        for first in range(0, total, step)
    ]
