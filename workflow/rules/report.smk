# Stage 5, report: the report's pages and the provenance record of the build.

import textwrap

# Snakemake's report shows HTML on the page, but its view icon only downloads a CSV or
# JSON file (its template decides by the file's type), and it keeps captions behind an
# icon: each table and figure gets a page with its caption written out, and the page,
# not the data file, is the report's item; a table's page offers its CSV to download.
# Name -> (title, table, report category).
REPORT_TABLES = {
    "claims": (
        "The paper's claims, recomputed",
        rules.claims_table.output.csv,
        "Claims",
    ),
    "fits": ("Fits per subject and depth", rules.fits_table.output[0], "Fits"),
    "bending": (
        "The bending skin per subject and depth",
        rules.bending_table.output[0],
        "Fits",
    ),
    "elastic_fits": (
        "The elastic finger per subject and depth",
        rules.elastic_fits.output[0],
        "Fits",
    ),
    "summary": (
        "Summary per species and depth",
        rules.fit_tables.output.summary_csv,
        "Fits",
    ),
    "trial_checks": (
        "What the paper's approximations cost, per trial",
        rules.sensitivity_tables.output.checks,
        "Supplement",
    ),
    "sensitivity": (
        "Refits under other analysis choices",
        rules.sensitivity_tables.output.sensitivity,
        "Supplement",
    ),
    "mechanics": (
        "The membrane per subject: pre-tension, stiffness, pre-strain",
        rules.mechanics.output.subjects,
        "Mechanics",
    ),
    "mechanics_trials": (
        "The membrane per trial: strain, load angle, force",
        rules.mechanics.output.trials,
        "Mechanics",
    ),
    "noise": ("The digitising noise and its priors", rules.noise.output[0], "Fits"),
}
#: The readings of each batch of subjects, a page per batch beside its CSV under Data:
#: kind -> (title, subcategory); the tables are prepare_profiles' outputs of that name.
REPORT_READINGS = {
    "converted": ("Readings in tissue mm", "Readings in tissue mm"),
    "averaged": ("Left/right averages", "Left/right averages"),
}
#: The rule graph drawn for the README (docs/rulegraph.sh), when the checkout has it
#: (a copy of workflow/ deployed alone does not): Snakemake's own, on the landing page,
#: puts every rule in one column with its arcs beside it.
RULE_GRAPH = REPOSITORY / "docs" / "rulegraph.png"
# The pages that are not a table or a figure: name -> (label, category).
REPORT_OTHER_PAGES = {
    "data": ("the subjects and depths", "Data"),
    "software": ("versions and source", "Provenance"),
    **({"rulegraph": ("the rule graph", "Provenance")} if RULE_GRAPH.is_file() else {}),
}


#: The longest label of a page in the report's lists, in characters: the sidebar widens
#: to a list's longest line (at 69 characters it took half the screen from the figure
#: beside it), so a longer title is cut at a word with an ellipsis; the page shows it whole.
LABEL_WIDTH = 40

# Every page, registered with its caption and category: tables, figures (numbered
# "Figure 2" ... "Figure 12" as the article numbers them, in order), others.
REPORT_PAGES = [
    *(
        report_item(
            result("report", f"{name}.html"),
            caption=f"../report/{name}.rst",
            category=category,
            subcategory="Tables",
            labels={"table": textwrap.shorten(title, LABEL_WIDTH, placeholder=" …")},
        )
        for name, (title, _, category) in REPORT_TABLES.items()
    ),
    *(
        report_item(
            result("report", kind, f"{batch}.html"),
            caption="../report/readings.rst",
            category="Data",
            subcategory=subcategory,
            labels={"subjects": batch},
        )
        for kind, (_, subcategory) in REPORT_READINGS.items()
        for batch in BATCH_IDS
    ),
    *(
        report_item(
            result("report", f"{figure.name}.html"),
            caption=f"../report/{figure.name}.rst",
            category=figure.category,
            subcategory="Figures",
            labels={
                "figure": registry.report_label(figure),
                "shows": textwrap.shorten(figure.title, LABEL_WIDTH, placeholder=" …"),
            },
        )
        for figure in registry.FIGURES
    ),
    *(
        report_item(
            result("report", f"{name}.html"),
            caption=f"../report/{name}.rst",
            category=category,
            subcategory="Pages",
            labels={"page": title},
        )
        for name, (title, category) in REPORT_OTHER_PAGES.items()
    ),
]


rule report_pages:
    """The report's pages: each table and figure shown with its caption; data; software."""
    input:
        checked=checked_raw_data,
        tables=[table for _, table, _ in REPORT_TABLES.values()],
        readings=[
            path
            for kind in REPORT_READINGS
            for path in expand(
                getattr(rules.prepare_profiles.output, kind), batch=BATCH_IDS
            )
        ],
        figures=[f for f in FIGURE_FILES if f.endswith(".png")],
        rulegraph=[os.path.relpath(RULE_GRAPH)] if RULE_GRAPH.is_file() else [],
        captions=[
            os.path.relpath(WORKFLOW_DIR / "report" / f"{name}.rst")
            for name in [
                *REPORT_TABLES,
                *(f.name for f in registry.FIGURES),
                *REPORT_OTHER_PAGES,
                *REPORT_READINGS,
                "readings",
            ]
        ],
        code=code("write_report_pages.py"),
    output:
        REPORT_PAGES,
    log:
        result("logs", "report_pages.log"),
    benchmark:
        result("benchmarks", "report_pages.tsv")
    conda:
        ENVIRONMENT
    params:
        # [name, title] of each table, in the order of the input `tables`
        tables=[[name, title] for name, (title, _, _) in REPORT_TABLES.items()],
        # [kind, title, batch] of each readings table, in the order of `readings`
        readings=[
            [kind, title, batch]
            for kind, (title, _) in REPORT_READINGS.items()
            for batch in BATCH_IDS
        ],
        config=startup.portable_config(config),
        notice=lambda wildcards: NOTICE,
        subjects=SUBJECTS,
    script:
        "../scripts/write_report_pages.py"


#: The jobs of the rules that run once per batch or subject: their wildcards' values
#: (their outputs and their logs are expanded with these).
JOB_WILDCARDS = {
    "check_profiles": {"batch": BATCH_IDS},
    "digitise": {"batch": list(DIGITISE_BATCHES)},
    "prepare_profiles": {"batch": BATCH_IDS},
    "prepare_outline": {"subject": OUTLINED},
    "fit_models": {"batch": BATCH_IDS},
    "fit_bending": {"batch": BATCH_IDS},
    "fit_sensitivity": {"batch": BATCH_IDS},
}
#: Every output of the default build by the rule that writes it, from the rules defined
#: so far (every stage before the records below; the calibration and the targets come
#: later), in the order they are defined: the provenance record depends on them all,
#: and the run crate names each file's rule.
OUTPUTS_BY_RULE = {
    stage.name: expand(
        getattr(rules, stage.name).output, **JOB_WILDCARDS.get(stage.name, {})
    )
    for stage in workflow.rules
}
# a rule that runs per batch or subject lists its jobs' wildcards above
for stage in workflow.rules:
    if stage.has_wildcards() and stage.name not in JOB_WILDCARDS:
        raise WorkflowError(
            f"rule {stage.name}: its jobs' wildcards are not in JOB_WILDCARDS"
        )


rule provenance:
    """Hash every raw input and record config, software versions and git commit."""
    input:
        # every raw file the build read: subject sheet, forces, profiles, outlines, notice
        raw=[
            f"{RAW}/subjects.csv",
            *FORCES,
            *RAW_PROFILES.values(),
            # the photographs' sheet and every photograph it names
            *([RAW_FILES["images"]["images.csv"]] if PHOTOGRAPHS else []),
            *(
                [RAW_FILES["images"]["truth.csv"]]
                if PHOTOGRAPHS and "truth.csv" in RAW_FILES["images"]
                else []
            ),
            *(f for files in PHOTOGRAPHS.values() for f in files),
            *(RAW_FILES["outlines"][f"{s}.csv"] for s in OUTLINED),
            *([RAW_FILES["notice"]] if RAW_FILES["notice"] else []),
        ],
        # built last, so the record is rewritten whenever any output is; listing every
        # intermediate here also makes each a target of the default build
        outputs=[f for files in OUTPUTS_BY_RULE.values() for f in files],
        code=code("write_provenance.py"),
    output:
        # on the report as a page (provenance_page), this file its download
        result("provenance.json"),
    log:
        result("logs", "provenance.log"),
    benchmark:
        result("benchmarks", "provenance.tsv")
    conda:
        ENVIRONMENT
    params:
        config=startup.portable_config(config),
    script:
        "../scripts/write_provenance.py"


rule provenance_page:
    """The provenance record as a page of the report, with the record to download."""
    input:
        record=rules.provenance.output[0],
        caption=os.path.relpath(WORKFLOW_DIR / "report" / "provenance.rst"),
        code=code("write_provenance_page.py"),
    output:
        report_item(
            result("report", "provenance.html"),
            caption="../report/provenance.rst",
            category="Provenance",
            subcategory="Pages",
            labels={"page": "the provenance record"},
        ),
    log:
        result("logs", "provenance_page.log"),
    benchmark:
        result("benchmarks", "provenance_page.tsv")
    conda:
        ENVIRONMENT
    params:
        config=startup.portable_config(config),
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/write_provenance_page.py"


# ------------------------------------------------------------------ the run as an RO-Crate

from lineload.publishing.bundle import bundle_name
from lineload.publishing.citation import citation_or_default, software_name
from lineload.publishing.crate import source_files
from lineload.runtime.gitcommit import head_commit

CITATION = citation_or_default(CITATION_FILES)
#: The workflow's source as the crate and the bundle carry it (a copy under source/,
#: so the results folder is a whole run).
SOURCE_FILES = source_files(REPOSITORY)
#: Each rule of the default build: what it does and its source in the crate's copy.
CRATE_RULES = {
    name: {
        "description": " ".join((getattr(rules, name).rule.docstring or name).split()),
        "source": "source/"
        + Path(
            os.path.relpath(getattr(rules, name).rule.snakefile, REPOSITORY)
        ).as_posix(),
    }
    for name in [*OUTPUTS_BY_RULE, "provenance", "provenance_page"]
}


rule crate:
    """The run as a Workflow Run RO-Crate: every file with its hash and rule, the config,
    the software; the raw inputs and the source copied in, so results/ is a whole run.
    """
    input:
        provenance=rules.provenance.output[0],
        provenance_page=rules.provenance_page.output[0],
        citation=CITATION_FILES,
        # the raw inputs, the subject sheet first (the raw folder is its folder)
        raw=rules.provenance.input.raw,
        outputs=[f for files in OUTPUTS_BY_RULE.values() for f in files],
        source=[os.path.relpath(REPOSITORY / name) for name in SOURCE_FILES],
        code=code("write_crate.py"),
    output:
        metadata=result("ro-crate-metadata.json"),
        inputs=directory(result("inputs")),
        source=directory(result("source")),
    log:
        result("logs", "crate.log"),
    benchmark:
        result("benchmarks", "crate.tsv")
    conda:
        ENVIRONMENT
    params:
        files=crate_files,
        rules=CRATE_RULES,
    script:
        "../scripts/write_crate.py"


# ------------------------------------------------------------------ the bundle (on request)


rule bundle:
    """On request: the run crate (results, raw inputs, source) as one reproducible zip
    with SHA256SUMS; every file the crate lists, and nothing else."""
    input:
        crate=rules.crate.output.metadata,
        folders=[rules.crate.output.inputs, rules.crate.output.source],
        provenance=rules.provenance.output[0],
        citation=rules.crate.input.citation,
        code=code("write_bundle.py"),
    output:
        result(
            "bundle",
            bundle_name(
                software_name(CITATION),
                CITATION["version"],
                head_commit(REPOSITORY),
            ),
        ),
    log:
        result("logs", "bundle.log"),
    conda:
        ENVIRONMENT
    params:
        # the crate's list of files and rules, as the crate job was given it
        files=crate_files,
        rules=CRATE_RULES,
        date=str(CITATION.get("date-released") or "1980-01-01"),
    script:
        "../scripts/write_bundle.py"
