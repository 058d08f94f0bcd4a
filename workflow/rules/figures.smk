# Stage 3, figures: the paper's Figures 1-7 and the supplementary figures.
# Four jobs, each drawing several figures in one Python process (one matplotlib
# import per job).  Every figure is written as PDF and PNG by make_figures.py.
import shlex

# Figures drawn by each rule (file stems under results/figures/).
FIGURE_GROUPS = {
    "figure_outlines": ["figure1"],
    "figure_schematics": ["figure3", "figure4", "figure5"],
    "figure_fits": ["figure2", "figure6", "figure7"],
    "figure_supplement": ["supplement_residuals", "supplement_arc_vs_parabola"],
}


def figure_files(group):
    """PDF and PNG of every figure a rule draws."""
    return [
        result("figures", f"{name}.{ext}")
        for name in FIGURE_GROUPS[group]
        for ext in ("pdf", "png")
    ]


def figure_args(group):
    """'--figure NAME' for every figure a rule draws."""
    return " ".join(f"--figure {name}" for name in FIGURE_GROUPS[group])


def subject_label(subject):
    """Display name of a subject: the sheet's optional label column, else its id."""
    if "label" in SUBJECTS.columns:
        label = SUBJECTS.loc[subject, "label"]
        if isinstance(label, str) and label.strip():
            return label.strip()
    return subject


# Every figure file the default target builds (PDF and PNG of each).
FIGURE_OUTPUTS = [path for group in FIGURE_GROUPS for path in figure_files(group)]

# Shared arguments: the subject list (id, species, label) in sheet order, the
# PNG resolution and the footer; the figure stage reads results files only.
FIGURE_SUBJECT_ARGS = " ".join(
    f"--subject {shlex.quote(s)} {SUBJECTS.loc[s, 'species']} {shlex.quote(subject_label(s))}"
    for s in SUBJECT_IDS
)
FIGURE_OUTDIR = result("figures")
# The drawing code is an input too, so editing the figures' style redraws them.
FIGURE_CODE = [SCRIPTS / "make_figures.py", WORKFLOW_DIR / "lineload" / "plotting.py"]
FIGURE_DPI = config["figures"]["png_dpi"]


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
    params:
        python=PYTHON,
        script=SCRIPTS / "make_figures.py",
        figures=figure_args("figure_outlines"),
        outdir=FIGURE_OUTDIR,
        dpi=FIGURE_DPI,
        notice=NOTICE,
        subjects=FIGURE_SUBJECT_ARGS,
        depth=(
            f"--outline-depth-mm {OUTLINE_DEPTH_MM}"
            if OUTLINE_DEPTH_MM is not None
            else ""
        ),
    shell:
        "{params.python} {params.script:q} {params.figures} --outdir {params.outdir:q}"
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
    params:
        python=PYTHON,
        script=SCRIPTS / "make_figures.py",
        figures=figure_args("figure_schematics"),
        outdir=FIGURE_OUTDIR,
        dpi=FIGURE_DPI,
        notice=NOTICE,
        ratio=config["figures"]["schematic_depth_ratio"],
    shell:
        "{params.python} {params.script:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q}"
        " --schematic-depth-ratio {params.ratio} > {log:q} 2>&1"


rule figure_fits:
    """Figures 2, 6 and 7: averaged profiles against the fitted models."""
    input:
        code=FIGURE_CODE,
        averaged=expand(
            result("data", "averaged", "{subject}.csv"), subject=SUBJECT_IDS
        ),
        fits=result("tables", "fits.csv"),
    output:
        figure_files("figure_fits"),
    log:
        result("logs", "figure_fits.log"),
    params:
        python=PYTHON,
        script=SCRIPTS / "make_figures.py",
        figures=figure_args("figure_fits"),
        outdir=FIGURE_OUTDIR,
        dpi=FIGURE_DPI,
        notice=NOTICE,
        subjects=FIGURE_SUBJECT_ARGS,
        examples=" ".join(
            f"--example-subject {shlex.quote(s)}" for s in EXAMPLE_SUBJECTS
        ),
        example_depth_mm=EXAMPLE_DEPTH_MM,
        window_mm=config["fit_window_mm"],
    shell:
        "{params.python} {params.script:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q} {params.subjects}"
        " --averaged {input.averaged:q} --fits {input.fits:q} {params.examples}"
        " --example-depth-mm {params.example_depth_mm}"
        " --fit-window-mm {params.window_mm} > {log:q} 2>&1"


rule figure_supplement:
    """Supplementary figures: residuals of the three fits; parabola against exact arc."""
    input:
        code=FIGURE_CODE,
        averaged=expand(
            result("data", "averaged", "{subject}.csv"), subject=SUBJECT_IDS
        ),
        fits=result("tables", "fits.csv"),
    output:
        figure_files("figure_supplement"),
    log:
        result("logs", "figure_supplement.log"),
    params:
        python=PYTHON,
        script=SCRIPTS / "make_figures.py",
        figures=figure_args("figure_supplement"),
        outdir=FIGURE_OUTDIR,
        dpi=FIGURE_DPI,
        notice=NOTICE,
        subjects=FIGURE_SUBJECT_ARGS,
        window_mm=config["fit_window_mm"],
    shell:
        "{params.python} {params.script:q} {params.figures} --outdir {params.outdir:q}"
        " --dpi {params.dpi} --notice={params.notice:q} {params.subjects}"
        " --averaged {input.averaged:q} --fits {input.fits:q}"
        " --fit-window-mm {params.window_mm} > {log:q} 2>&1"


rule figures:
    """Only the figures (and what they need)."""
    input:
        FIGURE_OUTPUTS,
