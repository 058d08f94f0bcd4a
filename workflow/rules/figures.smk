# Stage 3, figures: the paper's Figures 1-7 and the supplementary figures.
# lineload/figures/registry.py lists every figure once: the group (job) that draws
# it, its function and the arguments it takes.  One job per group, each drawing
# several figures in one Python process; every figure is written as PDF and PNG.


def first_of_each_species(candidates):
    """The first subject of each species among candidates, in subject-sheet order."""
    chosen = {}
    for subject in SUBJECT_IDS:
        if subject in candidates:
            chosen.setdefault(SUBJECTS[subject]["species"], subject)
    return list(chosen.values())


def chosen_subjects(key, candidates, need):
    """Subjects named in config['figures'][key], checked, or the default choice."""
    requested = config["figures"][key]
    for subject in requested:
        if subject not in candidates:
            abort(f"config, key 'figures/{key}': subject {subject!r} {need}")
    return list(requested) or first_of_each_species(candidates)


OUTLINE_SUBJECTS = chosen_subjects(
    "outline_subjects", DATASET["outlines"], f"has no outline file in {RAW}/outlines/"
)
OUTLINE_DEPTH_MM = config["figures"]["outline_depth_mm"]
if OUTLINE_SUBJECTS:
    common_depths = set.intersection(
        *(set(DATASET["outlines"][s]) for s in OUTLINE_SUBJECTS)
    )
    if OUTLINE_DEPTH_MM is None and common_depths:
        OUTLINE_DEPTH_MM = min(common_depths)
    if OUTLINE_DEPTH_MM not in common_depths:
        abort(
            "config, key 'figures/outline_depth_mm': expected a depth outlined for "
            f"{', '.join(OUTLINE_SUBJECTS)} ({', '.join(f'{d:g}' for d in sorted(common_depths))}),"
            f" got {OUTLINE_DEPTH_MM}"
        )
EXAMPLE_DEPTH_MM = config["figures"]["example_depth_mm"]
EXAMPLE_SUBJECTS = chosen_subjects(
    "example_subjects",
    [s for s in SUBJECT_IDS if EXAMPLE_DEPTH_MM in DATASET["depths_mm"][s]],
    f"is not in {RAW}/subjects.csv or has no profile at the figure depth",
)

# The values a figure function may take as settings (lineload.figures.registry.ARGUMENTS).
FIGURE_SETTINGS = {
    "notice": NOTICE,
    "fit_window_mm": config["fit_window_mm"],
    "example_subjects": EXAMPLE_SUBJECTS,
    "example_depth_mm": EXAMPLE_DEPTH_MM,
    "outline_subjects": OUTLINE_SUBJECTS,
    "outline_depth_mm": OUTLINE_DEPTH_MM,
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
}


def figure_files(group):
    """PDF and PNG of every figure of a group; the PNG goes into the report."""
    files = []
    for figure in registry.figures_in_group(group):
        caption, labels = f"../report/{figure.name}.rst", {"figure": figure.title}
        png = result("figures", f"{figure.name}.png")
        files += [
            result("figures", f"{figure.name}.pdf"),
            report_item(png, caption=caption, category=figure.category, labels=labels),
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
        ),
        "code": code(
            "draw_figures.py",
            [f"lineload.figures.{m}" for m in registry.modules_of_group(group)],
        ),
    }
    inputs.update({a: FIGURE_TABLES[a] for a in arguments if a in FIGURE_TABLES})
    return inputs


# Every figure file the default target builds (PDF and PNG of each).
FIGURE_FILES = [f for group in registry.GROUPS for f in figure_files(group)]


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
    script:
        "../scripts/draw_figures.py"
