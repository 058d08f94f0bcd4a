"""Rule report_pages: the report's HTML pages, a table or a figure each with its caption.

Captions are the workflow's caption files (workflow/report/*.rst), rendered as
Snakemake renders them (Jinja with the config, then reStructuredText to HTML).
"""

import platform
from pathlib import Path

from lineload.figures import registry
from lineload.io import output_to, read_json, read_results_csv, write_text
from lineload.publishing.article import group_depths_text
from lineload.publishing.provenance import git_state, package_versions
from lineload.publishing.reportpages import (
    caption,
    download_link,
    figure_page,
    table_page,
    versions_page,
)
from lineload.runtime.jobparams import given


def csv_download(path):
    """A table's CSV, offered on its page (the report itself only downloads a CSV)."""
    return download_link(Path(path).name, Path(path).read_bytes(), "text/csv")


def write_report_pages(inputs, outputs, tables, readings, config, notice, subjects, repository):
    """Write every page listed in the job's params into the folder of the job's outputs."""
    captions = Path(inputs.captions[0]).parent
    folder = Path(outputs[0]).parent
    depths_mm = read_json(inputs.checked)["depths_mm"]
    for (name, title), path in zip(tables, inputs.tables, strict=True):
        frame = read_results_csv(path)
        text = table_page(
            title,
            list(frame.columns),
            frame.itertuples(index=False),
            caption(captions / f"{name}.rst", config),
            notice,
            csv_download(path),
        )
        write_text(text, folder / f"{name}.html")
    # each batch's readings under its kind, captioned as its CSV is
    for (kind, title, batch), path in zip(readings, inputs.readings, strict=True):
        frame = read_results_csv(path)
        text = table_page(
            f"{title}: {batch}",
            list(frame.columns),
            frame.itertuples(index=False),
            caption(captions / f"{kind}.rst", config, {"batch": batch}),
            notice,
            csv_download(path),
        )
        write_text(text, folder / kind / f"{batch}.html")
    for figure in registry.FIGURES:
        png = Path(inputs.figures[0]).parent / f"{figure.name}.png"
        text = figure_page(
            figure.title,
            png.read_bytes(),
            caption(captions / f"{figure.name}.rst", config),
            notice,
        )
        write_text(text, folder / f"{figure.name}.html")
    by_species = {}
    for subject, about in subjects.items():
        by_species.setdefault(about["species"], []).append(subject)
    # a subject measured at fewer depths than its species is named (as in the article)
    rows = [
        (species, len(members), ", ".join(members), group_depths_text(members, depths_mm))
        for species, members in by_species.items()
    ]
    data = table_page(
        "The data",
        ["species", "subjects", "ids", "depths"],
        rows,
        caption(captions / "data.rst", config),
        notice,
    )
    write_text(data, folder / "data.html")
    git = git_state(repository)
    versions = [("python", platform.python_version())]
    versions += [(n, v) for n, v in package_versions().items() if v]
    versions += [("commit", git["commit"] or "unknown"), ("uncommitted changes", str(git["dirty"]))]
    write_text(
        versions_page("Software", versions, caption(captions / "software.rst", config)),
        folder / "software.html",
    )
    if inputs.rulegraph:
        graph = Path(inputs.rulegraph[0]).read_bytes()
        text = figure_page("The rule graph", graph, caption(captions / "rulegraph.rst", config))
        write_text(text, folder / "rulegraph.html")
    print(
        f"{len(tables)} tables, {len(readings)} tables of readings, {len(registry.FIGURES)}"
        f" figures, the data, the software{', the rule graph' if inputs.rulegraph else ''}"
    )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        write_report_pages(
            snakemake.input,
            snakemake.output,
            **given(snakemake.params),
            repository=Path(snakemake.scriptdir).parents[1],  # for its git commit
        )
