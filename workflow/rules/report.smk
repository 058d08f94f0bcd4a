# Stage 5, report: the provenance record of the build.


rule provenance:
    """Hash every raw input and record config, software versions and git commit."""
    input:
        spec=spec(
            "provenance",
            raw_dir=RAW,
            config=config,
            source_dir=str(Path(workflow.basedir).parent),
        ),
        raw=raw_files(),
        # built last, so the record is rewritten whenever any output is; listing every
        # intermediate here also makes each a target of the default build
        outputs=[
            expand(rules.prepare_profiles.output, batch=BATCH_IDS),
            expand(rules.fit_models.output, batch=BATCH_IDS),
            expand(rules.fit_sensitivity.output, batch=BATCH_IDS),
            expand(rules.prepare_outline.output, subject=DATASET["outlines"]),
            rules.fits_table.output,
            rules.sensitivity_tables.output,
            rules.fit_tables.output,
            rules.mechanics.output,
            rules.claims_table.output,
            FIGURE_FILES,
            rules.article.output,
            report_pages(),
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


rule report_pages:
    """The report's pages: each table and figure shown with its caption; data; software."""
    input:
        **report_page_inputs(),
    output:
        report_pages(),
    log:
        result("logs", "report_pages.log"),
    benchmark:
        result("benchmarks", "report_pages.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/write_report_pages.py"
