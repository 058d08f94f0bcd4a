"""Rule fit_models: every model for each subject and depth of a batch, all trials at once."""

from lineload.fitting.batch import FIT_COLUMNS, fit_trials
from lineload.fitting.inputs import labelled_rows, read_batch
from lineload.io import output_to, write_rows
from lineload.runtime.jobparams import given


def fit_models(averaged, noise, output, subjects, window_mm, other_windows_mm=()):
    """Fit every trial of the batch's subjects with its noise (the dataset's, with a
    digitised trial's registration error); one row per trial."""
    batch = read_batch(averaged, subjects, noise)  # numpy only: one job per batch
    # every trial of the batch in one call: the fits run for all of them together
    fitted = fit_trials(
        batch.distance_mm,
        batch.deflection_mm,
        batch.depth_mm,
        window_mm,
        noise=batch.noise,
        n_sides=batch.n_sides,
        other_windows_mm=other_windows_mm,
    )
    for subject, depth_mm, row in zip(batch.subject, batch.depth_mm, fitted, strict=True):
        print(
            f"{subject} {depth_mm:g} mm: {row['n_points']} points, "
            f"waterbed L = {row['waterbed_L_mm']:.3f} mm "
            f"[{row['waterbed_L_ci_low_mm']:.3f}, {row['waterbed_L_ci_high_mm']:.3f}], "
            f"RMSE waterbed/shifted/arc/Boussinesq = {row['waterbed_rmse_mm']:.4f}/"
            f"{row['shifted_rmse_mm']:.4f}/{row['arc_rmse_mm']:.4f}/"
            f"{row['boussinesq_rmse_mm']:.4f} mm"
        )
    write_rows(labelled_rows(batch, fitted), FIT_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_models(
            snakemake.input.averaged,
            snakemake.input.noise,
            snakemake.output[0],
            **given(snakemake.params),
        )
