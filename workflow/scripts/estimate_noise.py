"""Rule noise: the digitising noise of the dataset, from the left-right differences."""

import os

from lineload.io import output_to, read_json, read_trials, write_rows
from lineload.noise import NOISE_COLUMNS, measure_noise_table
from lineload.runtime.jobparams import given


def registrations(quality):
    """``(subject, depth_mm, registration_sd_mm, file, reading_sd_mm)`` of every
    digitised trial (its registration's error and its readings' own, from the digitise
    records)."""
    records = []
    for path in quality:
        for record in read_json(path)["subjects"]:  # a digitise batch's subjects
            for trial in record["trials"]:
                own_um = trial.get("own_reading_sd_um")
                records.append(
                    (
                        record["subject"],
                        trial["depth_mm"],
                        trial["registration_sd_um"] / 1000.0,
                        os.path.basename(path),
                        None if own_um is None else own_um / 1000.0,
                    )
                )
    return records


def noise_table(averaged, output, priors, max_trials, window_mm, quality=()):
    """Measure the noise from the trials' left-right differences; write the noise table,
    with each digitised trial's registration error (``quality``: the digitise records)."""
    profiles = [
        (x, left, right)
        for path in averaged
        for depths in read_trials(path, extra=("left_mm", "right_mm")).values()
        for x, _, left, right in depths.values()
    ]
    estimate, rows = measure_noise_table(
        profiles, priors, window_mm, max_trials, registrations(quality)
    )
    for row in rows:
        print(
            f"{row['scope']}: {row['parameter']} = {row['value']:.4g} "
            f"(SE {row['se']:.2g}; {row['source']})"
        )
    print(f"{estimate.n_trials} trials, {estimate.n_differences} left-right differences")
    write_rows(rows, NOISE_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        noise_table(
            snakemake.input.averaged,
            snakemake.output[0],
            **given(snakemake.params),
            quality=snakemake.input.quality,
        )
