"""Rule fit_bending: the bending skin fitted to each subject and depth of a batch."""

from lineload.fitting.bending import BENDING_COLUMNS, fit_bending_trials
from lineload.fitting.inputs import labelled_rows, read_batch
from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given


def fit_bending(averaged, noise, output, subjects, window_mm, wall):
    """Fit L and the bending length of every trial of the batch, on the fit window the
    other models use, with each trial's noise for the intervals; one row per trial."""
    batch = read_batch(averaged, subjects, noise)
    fitted = fit_bending_trials(
        batch.distance_mm,
        batch.deflection_mm,
        batch.depth_mm,
        window_mm,
        noise=batch.noise,
        n_sides=batch.n_sides,
        wall=wall,
    )
    for subject, depth_mm, row in zip(batch.subject, batch.depth_mm, fitted, strict=True):
        print(
            f"{subject} {depth_mm:g} mm: L = {row['bending_L_mm']:.3f} mm, bending length "
            f"{row['bending_length_mm']:.4g} mm [{row['bending_length_ci_low_mm']:.4g}, "
            f"{row['bending_length_ci_high_mm']:.4g}], RMSE {row['bending_rmse_mm']:.4f} mm"
        )
    write_rows(labelled_rows(batch, fitted), BENDING_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_bending(
            snakemake.input.averaged,
            snakemake.input.noise,
            snakemake.output[0],
            **given(snakemake.params),
        )
