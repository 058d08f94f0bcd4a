# Config and raw inputs, validated before any job is planned; what each job is given.
# Broken inputs stop the run here, every problem on its own line naming file, line and
# column (lineload/validation.py): no job starts, so nothing partial is written.
import os
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import min_version, validate

from lineload import checkcache, codedeps, settings
from lineload.interrupt import stop_on_sigterm
from lineload.figures import registry
from lineload.figures.choices import ChoiceError, example_choice, outline_choice
from lineload.io import load_schema, write_json_if_changed

min_version("9.0")

# The software of every job, one environment for the whole workflow, installed once
# with pip (requirements.txt) or conda (environment.yml, pinned alike); the rules run
# in the environment Snakemake runs in.  Naming the file here documents it per rule.
ENVIRONMENT = "../../environment.yml"


# Snakemake's parser reads a line that starts with `report(` as its report keyword,
# and snakefmt puts the call at a line start: call it by another name.
report_item = report


def where_to_look():
    """After a build: print where the reader's documents are."""
    lines = ["", "Where to look:"]
    for what, path in (
        ("the article", result("article", "reproduction.pdf")),
        ("the claims table", result("tables", "claims.md")),
    ):
        if Path(path).is_file():
            lines.append(f"  {what}: {path}")
    lines.append(f"  the HTML report: snakemake --report {result('report.html')}")
    print("\n".join(lines), file=sys.stderr)


def abort(message):
    """Print one line for the user and stop with a non-zero exit, no traceback."""
    sys.stderr.write(f"Error: {message}\n")
    raise SystemExit(1)


def abort_inputs(error):
    """Print every problem of the raw folder (one line each, up to a limit) and stop."""
    from lineload.validation import report_lines

    sys.stderr.write("".join(f"{line}\n" for line in report_lines(error)))
    raise SystemExit(1)


def warn(lines):
    """Print warnings about the inputs once per run (not again in each job)."""
    if workflow.is_main_process:
        sys.stderr.write("".join(f"Warning: {line}\n" for line in lines))


def data_folder(path):
    """The raw-data folder: as given; or, when a relative path is not found from the
    working folder (a run with -s or --directory elsewhere), the same path inside this
    workflow's own repository, if there is one."""
    own = Path(workflow.basedir).parent / path
    if Path(path).is_absolute() or Path(path).exists() or not own.is_dir():
        return path
    return str(own)


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
    species, magnification and display label in subject-sheet order, its
    contact length (None without one), the depths of each subject's profiles
    and of its outlines.
    """
    from lineload.validation import InputError, check_dataset

    try:
        validate(config, "../schemas/config.schema.yaml")
    except WorkflowError as error:
        abort(schema_message(error, "config"))
    config["raw_data"] = raw = data_folder(config["raw_data"])
    try:
        dataset = check_dataset(
            raw,
            {
                name: load_schema(name)
                for name in ("subjects", "profiles", "outlines", "forces")
            },
            plausibility=config["input_checks"],
        )
        validate(dataset["subjects"], "../schemas/subjects.schema.yaml")
    except InputError as error:
        abort_inputs(error)
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
    # Optional column: length of wedge edge in contact (mm), None without it.
    contact = (
        sheet["contact_length_mm"]
        if "contact_length_mm" in sheet.columns
        else [None] * len(sheet)
    )
    return {
        "config": dict(config),
        "subjects": subjects,
        "contact_length_mm": {
            str(s): None if c is None else float(c)
            for s, c in zip(sheet["subject"], contact)
        },
        "depths_mm": dataset["depths_mm"],
        "outlines": dataset["outlines"],
        "warnings": dataset["warnings"],
    }


# The check reads every raw file (and imports pandas), so a passed check is
# remembered under a fingerprint of the config, the checking code and the raw
# files' bytes; an unchanged dataset is then not read again (lineload/checkcache.py).
CHECK_CACHE = Path(".snakemake", "lineload", "input-check.json")
CHECK_CODE = [
    str(Path(workflow.basedir, "rules", "common.smk")),
    str(codedeps.PACKAGE_DIR / "validation.py"),
    str(codedeps.PACKAGE_DIR / "checkcache.py"),
    *codedeps.script_dependencies(codedeps.PACKAGE_DIR / "validation.py"),
    *sorted(str(p) for p in Path(workflow.basedir, "schemas").glob("*.schema.yaml")),
]
# --config values typed as in a config file; `a__b=value` sets a nested key (settings.py)
settings.apply_command_line(config, workflow.config_settings.config_args)
_raw_given = config.get("raw_data")
if _raw_given is None:  # not set: the schema's default
    _raw_given = load_schema("config")["properties"]["raw_data"]["default"]
if isinstance(_raw_given, str):
    _raw_given = data_folder(_raw_given)
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
warn(DATASET["warnings"])

RAW = config["raw_data"]
RES = config["results"]
# The optional force readings (data contract: data/README.md); [] without them.
FORCES = [f"{RAW}/forces.csv"] if Path(RAW, "forces.csv").is_file() else []

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


def result(*parts):
    """Path of an output under the results folder."""
    return str(Path(RES, *parts))


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
# The footer in force, from the config or NOTICE.txt: the report's front page says it.
config["data_notice"] = NOTICE


# ---------------------------------------------------------------- what each job is given
# A job's values (settings from the config, the subjects it handles, the footer) are
# written to <results>/specs/<rule>/<key>.json, and the file is an input of the job.
# It is rewritten only when its content changes, so a job reruns exactly when its
# values do; and a reviewer can open it to see what the job was given.  (Values passed
# as params would do the same, but comparing them makes Snakemake import pandas on
# every run.)
def spec(job, key="all", **values):
    """Write a job's spec (if changed) and return its path."""
    path = result("specs", job, f"{key}.json")
    write_json_if_changed(values, path)
    return path


def batch_specs(job, **values):
    """One spec per batch, with the batch's subjects; the path pattern for the rule."""
    for batch, members in BATCHES.items():
        subjects = {s: SUBJECTS[s] for s in members}
        spec(job, batch, subjects=subjects, **values)
    return result("specs", job, "{batch}.json")


def subject_specs(job, subjects):
    """One spec per subject (its id and magnification); the path pattern for the rule."""
    for subject in subjects:
        spec(
            job,
            subject,
            subject=subject,
            magnification=SUBJECTS[subject]["magnification"],
        )
    return result("specs", job, "{subject}.json")


# ---------------------------------------------------------------- the code each job runs
# Snakemake reruns a script: job when the script changes, not when a module it imports
# does; the package files a script reaches through its imports are inputs of its rule.
SCRIPTS = Path(workflow.basedir, "scripts")


def code(script, modules=()):
    """The package files a rule's script runs (lineload/codedeps.py), as relative paths."""
    return [
        os.path.relpath(path)
        for path in codedeps.script_dependencies(SCRIPTS / script, modules)
    ]


# ---------------------------------------------------------------- figures
def figure_choices():
    """Figures 1 and 2: subjects and depth as configured, else chosen from the data
    (lineload/figures/choices.py); a choice the data cannot satisfy stops the run."""
    species_of = {s: SUBJECTS[s]["species"] for s in SUBJECT_IDS}
    chosen = config["figures"]
    try:
        outline = outline_choice(
            species_of,
            DATASET["outlines"],
            chosen["outline_subjects"],
            chosen["outline_depth_mm"],
        )
        example = example_choice(
            species_of,
            DATASET["depths_mm"],
            chosen["example_subjects"],
            chosen["example_depth_mm"],
        )
    except ChoiceError as error:
        abort(str(error))
    return outline, example


OUTLINE, EXAMPLE = figure_choices()
OUTLINE_SUBJECTS = OUTLINE.subjects
# What was chosen and why, written to the log of the job that draws the figure.
FIGURE_CHOICES = {"outlines": [OUTLINE.log], "fits": [EXAMPLE.log]}

# The values a figure function may take as settings (lineload.figures.registry.ARGUMENTS).
FIGURE_SETTINGS = {
    "notice": NOTICE,
    "fit_window_mm": config["fit_window_mm"],
    "example_subjects": EXAMPLE.subjects,
    "example_depth_mm": EXAMPLE.depth_mm,
    "example_note": EXAMPLE.note,
    "outline_subjects": OUTLINE.subjects,
    "outline_depth_mm": OUTLINE.depth_mm,
    "schematic_depth_ratio": config["figures"]["schematic_depth_ratio"],
    "noise_mm": config["claims"]["noise_mm"],
}
# The results tables a figure function may take (registry kind "file").
FIGURE_TABLES = {
    "averaged": expand(result("data", "averaged", "{batch}.csv"), batch=BATCH_IDS),
    "fits": [result("tables", "fits.csv")],
    "outlines": expand(
        result("data", "outlines", "{subject}.csv"), subject=OUTLINE_SUBJECTS
    ),
    "sensitivity": [result("tables", "sensitivity.csv")],
    "checks": [result("tables", "trial_checks.csv")],
    "mechanics": [result("tables", "mechanics.csv")],
    "mechanics_trials": [result("tables", "mechanics_trials.csv")],
}


def figure_files(group):
    """PDF and PNG of every figure of a group (the report shows them through report_pages)."""
    files = []
    for figure in registry.figures_in_group(group):
        files += [
            result("figures", f"{figure.name}.pdf"),
            result("figures", f"{figure.name}.png"),
        ]
    return files


def figure_inputs(group):
    """Named inputs of a group's job: its spec, the tables its figures read, its code."""
    arguments = registry.arguments_of_group(group)
    subjects = [[s, SUBJECTS[s]["species"], SUBJECTS[s]["label"]] for s in SUBJECT_IDS]
    settings = {a: FIGURE_SETTINGS[a] for a in arguments if a in FIGURE_SETTINGS}
    inputs = {
        "spec": spec(
            f"figure_{group}",
            group=group,
            dpi=config["figures"]["png_dpi"],
            subjects=subjects if "subjects" in arguments else [],
            settings=settings,
            choices=FIGURE_CHOICES.get(group, []),
        ),
        "code": code(
            "draw_figures.py",
            sorted({f.import_path for f in registry.figures_in_group(group)}),
        ),
    }
    inputs.update({a: FIGURE_TABLES[a] for a in arguments if a in FIGURE_TABLES})
    return inputs


def article_inputs():
    """Named inputs of the article job: its spec, its source, the tables and every figure."""
    return {
        "spec": spec(
            "article",
            settings={
                "fit_window_mm": config["fit_window_mm"],
                "claims": config["claims"],
                "sensitivity": config["sensitivity"],
                "figures": {
                    key: FIGURE_SETTINGS[key]
                    for key in (
                        "example_subjects",
                        "example_depth_mm",
                        "outline_subjects",
                        "outline_depth_mm",
                    )
                },
            },
            subjects=SUBJECTS,
            depths_mm=DATASET["depths_mm"],
            notice=NOTICE,
            source_dir=str(Path(workflow.basedir).parent),
        ),
        "source": os.path.relpath(
            Path(workflow.basedir, "article", "reproduction.typ")
        ),
        "fits": result("tables", "fits.csv"),
        "claims": result("tables", "claims.csv"),
        "checks": result("tables", "trial_checks.csv"),
        "mechanics": result("tables", "mechanics.csv"),
        "figures": [f for f in FIGURE_FILES if f.endswith(".pdf")],
        "code": code("write_article.py"),
    }


# ---------------------------------------------------------------- the report's pages
# Snakemake's report shows HTML on the page (a CSV only as a download) and keeps captions
# behind an icon: each table and figure gets a page with its caption written out.
REPORT_TABLES = {
    "claims": (
        "The paper's claims, recomputed",
        result("tables", "claims.csv"),
        "Claims",
    ),
    "fits": ("Fits per subject and depth", result("tables", "fits.csv"), "Fits"),
    "summary": (
        "Summary per species and depth",
        result("tables", "summary.csv"),
        "Fits",
    ),
    "trial_checks": (
        "What the paper's approximations cost, per trial",
        result("tables", "trial_checks.csv"),
        "Supplement",
    ),
    "sensitivity": (
        "Refits under other analysis choices",
        result("tables", "sensitivity.csv"),
        "Supplement",
    ),
    "mechanics": (
        "The membrane per subject: pre-tension, stiffness, pre-strain",
        result("tables", "mechanics.csv"),
        "Mechanics",
    ),
    "mechanics_trials": (
        "The membrane per trial: strain, load angle, force",
        result("tables", "mechanics_trials.csv"),
        "Mechanics",
    ),
}


def report_page_inputs():
    """Named inputs of the report_pages job."""
    captions = Path(workflow.basedir, "report")
    names = [*REPORT_TABLES, *(f.name for f in registry.FIGURES), "data", "software"]
    return {
        "spec": spec(
            "report_pages",
            tables={
                name: [title, path] for name, (title, path, _) in REPORT_TABLES.items()
            },
            config=config,
            notice=NOTICE,
            subjects=SUBJECTS,
            depths_mm=DATASET["depths_mm"],
            source_dir=str(Path(workflow.basedir).parent),
        ),
        "tables": [path for _, path, _ in REPORT_TABLES.values()],
        "figures": [f for f in FIGURE_FILES if f.endswith(".png")],
        "captions": [os.path.relpath(captions / f"{name}.rst") for name in names],
        "code": code("write_report_pages.py"),
    }


def report_pages():
    """Every page of the report, each registered with its caption and category."""
    pages = []
    for name, (title, _, category) in REPORT_TABLES.items():
        pages.append(
            report_item(
                result("report", f"{name}.html"),
                caption=f"../report/{name}.rst",
                category=category,
                subcategory="Tables",
                labels={"table": title},
            )
        )
    supplements = [f for f in registry.FIGURES if f.category == "Supplement"]
    for figure in registry.FIGURES:
        # "Figure 2" or "Supplement 1" first, so the report lists them in the paper's order
        number = (
            f"Supplement {supplements.index(figure) + 1}"
            if figure in supplements
            else figure.name.replace("figure", "Figure ")
        )
        pages.append(
            report_item(
                result("report", f"{figure.name}.html"),
                caption=f"../report/{figure.name}.rst",
                category=figure.category,
                subcategory="Figures",
                labels={"figure": number, "shows": figure.title},
            )
        )
    for name, title, category in (
        ("data", "the subjects and depths", "Data"),
        ("software", "versions and source", "Provenance"),
    ):
        pages.append(
            report_item(
                result("report", f"{name}.html"),
                caption=f"../report/{name}.rst",
                category=category,
                subcategory="Pages",
                labels={"page": title},
            )
        )
    return pages


# Every figure file the default target builds (PDF and PNG of each).
FIGURE_FILES = [f for group in registry.GROUPS for f in figure_files(group)]


# ---------------------------------------------------------------- provenance
def raw_files():
    """Every raw input the build read: subject sheet, forces, profiles, outlines, notice."""
    files = [f"{RAW}/subjects.csv", *FORCES]
    files += [f"{RAW}/profiles/{s}.csv" for s in SUBJECT_IDS]
    files += [f"{RAW}/outlines/{s}.csv" for s in DATASET["outlines"]]
    if Path(RAW, "NOTICE.txt").is_file():
        files.append(f"{RAW}/NOTICE.txt")
    return files
