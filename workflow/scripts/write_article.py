"""Rule article: the facts of the text from the results tables, then the PDF with Typst.

The Typst source is copied beside the facts into <results>/article/ and compiled
there with the results folder as Typst's root, so that it reads the tables and
figures of this build and nothing else; fonts are Typst's own (no system fonts),
and the document carries no date, so two builds give the same bytes.
"""

import platform
import shutil
from pathlib import Path

import typst

from lineload.figures.choices import figure_settings
from lineload.io import (
    json_text,
    output_to,
    read_json,
    read_results_csv,
    read_rows,
    replaced_atomically,
    write_text,
)
from lineload.noise import reading_noise_mm
from lineload.publishing.article import (
    article_facts,
    bending_facts,
    calibration_design,
    elastic_facts,
    photograph_facts,
)
from lineload.publishing.citation import author_names, citation_or_default, software_name
from lineload.publishing.provenance import git_state, package_versions
from lineload.runtime.jobparams import given
from lineload.simulation.notices import DATA_NOTICE


def compile_pdf(source, root):
    """Typst's PDF of ``source``; a warning (an unknown font, say) is an error too."""
    try:
        pdf, warnings = typst.compile_with_warnings(
            str(source), root=str(root), ignore_system_fonts=True
        )
    except typst.TypstError as error:
        raise RuntimeError(f"Typst could not typeset {source}:\n{error.diagnostic}") from None
    if warnings:
        raise RuntimeError("\n".join(w.diagnostic for w in warnings))
    return pdf


def write_article(inputs, outputs, settings, subjects, notice, repository):
    """Write facts.json, the copy of the source, and the PDF."""
    citation = citation_or_default(inputs.citation)
    software = {
        "name": software_name(citation),
        "version": citation["version"],
        "released": citation.get("date-released", ""),
        # the byline: a placeholder until a release names the authors, shown as such
        "authors": author_names(citation)[0],
        "authors_placeholder": author_names(citation)[1],
        "python": platform.python_version(),
        "packages": package_versions(),
        "git": git_state(repository),
    }
    found = read_json(inputs.checked)
    depths_mm = found["depths_mm"]
    species_of = {subject: about["species"] for subject, about in subjects.items()}
    chosen, logs = figure_settings(species_of, depths_mm, found["outlines_mm"], settings["figures"])
    for line in logs["outlines"] + logs["fits"]:  # as the figure jobs chose
        print(line)
    settings = {**settings, "figures": {k: v for k, v in chosen.items() if k != "example_note"}}
    # one reading's noise as the claims used it: configured, else measured
    noise_mm = reading_noise_mm(read_rows(inputs.noise), settings["claims"]["noise_mm"])
    settings = {**settings, "claims": {**settings["claims"], "noise_mm": round(noise_mm, 4)}}
    facts = article_facts(
        read_results_csv(inputs.fits),
        read_results_csv(inputs.claims),
        read_results_csv(inputs.checks),
        subjects,
        depths_mm,
        settings,
        notice,
        software,
        read_results_csv(inputs.mechanics),
        {
            "verdicts": read_results_csv(inputs.verdict_calibration),
            "coverage": read_results_csv(inputs.coverage),
            "boundary": read_results_csv(inputs.boundary_calibration),
            "mechanics": read_results_csv(inputs.mechanics_coverage),
            "bootstrap": read_results_csv(inputs.bootstrap),
            "design": calibration_design(read_results_csv(inputs.calibration_design)),
        },
        # the generator's own list of what it built in: for its reconstruction only
        read_json(inputs.built_in) if notice == DATA_NOTICE.splitlines()[0] else None,
        results_name=Path(outputs.facts).resolve().parents[1].name,
    )
    # the subjects read from photographs: how well, and their quality figures
    results = Path(outputs.facts).resolve().parents[1]
    facts["photographs"] = photograph_facts(
        [read_json(path) for path in inputs.digitised],
        subjects,
        [Path(path).resolve().relative_to(results).as_posix() for path in inputs.digitised_figures],
    )
    # the bending skin, the paper's closing suggestion
    facts["bending"] = bending_facts(
        read_results_csv(inputs.bending),
        read_results_csv(inputs.fits),
        read_results_csv(inputs.claims),
    )
    # the layered elastic finger of the later literature
    facts["elastic"] = elastic_facts(
        read_results_csv(inputs.elastic), read_results_csv(inputs.fits)
    )
    write_text(json_text(facts), outputs.facts)
    with replaced_atomically(outputs.source) as temporary:
        shutil.copyfile(inputs.source, temporary)
    with replaced_atomically(outputs.references) as temporary:  # beside it, for Typst
        shutil.copyfile(inputs.references, temporary)
    root = Path(outputs.pdf).resolve().parents[1]  # the results folder
    pdf = compile_pdf(Path(outputs.source).resolve(), root)
    with replaced_atomically(outputs.pdf) as temporary:
        Path(temporary).write_bytes(pdf)
    print(f"{outputs.pdf}: {len(pdf)} bytes; {facts['verdicts']['sentence']}")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        write_article(
            snakemake.input,
            snakemake.output,
            **given(snakemake.params),
            repository=Path(snakemake.scriptdir).parents[1],  # for its git commit
        )
