# Stage 3, figures: the paper's Figures 1-7 and the supplementary figures.
# lineload/figures/registry.py lists every figure once: the group (job) that draws
# it, its function and the arguments it takes.  One job per group, each drawing
# several figures in one Python process; every figure is written as PDF and PNG.


rule figure_outlines:
    """Figure 1: resting and deformed outlines, to scale (a note if there are none)."""
    input:
        **figure_inputs("outlines"),
    output:
        figure_files("outlines"),
    log:
        result("logs", "figure_outlines.log"),
    benchmark:
        result("benchmarks", "figure_outlines.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/draw_figures.py"


rule figure_schematics:
    """Figures 3-5: the waterbed model, material point and free-body diagrams, from eq. 19."""
    input:
        **figure_inputs("schematics"),
    output:
        figure_files("schematics"),
    log:
        result("logs", "figure_schematics.log"),
    benchmark:
        result("benchmarks", "figure_schematics.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/draw_figures.py"


rule figure_fits:
    """Figures 2, 6 and 7: averaged profiles against the fitted models."""
    input:
        **figure_inputs("fits"),
    output:
        figure_files("fits"),
    log:
        result("logs", "figure_fits.log"),
    benchmark:
        result("benchmarks", "figure_fits.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/draw_figures.py"


rule figure_supplements:
    """Supplementary figures: residuals, parabola against arc, sensitivity, coordinates."""
    input:
        **figure_inputs("supplements"),
    output:
        figure_files("supplements"),
    log:
        result("logs", "figure_supplements.log"),
    benchmark:
        result("benchmarks", "figure_supplements.tsv")
    priority: 1
    conda:
        ENVIRONMENT
    script:
        "../scripts/draw_figures.py"
