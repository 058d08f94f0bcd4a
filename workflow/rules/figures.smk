# Stage 3, figures: the paper's Figures 1-7 and the supplementary figures.
# Four jobs, each drawing several figures in one Python process (one matplotlib
# import per job).  Every figure is written as PDF and PNG by make_figures.py.
rule figure_outlines:
    """Figure 1: resting and deformed outlines, to scale (a note if there are none)."""
    input:
        code=FIGURE_CODE,
        outlines=expand(
            result("data", "outlines", "{subject}.csv"), subject=OUTLINE_SUBJECTS
        ),
    output:
        figure_files("figure_outlines"),
    log:
        result("logs", "figure_outlines.log"),
    benchmark:
        result("benchmarks", "figure_outlines.tsv")
    conda:
        ENVIRONMENT
    params:
        figures=figure_args("figure_outlines"),
        outdir=lambda wildcards, output: str(Path(output[0]).parent),
        dpi=FIGURE_DPI,
        notice=NOTICE,
        subjects=FIGURE_SUBJECT_ARGS,
        depth=(
            f"--outline-depth-mm {OUTLINE_DEPTH_MM}"
            if OUTLINE_DEPTH_MM is not None
            else ""
        ),
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q} {params.subjects}"
        " --outline {input.outlines:q} {params.depth} > {log:q} 2>&1"


rule figure_schematics:
    """Figures 3-5: the waterbed model, material point and free-body diagrams, from eq. 19."""
    input:
        code=FIGURE_CODE,
    output:
        figure_files("figure_schematics"),
    log:
        result("logs", "figure_schematics.log"),
    benchmark:
        result("benchmarks", "figure_schematics.tsv")
    conda:
        ENVIRONMENT
    params:
        figures=figure_args("figure_schematics"),
        outdir=lambda wildcards, output: str(Path(output[0]).parent),
        dpi=FIGURE_DPI,
        notice=NOTICE,
        ratio=config["figures"]["schematic_depth_ratio"],
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q}"
        " --schematic-depth-ratio {params.ratio} > {log:q} 2>&1"


rule figure_fits:
    """Figures 2, 6 and 7: averaged profiles against the fitted models."""
    input:
        code=FIGURE_CODE,
        averaged=expand(result("data", "averaged", "{batch}.csv"), batch=BATCH_IDS),
        fits=result("tables", "fits.csv"),
    output:
        figure_files("figure_fits"),
    log:
        result("logs", "figure_fits.log"),
    benchmark:
        result("benchmarks", "figure_fits.tsv")
    conda:
        ENVIRONMENT
    params:
        figures=figure_args("figure_fits"),
        outdir=lambda wildcards, output: str(Path(output[0]).parent),
        dpi=FIGURE_DPI,
        notice=NOTICE,
        subjects=FIGURE_SUBJECT_ARGS,
        examples=" ".join(
            f"--example-subject {shlex.quote(s)}" for s in EXAMPLE_SUBJECTS
        ),
        example_depth_mm=EXAMPLE_DEPTH_MM,
        window_mm=config["fit_window_mm"],
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q} {params.subjects}"
        " --averaged {input.averaged:q} --fits {input.fits:q} {params.examples}"
        " --example-depth-mm {params.example_depth_mm}"
        " --fit-window-mm {params.window_mm} > {log:q} 2>&1"


rule figure_supplement:
    """Supplementary figures: residuals, parabola against arc, sensitivity, coordinates."""
    input:
        code=FIGURE_CODE,
        averaged=expand(result("data", "averaged", "{batch}.csv"), batch=BATCH_IDS),
        fits=result("tables", "fits.csv"),
        sensitivity=result("tables", "sensitivity.csv"),
        checks=result("tables", "trial_checks.csv"),
    output:
        figure_files("figure_supplement"),
    log:
        result("logs", "figure_supplement.log"),
    benchmark:
        result("benchmarks", "figure_supplement.tsv")
    priority: 1
    conda:
        ENVIRONMENT
    params:
        figures=figure_args("figure_supplement"),
        outdir=lambda wildcards, output: str(Path(output[0]).parent),
        dpi=FIGURE_DPI,
        notice=NOTICE,
        subjects=FIGURE_SUBJECT_ARGS,
        window_mm=config["fit_window_mm"],
        noise_mm=config["claims"]["noise_mm"],
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q} {params.subjects}"
        " --averaged {input.averaged:q} --fits {input.fits:q}"
        " --sensitivity {input.sensitivity:q} --checks {input.checks:q}"
        " --fit-window-mm {params.window_mm} --noise-mm {params.noise_mm} > {log:q} 2>&1"


rule figures:
    """Only the figures (and what they need)."""
    input:
        FIGURE_OUTPUTS,
