"""Rule bootstrap: a parametric bootstrap of the data's own fits - do its intervals cover?"""

from lineload.io import output_to, read_rows, read_trials, write_rows, write_text
from lineload.noise import model_from_rows, trial_models
from lineload.runtime.jobparams import given
from lineload.simulation.coverage import (
    COVERAGE_COLUMNS,
    TRIAL_COLUMNS,
    bootstrap_study,
    summarise_coverage,
)
from lineload.simulation.reports import bootstrap_markdown, calibration_command

#: Each model's fitted parameters, as the fit table names them.
FITTED = {
    "waterbed": {"L_mm": "waterbed_L_mm"},
    "arc": {"L_mm": "arc_L_mm"},
    "boussinesq": {"A_mm": "boussinesq_A_mm", "x0_mm": "boussinesq_x0_mm"},
}


def bootstrap(inputs, outputs, seed, replicates, window_mm, notice):
    """Replicate every trial from its fits with the measured noise; write the coverage."""
    grids = {}
    for path in inputs.averaged:
        for subject, depths in read_trials(path).items():
            for depth_mm, (distance_mm, _) in depths.items():
                keep = (distance_mm > 0) & (distance_mm <= window_mm + 0.5)
                grids[(subject, depth_mm)] = distance_mm[keep]
    fit_rows = read_rows(inputs.fits)
    noise_rows = read_rows(inputs.noise)
    noise = model_from_rows(noise_rows)
    # each trial's own model: the dataset's, or a photographed trial's registration error
    own = trial_models(noise_rows, [(r["subject"], float(r["depth_mm"])) for r in fit_rows])
    fitted = [
        {
            "species": row["species"],
            "depth_mm": float(row["depth_mm"]),
            "distance_mm": grids[(row["subject"], float(row["depth_mm"]))],
            "noise": model,
            **{
                name: {p: float(row[column] or "nan") for p, column in columns.items()}
                for name, columns in FITTED.items()
            },
        }
        for row, model in zip(fit_rows, own, strict=True)
    ]
    rows = bootstrap_study(fitted, seed, replicates, noise, window_mm)
    summary = summarise_coverage(rows)
    write_rows(rows, TRIAL_COLUMNS, outputs.trials)
    write_rows(summary, COVERAGE_COLUMNS, outputs.summary)
    command = calibration_command(seed, bootstrap_replicates=replicates)
    write_text(bootstrap_markdown(summary, command, len(fitted), notice), outputs.markdown)
    for row in summary:
        if row["species"] == "all":
            print(f"{row['model']} {row['parameter']}: {row['n_covered']}/{row['n_trials']}")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        bootstrap(snakemake.input, snakemake.output, **given(snakemake.params))
