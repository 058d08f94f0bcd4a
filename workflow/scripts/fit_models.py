"""Rule fit_models: every model for each subject and depth of a batch, all trials at once."""

from lineload.fitting import FIT_COLUMNS, fit_trials
from lineload.io import output_to, read_json, read_trials, write_rows


def fit_models(averaged, output, subjects, window_mm):
    """Fit every trial of the batch's subjects; write one row per subject and depth."""
    trials = read_trials(averaged)  # numpy only: this job runs once per batch
    keys = [
        (subject, about["species"], depth_mm, x, y)
        for subject, about in subjects.items()
        for depth_mm, (x, y) in trials.get(subject, {}).items()
    ]
    # every trial of the batch in one call: the fits run for all of them together
    fitted = fit_trials([k[3] for k in keys], [k[4] for k in keys], [k[2] for k in keys], window_mm)
    rows = []
    for (subject, species, depth_mm, _, _), row in zip(keys, fitted, strict=True):
        rows.append({"subject": subject, "species": species, **row})
        print(
            f"{subject} {depth_mm:g} mm: {row['n_points']} points, "
            f"waterbed L = {row['waterbed_L_mm']:.3f} mm, "
            f"RMSE waterbed/shifted/arc/Boussinesq = {row['waterbed_rmse_mm']:.4f}/"
            f"{row['shifted_rmse_mm']:.4f}/{row['arc_rmse_mm']:.4f}/"
            f"{row['boussinesq_rmse_mm']:.4f} mm"
        )
    write_rows(rows, FIT_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_models(snakemake.input.averaged, snakemake.output[0], **read_json(snakemake.input.spec))
