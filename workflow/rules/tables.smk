# Stage 4, tables: fit tables in CSV/Markdown/LaTeX, species summary, claims.


rule fit_tables:
    """Fit table as Markdown and LaTeX; summary per species and depth (CSV, Markdown, LaTeX)."""
    input:
        code=code_inputs("make_tables.py"),
        fits=result("tables", "fits.csv"),
    output:
        fits_md=result("tables", "fits.md"),
        fits_tex=result("tables", "fits.tex"),
        summary_csv=report(
            result("tables", "summary.csv"),
            caption="../report/summary.rst",
            category="Fits",
            labels={"table": "summary per species and depth"},
        ),
        summary_md=result("tables", "summary.md"),
        summary_tex=result("tables", "summary.tex"),
    log:
        result("logs", "fit_tables.log"),
    conda:
        ENVIRONMENT
    params:
        notice=NOTICE,
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} --fits {input.fits:q} --notice={params.notice:q}"
        " --fits-md {output.fits_md:q} --fits-tex {output.fits_tex:q}"
        " --summary-csv {output.summary_csv:q} --summary-md {output.summary_md:q}"
        " --summary-tex {output.summary_tex:q} > {log:q} 2>&1"


rule claims_table:
    """Recompute the paper's claims C1-C10 from the fits and averaged profiles, with verdicts."""
    input:
        code=code_inputs("make_claims.py"),
        fits=result("tables", "fits.csv"),
        averaged=expand(result("data", "averaged", "{batch}.csv"), batch=BATCH_IDS),
    output:
        csv=report(
            result("tables", "claims.csv"),
            caption="../report/claims.rst",
            category="Claims",
            labels={"table": "claims C1-C10"},
        ),
        md=result("tables", "claims.md"),
    log:
        result("logs", "claims_table.log"),
    conda:
        ENVIRONMENT
    params:
        noise_mm=config["claims"]["noise_mm"],
        large_depth_mm=config["claims"]["large_depth_mm"],
        symmetry_tolerance=config["claims"]["symmetry_tolerance"],
        misfit_growth=config["claims"]["misfit_growth"],
        significance=config["claims"]["significance"],
        notice=NOTICE,
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} --fits {input.fits:q} --averaged {input.averaged:q}"
        " --noise-mm {params.noise_mm} --large-depth-mm {params.large_depth_mm}"
        " --symmetry-tolerance {params.symmetry_tolerance}"
        " --misfit-growth {params.misfit_growth} --significance {params.significance}"
        " --notice={params.notice:q} --csv {output.csv:q} --md {output.md:q} > {log:q} 2>&1"


# Every table file the default target builds.
TABLE_OUTPUTS = [
    *rules.fit_tables.output,
    *rules.claims_table.output,
]
