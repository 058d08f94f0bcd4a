# Stage 6, article: the reproduction written by the workflow from its own results.


rule article:
    """Typeset the reproduction article (Typst) from the results tables and figures."""
    input:
        source=os.path.relpath(WORKFLOW_DIR / "article" / "reproduction.typ"),
        references=os.path.relpath(WORKFLOW_DIR / "article" / "references.yml"),
        # the workflow's name, version and release date, printed in the title block
        citation=CITATION_FILES,
        checked=checked_raw_data,
        fits=rules.fits_table.output[0],
        bending=rules.bending_table.output[0],
        elastic=rules.elastic_fits.output[0],
        claims=rules.claims_table.output.csv,
        checks=rules.sensitivity_tables.output.checks,
        noise=rules.noise.output[0],
        mechanics=rules.mechanics.output.subjects,
        verdict_calibration=COMMITTED_CALIBRATION["verdicts"],
        coverage=COMMITTED_CALIBRATION["coverage"],
        boundary_calibration=COMMITTED_CALIBRATION["boundary"],
        mechanics_coverage=COMMITTED_CALIBRATION["mechanics_coverage"],
        bootstrap=COMMITTED_CALIBRATION["bootstrap"],
        # its trials: the design the calibration was computed for
        calibration_design=os.path.relpath(
            REPOSITORY / "docs" / "calibration" / "bootstrap_trials.csv"
        ),
        # what the reconstruction's generator built in (read only for its data)
        built_in=os.path.relpath(REPOSITORY / "data" / "built_in_verdicts.json"),
        figures=[f for f in FIGURE_FILES if f.endswith(".pdf")],
        # the photographed subjects' quality records and figures (none without photographs)
        digitised=expand(rules.digitise.output.quality, batch=list(DIGITISE_BATCHES)),
        digitised_figures=expand(
            rules.digitise.output.pdf, batch=list(DIGITISE_BATCHES)
        ),
        code=code("write_article.py"),
    output:
        pdf=report_item(
            result("article", "reproduction.pdf"),
            caption="../report/article.rst",
            category="Article",
            labels={"document": "the reproduction, as an article"},
        ),
        facts=result("article", "facts.json"),
        source=result("article", "reproduction.typ"),
        references=result("article", "references.yml"),
    log:
        result("logs", "article.log"),
    benchmark:
        result("benchmarks", "article.tsv")
    conda:
        ENVIRONMENT
    params:
        settings={
            "fit_window_mm": config["fit_window_mm"],
            "claims": config["claims"],
            "noise": config["noise"],
            "sensitivity": config["sensitivity"],
            "digitise": config["digitise"],
            # as configured; the job chooses those left unset, as the figure jobs do
            "figures": {key: config["figures"][key] for key in CHOICE_KEYS},
        },
        subjects=SUBJECTS,
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/write_article.py"
