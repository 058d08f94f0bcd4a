"""Rule claims_table: recompute the paper's claims with verdicts."""

import sys
from dataclasses import replace

import pandas as pd

from lineload.claims import (
    CLAIM_COLUMNS,
    InternalError,
    claims_markdown,
    compute_claims,
    judged_settings,
    trial_key,
)
from lineload.fitting.bending import with_bending
from lineload.fitting.elastic import with_elastic
from lineload.io import output_to, read_results_csv, read_rows, write_csv, write_text
from lineload.noise import model_from_rows, trial_models
from lineload.priors import CHANGED_COLUMN, prior_column, refit_at_priors, with_prior_verdicts
from lineload.rawdata.validation import read_forces
from lineload.runtime.jobparams import given
from lineload.simulation.rates import claim_error_rates


def make_claims(inputs, outputs, settings, notice):
    """Compute the claims from fits, averaged profiles, noise and forces; write CSV, Markdown
    (with each rule's error rate from the committed calibration)."""
    fits_path, averaged_paths, noise_path = inputs.fits, inputs.averaged, inputs.noise
    forces_paths = list(inputs.forces)
    fits = with_bending(read_results_csv(fits_path), read_results_csv(inputs.bending))
    fits = with_elastic(fits, read_results_csv(inputs.elastic))
    averaged = pd.concat([read_results_csv(path) for path in averaged_paths], ignore_index=True)
    forces = read_forces(forces_paths[0]) if forces_paths else None
    rows = read_rows(noise_path)
    keys = list(zip(fits["subject"], fits["depth_mm"], strict=True))
    settings = judged_settings(settings, fits, model_from_rows(rows), trial_models(rows, keys))
    claims = compute_claims(fits, averaged, settings, forces=forces)
    by_multiple = {}
    for multiple in settings.prior_multiples:
        # every trial fitted and every claim judged again with the priors scaled
        scaled = {key: model.scaled_priors(multiple) for key, model in settings.trial_noise.items()}
        refitted = refit_at_priors(fits, averaged, [scaled[trial_key(*k)] for k in keys])
        # least squares: the bending and elastic fits (C13, C12) do not move with the priors
        refitted = with_elastic(with_bending(refitted, fits), fits)
        at_multiple = replace(
            settings,
            noise_model=settings.noise_model.scaled_priors(multiple),
            trial_noise=scaled,
        )
        by_multiple[multiple] = compute_claims(refitted, averaged, at_multiple, forces=forces)
    claims = with_prior_verdicts(claims, by_multiple)
    columns = [*CLAIM_COLUMNS, *(prior_column(m) for m in by_multiple), CHANGED_COLUMN]
    write_csv(claims, outputs.csv, columns=columns)
    error_rates = claim_error_rates(
        read_results_csv(inputs.verdict_calibration),
        read_results_csv(inputs.boundary_calibration),
    )
    write_text(claims_markdown(claims, notice, error_rates), outputs.md)
    for _, row in claims.iterrows():
        print(f"{row['claim']}: {row['verdict']} ({row['our_value']})")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        try:
            make_claims(snakemake.input, snakemake.output, **given(snakemake.params))
        except InternalError as error:
            # a bug, not a finding: one sentence where the user looks, no claims written
            print(f"Error: {error}")
            print(f"Error: {error}", file=sys.__stderr__)
            sys.exit(1)
