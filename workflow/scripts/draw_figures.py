"""Rules figure_*: draw one group of figures from the registry, each as PDF and PNG.

The job's spec names the group, the PNG resolution, the subject list, the
settings its figures take and, in words, the subjects and depths chosen for
them (printed to the log); the tables they read are the job's named inputs.
Which function draws each figure, and with which arguments, is in
lineload.figures.registry.
"""

from importlib import import_module
from pathlib import Path

import pandas as pd

from lineload.figures import registry
from lineload.figures.style import save_figure
from lineload.io import output_to, read_json, read_results_csv


def draw_figures(inputs, outputs, group, dpi, subjects, settings, choices=()):
    """Draw and save every figure of ``group``; log the choices made for them."""
    for line in choices:  # which subjects and depth a figure shows, and why
        print(line)
    values = dict(settings)
    values["subjects"] = pd.DataFrame(subjects, columns=["subject", "species", "label"])
    for name in registry.file_arguments(group):
        frames = [read_results_csv(path) for path in inputs[name]]
        values[name] = pd.concat(frames, ignore_index=True) if frames else None
    folder = Path(outputs[0]).parent
    print(f"footer: {values['notice']!r}" if values.get("notice") else "footer: none")
    for figure in registry.figures_in_group(group):
        draw = getattr(import_module(figure.import_path), figure.function)
        fig = draw(**{a: values[a] for a in figure.arguments}, **dict(figure.fixed))
        pdf, png = folder / f"{figure.name}.pdf", folder / f"{figure.name}.png"
        save_figure(fig, pdf, png, dpi)
        print(f"{figure.name}: {len(fig.axes)} axes -> {pdf}, {png} ({dpi} dpi)")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        draw_figures(snakemake.input, snakemake.output, **read_json(snakemake.input.spec))
