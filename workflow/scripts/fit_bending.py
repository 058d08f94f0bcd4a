"""Rule fit_bending: the bending skin fitted to each subject and depth of a batch."""

from lineload.fitting.bending import BENDING_COLUMNS, fit_bending_trials
from lineload.io import output_to, read_rows, read_trials, write_rows
from lineload.noise import trial_models
from lineload.runtime.jobparams import given


def fit_bending(averaged, noise, output, subjects, window_mm, wall):
    """Fit L and the bending length of every trial of the batch, on the fit window the
    other models use, with each trial's noise for the intervals; one row per trial."""
    trials = read_trials(averaged, extra=("n_sides",))
    keys = [
        (subject, about["species"], depth_mm, *columns)
        for subject, about in subjects.items()
        for depth_mm, columns in trials.get(subject, {}).items()
    ]
    noise_models = trial_models(read_rows(noise), [(k[0], k[2]) for k in keys])
    fitted = fit_bending_trials(
        [k[3] for k in keys],
        [k[4] for k in keys],
        [k[2] for k in keys],
        window_mm,
        noise=noise_models,
        n_sides=[k[5] for k in keys],
        wall=wall,
    )
    rows = []
    for (subject, species, depth_mm, *_), row in zip(keys, fitted, strict=True):
        rows.append({"subject": subject, "species": species, **row})
        print(
            f"{subject} {depth_mm:g} mm: L = {row['bending_L_mm']:.3f} mm, bending length "
            f"{row['bending_length_mm']:.4g} mm [{row['bending_length_ci_low_mm']:.4g}, "
            f"{row['bending_length_ci_high_mm']:.4g}], RMSE {row['bending_rmse_mm']:.4f} mm"
        )
    write_rows(rows, BENDING_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_bending(
            snakemake.input.averaged,
            snakemake.input.noise,
            snakemake.output[0],
            **given(snakemake.params),
        )
