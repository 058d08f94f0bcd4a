"""Rule mechanics: membrane geometry per trial; pre-tension, stiffness, pre-strain per subject."""

from lineload.io import output_to, read_results_csv, write_csv
from lineload.mechanics import SUBJECT_COLUMNS, TRIAL_COLUMNS, mechanics_tables
from lineload.rawdata.validation import read_forces
from lineload.runtime.jobparams import given


def fit_mechanics(fits_path, forces_paths, outputs, contact_length_mm, force_sd_N):
    """Write mechanics.csv and mechanics_trials.csv from the fit table and the forces."""
    fits = read_results_csv(fits_path)
    forces = read_forces(forces_paths[0]) if forces_paths else None
    subjects, trials = mechanics_tables(fits, forces, contact_length_mm, force_sd_N)
    write_csv(subjects, outputs.subjects, columns=SUBJECT_COLUMNS)
    write_csv(trials, outputs.trials, columns=TRIAL_COLUMNS)
    print(
        f"{len(trials)} trials, {0 if forces is None else len(forces)} forces; "
        f"{len(subjects)} subjects fitted (force precision {force_sd_N:g} N)"
    )
    for row in subjects.itertuples():
        print(
            f"{row.subject}: prestrain {row.prestrain:.3f} +- {row.prestrain_se:.3f}, "
            f"N0 {row.pretension_N_per_mm:.4f} N/mm, E {row.stiffness_N_per_mm:.4f} N/mm, "
            f"chi2 {row.chi2:.2f} on {row.dof} dof"
        )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        fit_mechanics(
            snakemake.input.fits,
            list(snakemake.input.forces),
            snakemake.output,
            **given(snakemake.params),
        )
