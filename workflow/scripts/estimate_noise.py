"""Rule noise: the digitising noise of the dataset, from the left-right differences."""

from lineload.io import output_to, read_json, read_trials, write_rows
from lineload.noise import NOISE_COLUMNS, estimate_noise, noise_rows, noise_trials


def noise_table(averaged, output, priors, max_trials, window_mm):
    """Measure the noise from the trials' left-right differences; write the noise table."""
    profiles = [
        (x, left, right)
        for path in averaged
        for depths in read_trials(path, extra=("left_mm", "right_mm")).values()
        for x, _, left, right in depths.values()
    ]
    trials = noise_trials(profiles, window_mm, max_trials)
    estimate = estimate_noise(trials, max_trials=max_trials)
    rows = noise_rows(estimate, priors)
    for row in rows:
        print(f"{row['parameter']} = {row['value']:.4g} (SE {row['se']:.2g}; {row['source']})")
    print(f"{estimate.n_trials} trials, {estimate.n_differences} left-right differences")
    write_rows(rows, NOISE_COLUMNS, output)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        noise_table(
            snakemake.input.averaged, snakemake.output[0], **read_json(snakemake.input.spec)
        )
