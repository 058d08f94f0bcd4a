"""The workflow's figures: one shared style, one registry, one module per family.

Importing this package imports nothing heavy, so Snakemake can read the
registry when it parses the workflow; the drawing modules import matplotlib.

Modules
-------
registry
    The one list of figures (:data:`~lineload.figures.registry.FIGURES`): file
    name, the job that draws it, its function and the arguments it takes.
style
    The shared look (rcParams, colours, sizes), :func:`~lineload.figures.style.save_figure`,
    the data-notice footer, message figures and shared axis helpers.
data
    Figures drawn from the measurements: outlines (1), examples (2) and the
    per-species fits (6, 7).
schematics
    Figures 3-5, drawn from the model's equations alone.
supplements
    Residuals, parabola against arc, sensitivity and coordinates.
"""
