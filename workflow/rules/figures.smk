# Stage 3, figures: the paper's Figures 1-7 and the supplementary figures.
# lineload/figures/registry.py lists every figure once: the group (job) that draws
# it, its function and the arguments it takes.  One job per group, each drawing
# several figures in one Python process; every figure is written as PDF and PNG.
from lineload.figures import registry
from lineload.figures.choices import CHOICE_KEYS

# The settings a figure function may take (registry kind "setting").  The subjects and
# depths of Figures 1 and 2 are as configured here; the job chooses those left unset
# from the depths the raw-data check found, and logs what it chose and why.
FIGURE_SETTINGS = {
    "notice": NOTICE,
    "fit_window_mm": config["fit_window_mm"],
    **{key: config["figures"][key] for key in CHOICE_KEYS},
    "schematic_depth_ratio": config["figures"]["schematic_depth_ratio"],
    "noise_mm": config["claims"]["noise_mm"],
}
# The results tables a figure function may take (registry kind "file"), each a list:
# the job reads the files of one name as one table.
FIGURE_TABLES = {
    "averaged": expand(rules.prepare_profiles.output.averaged, batch=BATCH_IDS),
    "fits": [rules.fits_table.output[0]],
    "outlines": expand(rules.prepare_outline.output[0], subject=OUTLINED),
    "sensitivity": [rules.sensitivity_tables.output.sensitivity],
    "checks": [rules.sensitivity_tables.output.checks],
    "mechanics": [rules.mechanics.output.subjects],
    "mechanics_trials": [rules.mechanics.output.trials],
    "noise": [rules.noise.output[0]],
    "bending": [rules.bending_table.output[0]],
    "elastic": [rules.elastic_fits.output[0]],
    "elastic_library": [rules.elastic_fits.input.library],
    # the committed calibration, so the default build draws it without running it
    "coverage": [COMMITTED_CALIBRATION["coverage"]],
}
# Per group: the settings its figures take; the subject sheet ([subject, species,
# label] in sheet order) if they take it; its named inputs (the raw-data check, the
# tables, the code); its files (PDF and PNG of each figure).
GROUP_SETTINGS = {
    group: {
        a: FIGURE_SETTINGS[a]
        for a in registry.arguments_of_group(group, "setting")
        if a in FIGURE_SETTINGS
    }
    for group in registry.GROUPS
}
GROUP_SUBJECTS = {
    group: (
        [[s, SUBJECTS[s]["species"], SUBJECTS[s]["label"]] for s in SUBJECT_IDS]
        if "subjects" in registry.arguments_of_group(group)
        else []
    )
    for group in registry.GROUPS
}
GROUP_INPUTS = {
    group: {
        "checked": checked_raw_data,
        **{name: FIGURE_TABLES[name] for name in registry.file_arguments(group)},
        "code": code(
            "draw_figures.py",
            sorted({f.import_path for f in registry.figures_in_group(group)}),
        ),
    }
    for group in registry.GROUPS
}
GROUP_FILES = {
    group: [
        result("figures", f"{figure.name}.{ext}")
        for figure in registry.figures_in_group(group)
        for ext in ("pdf", "png")
    ]
    for group in registry.GROUPS
}
# Every figure file the default target builds.
FIGURE_FILES = [f for group in registry.GROUPS for f in GROUP_FILES[group]]


# One rule per group, figure_<group>, all alike: the group's figures drawn by one
# script from the registry's entries.
#   figure_outlines    Figure 1: resting and deformed outlines, to scale
#   figure_schematics  Figures 3-5: the waterbed model, material point, free body (eq. 19)
#   figure_fits        Figures 2, 6 and 7: averaged profiles against the fitted models
#   figure_supplements residuals, parabola against arc, sensitivity, coordinates
#   figure_families    the later model families: the bending skin beside the other
#                      families and its bending lengths; the elastic finger's fits and
#                      its modulus ratios (one job: one matplotlib start-up for both)
#   figure_calibration coverage when the priors are wrong (the committed calibration)
for group in registry.GROUPS:

    rule:
        name:
            f"figure_{group}"
        input:
            **GROUP_INPUTS[group],
        output:
            GROUP_FILES[group],
        log:
            result("logs", f"figure_{group}.log"),
        benchmark:
            result("benchmarks", f"figure_{group}.tsv")
        priority: PRIORITY.get(f"figure_{group}", 0)
        conda:
            ENVIRONMENT
        params:
            group=group,
            dpi=config["figures"]["png_dpi"],
            subjects=GROUP_SUBJECTS[group],
            settings=GROUP_SETTINGS[group],
        script:
            "../scripts/draw_figures.py"
