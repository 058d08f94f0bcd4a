# Stage 4, tables: fit tables in CSV/Markdown/LaTeX, species summary, claims.


rule fit_tables:
    """Fit table as Markdown and LaTeX; summary per species and depth (CSV, Markdown, LaTeX)."""
    input:
        fits=rules.fits_table.output[0],
        code=code("make_tables.py"),
    output:
        fits_md=result("tables", "fits.md"),
        fits_tex=result("tables", "fits.tex"),
        summary_csv=result("tables", "summary.csv"),
        summary_md=result("tables", "summary.md"),
        summary_tex=result("tables", "summary.tex"),
    log:
        result("logs", "fit_tables.log"),
    benchmark:
        result("benchmarks", "fit_tables.tsv")
    priority: PRIORITY["fit_tables"]
    conda:
        ENVIRONMENT
    params:
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/make_tables.py"


rule claims_table:
    """Recompute the paper's claims from the fits, averaged profiles and forces, with verdicts."""
    input:
        fits=rules.fits_table.output[0],
        # C13: the bending skin against the waterbed
        bending=rules.bending_table.output[0],
        # C12: the layered elastic finger against the homogeneous one
        elastic=rules.elastic_fits.output[0],
        averaged=expand(rules.prepare_profiles.output.averaged, batch=BATCH_IDS),
        noise=rules.noise.output[0],
        # C11 checks the measured forces too when there are any
        forces=FORCES,
        verdict_calibration=COMMITTED_CALIBRATION["verdicts"],
        boundary_calibration=COMMITTED_CALIBRATION["boundary"],
        code=code("make_claims.py"),
    output:
        csv=result("tables", "claims.csv"),
        md=result("tables", "claims.md"),
    log:
        result("logs", "claims_table.log"),
    benchmark:
        result("benchmarks", "claims_table.tsv")
    priority: PRIORITY["claims_table"]
    conda:
        ENVIRONMENT
    params:
        settings={
            **config["claims"],
            "force_sd_N": config["mechanics"]["force_sd_N"],
        },
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/make_claims.py"
