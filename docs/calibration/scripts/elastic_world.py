"""A calibration world the fits do not assume: the finite-element finger, read with errors.

The study's functions live in :mod:`lineload.simulation.elastic_world`; this script runs them
at the committed size and writes the tables beside ``docs/calibration/elastic_world.md``:

1. **Profiles** (``elastic_world_profiles.csv``, kept so that the second half reruns without
   the solver): :data:`~lineload.simulation.elastic_world.SECTIONS_PER_SPECIES` sections per
   species the library does not hold (seed
   :data:`~lineload.simulation.elastic_world.SECTION_SEED`), each at the ratios
   :data:`~lineload.simulation.elastic_world.RATIOS`, solved at the library's four depths on
   a mesh of grade :data:`~lineload.simulation.elastic_world.GRADE` (the library's is 0.4).
   Solved only when the table is missing or with ``--solve``.
2. **Scores**: :data:`DATASETS` datasets per ratio, each every section of both species at
   that ratio, read with fresh digitising errors (seed ``(SEED, world, dataset)``) and
   analysed as the workflow does: ``elastic_world_coverage.csv`` (the paper's models'
   intervals against their best fit to the error-free profile), ``elastic_world_verdicts.csv``
   and ``elastic_world_verdict_datasets.csv`` (each claim's verdict against its truth),
   ``elastic_world_ratio.csv`` and ``elastic_world_ratio_trials.csv`` (the layered fit's ratio).
   The same worlds again on the first :data:`PRIOR_DATASETS` datasets' draws with the errors
   the left-right differences cannot measure at :data:`PRIOR_RATIO` times their stated sizes
   (worlds named ``..., shared errors 2x``), the priors stated as configured.

Run: ``python docs/calibration/scripts/elastic_world.py [--solve] [--datasets N]``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import pandas as pd
import yaml

from lineload.elastic.library import LibraryGrid
from lineload.fitting.elastic import library_blocks
from lineload.io import config_defaults
from lineload.simulation import elastic_world as world

REPO = Path(__file__).resolve().parents[3]
OUT = REPO / "docs" / "calibration"
PROFILES = OUT / "elastic_world_profiles.csv"
#: Seed of the datasets' errors, and datasets per world.
SEED, DATASETS = 3614, 20
#: The worlds again with the errors the left-right differences cannot measure at this
#: multiple of their stated sizes (the priors stated as configured), on the first
#: ``PRIOR_DATASETS`` datasets' draws: how the scores move when the priors are wrong.
PRIOR_RATIO, PRIOR_DATASETS = 2.0, 10


def solve(grid):
    frames = []
    for species in ("monkey", "human"):
        sections = world.world_sections(species, grid)
        frames.append(world.solve_world_profiles(species, sections, world.RATIOS, grid.depths_mm))
    return pd.concat(frames, ignore_index=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--solve", action="store_true", help="solve the profiles again")
    parser.add_argument("--datasets", type=int, default=DATASETS, help="datasets per world")
    args = parser.parse_args()
    grid = LibraryGrid.from_config(config_defaults("elastic"))
    if args.solve or not PROFILES.exists():
        wall, cpu = time.perf_counter(), time.process_time()
        solve(grid).to_csv(PROFILES, index=False)
        print(
            f"profiles solved in {time.perf_counter() - wall:.1f} s "
            f"({time.process_time() - cpu:.1f} s of CPU)"
        )
    solutions = world.solutions_from_table(pd.read_csv(PROFILES))
    blocks = library_blocks(pd.read_csv(REPO / config_defaults("elastic")["library_file"]))
    noise = config_defaults("noise")
    max_trials = noise.pop("max_trials")
    schema = yaml.safe_load((REPO / "workflow" / "schemas" / "config.schema.yaml").read_text())
    window_mm = float(schema["properties"]["fit_window_mm"]["default"])
    wall, cpu = time.perf_counter(), time.process_time()
    scores = world.world_study(
        solutions,
        SEED,
        args.datasets,
        window_mm,
        noise,
        max_trials,
        blocks,
        config_defaults("claims"),
        ratios=world.RATIOS,
    )
    print(
        f"{args.datasets} datasets per world scored in {time.perf_counter() - wall:.1f} s "
        f"({time.process_time() - cpu:.1f} s of CPU)"
    )
    wall, cpu = time.perf_counter(), time.process_time()
    wrong = world.world_study(
        solutions,
        SEED,
        min(PRIOR_DATASETS, args.datasets),
        window_mm,
        noise,
        max_trials,
        blocks,
        config_defaults("claims"),
        ratios=world.RATIOS,
        prior_ratio=PRIOR_RATIO,
    )
    for part, rows in wrong.items():
        scores[part] += rows
    print(
        f"and with the shared errors {PRIOR_RATIO:g}x in {time.perf_counter() - wall:.1f} s "
        f"({time.process_time() - cpu:.1f} s of CPU)"
    )
    coverage = pd.DataFrame(world.summarise_world_coverage(scores["coverage"]))
    verdicts = pd.DataFrame(world.summarise_world_verdicts(scores["verdicts"]))
    ratio = pd.DataFrame(world.summarise_ratio(scores["ratio"]))
    coverage.to_csv(OUT / "elastic_world_coverage.csv", index=False, float_format="%.6g")
    verdicts.to_csv(OUT / "elastic_world_verdicts.csv", index=False, float_format="%.6g")
    pd.DataFrame(scores["verdicts"], columns=world.VERDICT_COLUMNS).to_csv(
        OUT / "elastic_world_verdict_datasets.csv", index=False
    )
    ratio.to_csv(OUT / "elastic_world_ratio.csv", index=False, float_format="%.6g")
    pd.DataFrame(scores["ratio"], columns=world.RATIO_COLUMNS).to_csv(
        OUT / "elastic_world_ratio_trials.csv", index=False, float_format="%.6g"
    )
    with pd.option_context("display.width", 200, "display.max_rows", 500):
        print(coverage[coverage["species"] == "all"].to_string())
        print(verdicts.to_string())
        print(ratio.to_string())


if __name__ == "__main__":
    main()
