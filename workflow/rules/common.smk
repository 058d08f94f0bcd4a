# Loads and validates the config and every raw input before any job is planned.
# A broken input stops the run here with one message naming file, line and
# column: no job starts, so nothing partial is written.
import json
import shlex
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import min_version, validate

min_version("9.0")

WORKFLOW_DIR = Path(workflow.basedir) / "workflow"
sys.path.insert(0, str(WORKFLOW_DIR))

from lineload import checkcache  # noqa: E402  (standard library only)
from lineload.io import load_schema  # noqa: E402


def abort(message):
    """Print one line for the user and stop with a non-zero exit, no traceback."""
    sys.stderr.write(f"Error: {message}\n")
    raise SystemExit(1)


def schema_message(error, what):
    """One line from a snakemake.utils.validate failure (a jsonschema error inside)."""
    inner = error.__context__
    if not hasattr(inner, "absolute_path"):
        return f"{what}: {error}"
    where = "/".join(str(p) for p in inner.absolute_path)
    message = inner.message
    if inner.validator == "additionalProperties":
        allowed = ", ".join(sorted(inner.schema.get("properties", {})))
        message = f"{message}; expected only the keys {allowed}"
    elif "description" in inner.schema:
        message = f"{message} ({inner.schema['description'].rstrip('.')})"
    return f"{what}, key '{where}': {message}" if where else f"{what}: {message}"


def check_inputs():
    """Validate the config (filling in its defaults) and every raw file; abort at the first problem.

    Returns what the rules need from the data as plain values (JSON-ready, so a
    passed check can be remembered): the validated config, each subject's
    species, magnification and display label in subject-sheet order, the depths
    of each subject's profiles and of its outlines.
    """
    from lineload.validation import InputError, check_dataset

    try:
        validate(config, "../schemas/config.schema.yaml")
    except WorkflowError as error:
        abort(schema_message(error, "config"))
    raw = config["raw_data"]
    try:
        dataset = check_dataset(
            raw,
            {name: load_schema(name) for name in ("subjects", "profiles", "outlines")},
        )
        validate(dataset["subjects"], "../schemas/subjects.schema.yaml")
    except InputError as error:
        abort(str(error))
    except WorkflowError as error:
        abort(schema_message(error, f"{raw}/subjects.csv"))
    sheet = dataset["subjects"]
    labels = sheet["label"] if "label" in sheet.columns else [None] * len(sheet)
    subjects = {
        str(subject): {
            "species": str(species),
            "magnification": float(magnification),
            # Display name: the optional label column, else the id.
            "label": (
                label.strip() if isinstance(label, str) and label.strip() else subject
            ),
        }
        for subject, species, magnification, label in zip(
            sheet["subject"], sheet["species"], sheet["magnification"], labels
        )
    }
    return {
        "config": dict(config),
        "subjects": subjects,
        "depths_mm": dataset["depths_mm"],
        "outlines": dataset["outlines"],
    }


# The check reads every raw file (and imports pandas), so a passed check is
# remembered under a fingerprint of the config, the checking code and the raw
# files' bytes; an unchanged dataset is then not read again (see checkcache.py).
CHECK_CACHE = Path(".snakemake", "lineload", "input-check.json")
CHECK_CODE = [
    WORKFLOW_DIR / "lineload" / name
    for name in ("checkcache.py", "io.py", "validation.py")
]
CHECK_CODE += [WORKFLOW_DIR / "rules" / "common.smk"]
CHECK_CODE += sorted((WORKFLOW_DIR / "schemas").glob("*.schema.yaml"))
_raw_given = config.get("raw_data")
if _raw_given is None:  # not set: the schema's default
    _raw_given = load_schema("config")["properties"]["raw_data"]["default"]
_check_key = (
    checkcache.fingerprint(config, _raw_given, CHECK_CODE)
    if isinstance(_raw_given, str)
    else None
)
DATASET = checkcache.load(CHECK_CACHE, _check_key) if _check_key else None
if DATASET is None:
    DATASET = check_inputs()
    if _check_key:
        checkcache.store(CHECK_CACHE, _check_key, DATASET)
else:
    config.update(DATASET["config"])

RAW = config["raw_data"]
RES = config["results"]
# Every job runs the entry points with the interpreter that runs Snakemake (so an
# unactivated virtual environment still works). It is set once as a shell variable
# rather than passed in params, because `.venv/bin/python` and `.venv/bin/python3`
# name the same interpreter, and in params the difference would read as a change.
shell.prefix(f"LINELOAD_PYTHON={shlex.quote(sys.executable)}; ")
SCRIPTS = WORKFLOW_DIR / "scripts"

# Subject id -> {"species", "magnification", "label"}, in subject-sheet order.
SUBJECTS = DATASET["subjects"]
SUBJECT_IDS = list(SUBJECTS)
# Per-subject work runs in batches: each job pays Python's start-up once for all
# its subjects.  A batch of one is named after its subject (the usual case for a
# handful of subjects, so editing one file reruns only that subject's jobs); a
# larger one after its first subject and how many follow ("M1+124").
MAX_JOBS_PER_RULE = 8
PER_JOB = config["subjects_per_job"]
if PER_JOB == "auto":
    PER_JOB = max(1, -(-len(SUBJECT_IDS) // MAX_JOBS_PER_RULE))
BATCHES = {}
for start in range(0, len(SUBJECT_IDS), PER_JOB):
    members = SUBJECT_IDS[start : start + PER_JOB]
    BATCHES[members[0] if len(members) == 1 else f"{members[0]}+{len(members) - 1}"] = (
        members
    )
BATCH_IDS = list(BATCHES)


def raw_files():
    """Every raw input the build read: subject sheet, profiles, outlines, notice."""
    files = [f"{RAW}/subjects.csv"]
    files += [f"{RAW}/profiles/{s}.csv" for s in SUBJECT_IDS]
    files += [f"{RAW}/outlines/{s}.csv" for s in DATASET["outlines"]]
    if Path(RAW, "NOTICE.txt").is_file():
        files.append(f"{RAW}/NOTICE.txt")
    return files


# The pinned environment named by all rules (conda directive), as documentation
# for readers and as what `snakemake --use-conda` builds.
ENVIRONMENT = "../../environment.yml"


def subject_species_args(batch):
    """'--subject ID SPECIES' for each subject of a batch, for the fit scripts."""
    return " ".join(f"--subject {s} {SUBJECTS[s]['species']}" for s in BATCHES[batch])


def code_inputs(script_name):
    """An entry point (first) and every lineload module it imports, directly or not.

    Given as inputs to its rule, so editing the science code reruns the jobs it
    affects (Snakemake tracks a rule's shell text, not the Python it calls).
    """
    import re

    package = WORKFLOW_DIR / "lineload"
    pattern = re.compile(r"^\s*from (?:lineload|)\.?([a-z_]*) import ([\w, (]+)", re.M)
    files, queue = [SCRIPTS / script_name], [SCRIPTS / script_name]
    while queue:
        text = queue.pop().read_text(encoding="utf-8")
        for module, names in pattern.findall(text):
            candidates = [module] if module else [n.strip() for n in names.split(",")]
            for name in candidates:
                path = package / f"{name}.py"
                if path.is_file() and path not in files:
                    files.append(path)
                    queue.append(path)
    return [str(files[0])] + sorted(str(f) for f in files[1:])


def result(*parts):
    """Path of an output under the results folder."""
    return str(Path(RES, *parts))


SPECIES_SUBJECTS = {
    species: [s for s in SUBJECT_IDS if SUBJECTS[s]["species"] == species]
    for species in ("monkey", "human")
}


def first_of_each_species(candidates):
    """The first monkey and the first human among candidates, in subject-sheet order."""
    return [
        next(s for s in SPECIES_SUBJECTS[sp] if s in candidates)
        for sp in ("monkey", "human")
        if any(s in candidates for s in SPECIES_SUBJECTS[sp])
    ]


def chosen_subjects(key, candidates, need):
    """Subjects named in config['figures'][key], checked, or the default choice."""
    requested = config["figures"][key]
    for subject in requested:
        if subject not in candidates:
            abort(f"config, key 'figures/{key}': subject {subject!r} {need}")
    return list(requested) or first_of_each_species(candidates)


OUTLINE_SUBJECTS = chosen_subjects(
    "outline_subjects", DATASET["outlines"], f"has no outline file in {RAW}/outlines/"
)
OUTLINE_DEPTH_MM = config["figures"]["outline_depth_mm"]
if OUTLINE_SUBJECTS:
    common_depths = set.intersection(
        *(set(DATASET["outlines"][s]) for s in OUTLINE_SUBJECTS)
    )
    if OUTLINE_DEPTH_MM is None and common_depths:
        OUTLINE_DEPTH_MM = min(common_depths)
    if OUTLINE_DEPTH_MM not in common_depths:
        abort(
            "config, key 'figures/outline_depth_mm': expected a depth outlined for "
            f"{', '.join(OUTLINE_SUBJECTS)} ({', '.join(f'{d:g}' for d in sorted(common_depths))}),"
            f" got {OUTLINE_DEPTH_MM}"
        )
EXAMPLE_DEPTH_MM = config["figures"]["example_depth_mm"]
EXAMPLE_SUBJECTS = chosen_subjects(
    "example_subjects",
    [s for s in SUBJECT_IDS if EXAMPLE_DEPTH_MM in DATASET["depths_mm"][s]],
    f"is not in {RAW}/subjects.csv or has no profile at the figure depth",
)


def read_notice():
    """Footer for figures and tables: config, else the raw folder's NOTICE.txt, else none."""
    if config["data_notice"] is not None:
        return config["data_notice"]
    path = Path(RAW, "NOTICE.txt")
    if path.is_file():
        lines = path.read_text(encoding="utf-8").splitlines()
        return lines[0].strip() if lines else ""
    return ""


NOTICE = read_notice()


# ---------------------------------------------------------------- figures
# Figures drawn by each rule (file stems under results/figures/).
FIGURE_GROUPS = {
    "figure_outlines": ["figure1"],
    "figure_schematics": ["figure3", "figure4", "figure5"],
    "figure_fits": ["figure2", "figure6", "figure7"],
    "figure_supplement": [
        "supplement_residuals",
        "supplement_arc_vs_parabola",
        "supplement_sensitivity",
        "supplement_coordinates",
    ],
}


# Snakemake's parser reads a line that starts with `report(` as its report keyword,
# and snakefmt puts the call at a line start: call it by another name.
report_item = report


def figure_files(group):
    """PDF and PNG of every figure a rule draws; the PNG goes into the report."""
    files = []
    for name in FIGURE_GROUPS[group]:
        category = "Supplement" if name.startswith("supplement") else "Paper figures"
        caption, labels = f"../report/{name}.rst", {"figure": name.replace("_", " ")}
        png = result("figures", f"{name}.png")
        files += [
            result("figures", f"{name}.pdf"),
            report_item(png, caption=caption, category=category, labels=labels),
        ]
    return files


def figure_args(group):
    """'--figure NAME' for every figure a rule draws."""
    return " ".join(f"--figure {name}" for name in FIGURE_GROUPS[group])


# Every figure file the default target builds (PDF and PNG of each).
FIGURE_OUTPUTS = [path for group in FIGURE_GROUPS for path in figure_files(group)]

# Shared arguments: the subject list (id, species, label) in sheet order, the
# PNG resolution and the footer; the figure stage reads results files only.
FIGURE_SUBJECT_ARGS = " ".join(
    f"--subject {shlex.quote(s)} {SUBJECTS[s]['species']} {shlex.quote(SUBJECTS[s]['label'])}"
    for s in SUBJECT_IDS
)
# The drawing code is an input too, so editing the figures' style redraws them.
FIGURE_CODE = code_inputs("make_figures.py")
FIGURE_DPI = config["figures"]["png_dpi"]
