"""Rule elastic_fits: the homogeneous and the layered finger fitted to every trial."""

import time

import pandas as pd

from lineload.fitting.elastic import ELASTIC_COLUMNS, fit_elastic_trials, library_blocks
from lineload.fitting.inputs import labelled_rows, read_batch
from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given


def fit_elastic(averaged, library, noise, output, batches, window_mm):
    """Fit both fingers by interpolation in the kept library, on the fit window the other
    models use, with each trial's noise for the ratio's interval; one row per trial, in the
    subject sheet's order."""
    try:
        blocks = library_blocks(pd.read_csv(library))
    except (ValueError, KeyError, pd.errors.ParserError) as error:
        raise SystemExit(
            f"{library}: not the elastic finger's solution library ({error}); rebuild it with "
            "`snakemake elastic_library` or point elastic.library_file at one"
        ) from None
    rows = []
    for table, subjects in zip(averaged, batches, strict=True):
        batch = read_batch(table, subjects, noise)
        start = time.perf_counter()
        fitted = fit_elastic_trials(
            batch.distance_mm,
            batch.deflection_mm,
            batch.species,
            batch.depth_mm,
            window_mm,
            blocks,
            noise=batch.noise,
            n_sides=batch.n_sides,
        )
        seconds = time.perf_counter() - start
        print(f"{table}: {len(batch)} trials in {1000 * seconds:.1f} ms")
        for subject, depth_mm, row in zip(batch.subject, batch.depth_mm, fitted, strict=True):
            print(
                f"  {subject} {depth_mm:g} mm: ratio {row['elastic_layered_modulus_ratio']:.3g} "
                f"[{row['elastic_layered_ratio_ci_low']:.3g}, "
                f"{row['elastic_layered_ratio_ci_high']:.3g}], RMSE homogeneous "
                f"{row['elastic_homogeneous_rmse_mm']:.4f} mm, layered "
                f"{row['elastic_layered_rmse_mm']:.4f} mm {row['elastic_note']}"
            )
        rows += labelled_rows(batch, fitted)
    write_rows(rows, ELASTIC_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_elastic(
            list(snakemake.input.averaged),
            snakemake.input.library,
            snakemake.input.noise,
            snakemake.output[0],
            **given(snakemake.params),
        )
