"""Rule fit_tables: fit table and species summary as Markdown, LaTeX and CSV."""

from lineload.io import output_to, read_results_csv, write_csv, write_text
from lineload.publishing.tables import (
    SUMMARY_COLUMNS,
    fits_latex,
    fits_markdown,
    summarise_fits,
    summary_latex,
    summary_markdown,
)
from lineload.runtime.jobparams import given


def make_tables(fits_path, outputs, notice):
    """Write the fit table and the species summary in every format."""
    fits = read_results_csv(fits_path)
    summary = summarise_fits(fits)
    write_text(fits_markdown(fits, notice), outputs.fits_md)
    write_text(fits_latex(fits, notice), outputs.fits_tex)
    write_csv(summary, outputs.summary_csv, columns=SUMMARY_COLUMNS)
    write_text(summary_markdown(summary, notice), outputs.summary_md)
    write_text(summary_latex(summary, notice), outputs.summary_tex)
    print(f"{fits_path}: {len(fits)} trials -> {len(summary)} species/depth rows")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        make_tables(snakemake.input.fits, snakemake.output, **given(snakemake.params))
