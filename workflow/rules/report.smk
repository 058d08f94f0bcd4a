# Stage 5, report: the report's pages and the provenance record of the build.

# Snakemake's report shows HTML on the page (a CSV only as a download) and keeps captions
# behind an icon: each table and figure gets a page with its caption written out.
# Name -> (title, table, report category).
REPORT_TABLES = {
    "claims": (
        "The paper's claims, recomputed",
        rules.claims_table.output.csv,
        "Claims",
    ),
    "fits": ("Fits per subject and depth", rules.fits_table.output[0], "Fits"),
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
}
# The pages that are not a table or a figure: name -> (label, category).
REPORT_OTHER_PAGES = {
    "data": ("the subjects and depths", "Data"),
    "software": ("versions and source", "Provenance"),
}


# Every page, registered with its caption and category: tables, figures (numbered
# "Figure 2" ... "Figure 12" as the article numbers them, in order), others.
REPORT_PAGES = [
    *(
        report_item(
            result("report", f"{name}.html"),
            caption=f"../report/{name}.rst",
            category=category,
            subcategory="Tables",
            labels={"table": title},
        )
        for name, (title, _, category) in REPORT_TABLES.items()
    ),
    *(
        report_item(
            result("report", f"{figure.name}.html"),
            caption=f"../report/{figure.name}.rst",
            category=figure.category,
            subcategory="Figures",
            labels={"figure": registry.report_label(figure), "shows": figure.title},
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
        spec=spec(
            "report_pages",
            # [name, title] of each table, in the order of the input `tables`
            tables=[[name, title] for name, (title, _, _) in REPORT_TABLES.items()],
            config=startup.portable_config(config),
            notice=NOTICE,
            subjects=SUBJECTS,
        ),
        checked=checked_raw_data,
        tables=[table for _, table, _ in REPORT_TABLES.values()],
        figures=[f for f in FIGURE_FILES if f.endswith(".png")],
        captions=[
            os.path.relpath(Path(workflow.basedir, "report", f"{name}.rst"))
            for name in [
                *REPORT_TABLES,
                *(f.name for f in registry.FIGURES),
                *REPORT_OTHER_PAGES,
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
    script:
        "../scripts/write_report_pages.py"


rule provenance:
    """Hash every raw input and record config, software versions and git commit."""
    input:
        spec=spec("provenance", config=startup.portable_config(config)),
        # every raw file the build read: subject sheet, forces, profiles, outlines, notice
        raw=[
            f"{RAW}/subjects.csv",
            *FORCES,
            *PROFILES.values(),
            *(RAW_FILES["outlines"][f"{s}.csv"] for s in OUTLINED),
            *([RAW_FILES["notice"]] if RAW_FILES["notice"] else []),
        ],
        # built last, so the record is rewritten whenever any output is; listing every
        # intermediate here also makes each a target of the default build
        outputs=[
            rules.check_raw_data.output,
            expand(rules.prepare_profiles.output, batch=BATCH_IDS),
            expand(rules.fit_models.output, batch=BATCH_IDS),
            expand(rules.fit_sensitivity.output, batch=BATCH_IDS),
            expand(rules.prepare_outline.output, subject=OUTLINED),
            rules.fits_table.output,
            rules.sensitivity_tables.output,
            rules.fit_tables.output,
            rules.mechanics.output,
            rules.claims_table.output,
            FIGURE_FILES,
            rules.article.output,
            rules.report_pages.output,
        ],
        code=code("write_provenance.py"),
    output:
        report_item(
            result("provenance.json"),
            caption="../report/provenance.rst",
            category="Data",
            labels={"file": "provenance record"},
        ),
    log:
        result("logs", "provenance.log"),
    benchmark:
        result("benchmarks", "provenance.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/write_provenance.py"
