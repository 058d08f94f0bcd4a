"""Rule fit_models: every model for each subject and depth of a batch, all trials at once."""

from lineload.fitting.batch import FIT_COLUMNS, fit_trials
from lineload.io import output_to, read_rows, read_trials, write_rows
from lineload.noise import trial_models
from lineload.runtime.jobparams import given


def fit_models(averaged, noise, output, subjects, window_mm, other_windows_mm=()):
    """Fit every trial of the batch's subjects with its noise (the dataset's, with a
    digitised trial's registration error); one row per trial."""
    trials = read_trials(averaged, extra=("n_sides",))  # numpy only: one job per batch
    keys = [
        (subject, about["species"], depth_mm, *columns)
        for subject, about in subjects.items()
        for depth_mm, columns in trials.get(subject, {}).items()
    ]
    noise_models = trial_models(read_rows(noise), [(k[0], k[2]) for k in keys])
    # every trial of the batch in one call: the fits run for all of them together
    fitted = fit_trials(
        [k[3] for k in keys],
        [k[4] for k in keys],
        [k[2] for k in keys],
        window_mm,
        noise=noise_models,
        n_sides=[k[5] for k in keys],
        other_windows_mm=other_windows_mm,
    )
    rows = []
    for (subject, species, depth_mm, *_), row in zip(keys, fitted, strict=True):
        rows.append({"subject": subject, "species": species, **row})
        print(
            f"{subject} {depth_mm:g} mm: {row['n_points']} points, "
            f"waterbed L = {row['waterbed_L_mm']:.3f} mm "
            f"[{row['waterbed_L_ci_low_mm']:.3f}, {row['waterbed_L_ci_high_mm']:.3f}], "
            f"RMSE waterbed/shifted/arc/Boussinesq = {row['waterbed_rmse_mm']:.4f}/"
            f"{row['shifted_rmse_mm']:.4f}/{row['arc_rmse_mm']:.4f}/"
            f"{row['boussinesq_rmse_mm']:.4f} mm"
        )
    write_rows(rows, FIT_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_models(
            snakemake.input.averaged,
            snakemake.input.noise,
            snakemake.output[0],
            **given(snakemake.params),
        )
