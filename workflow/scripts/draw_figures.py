"""Rules figure_*: draw one group of figures from the registry, each as PDF and PNG.

The job's params name the group, the PNG resolution, the subject list and the
settings its figures take; the subjects and depths of Figures 1 and 2 left unset
there are chosen here from the depths the raw-data check found, and the choice
is printed to the log with its reason.  The tables they read are the job's named
inputs.
Which function draws each figure, and with which arguments, is in
lineload.figures.registry.
"""

import sys
from importlib import import_module
from pathlib import Path

import pandas as pd

from lineload.figures import registry
from lineload.figures.choices import CHOICE_KEYS, ChoiceError, figure_settings
from lineload.figures.style import save_figure
from lineload.io import output_to, read_json, read_results_csv
from lineload.runtime.jobparams import given


def choose(settings, group, checked, species_of):
    """The settings with Figures 1 and 2's subjects and depth chosen; log the choice."""
    if not set(CHOICE_KEYS) & set(settings):
        return settings
    found = read_json(checked)
    configured = {key: settings.get(key) for key in CHOICE_KEYS}
    configured["example_subjects"] = configured["example_subjects"] or []
    configured["outline_subjects"] = configured["outline_subjects"] or []
    chosen, logs = figure_settings(species_of, found["depths_mm"], found["outlines_mm"], configured)
    for line in logs[group]:  # which subjects and depth a figure shows, and why
        print(line)
    if chosen["example_note"] and "example_note" in registry.arguments_of_group(group):
        print(f"note: {chosen['example_note']}")
    wanted = registry.arguments_of_group(group)
    return {**settings, **{k: v for k, v in chosen.items() if k in wanted}}


def draw_figures(inputs, outputs, group, dpi, subjects, settings):
    """Draw and save every figure of ``group``; log the choices made for them."""
    species_of = {subject: species for subject, species, _ in subjects}
    values = choose(settings, group, inputs.checked, species_of)
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
    try:
        with output_to(snakemake.log[0]):
            draw_figures(snakemake.input, snakemake.output, **given(snakemake.params))
    except ChoiceError as error:  # a configured choice the data cannot satisfy: one line
        sys.stderr.write(f"Error: {error}\n")
        sys.exit(1)
