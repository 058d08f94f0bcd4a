"""How near the wedge's tip a misplaced wedge makes a reading land.

A reading taken at ``x`` sees the skin at ``x`` plus the wedge's shift (left side; minus
on the right); :data:`lineload.simulation.errors.SEEN_FLOOR_MM` stops it at the tip.
The generator and the coverage study once floored it differently (0 and 1 um).  This
counts, over the shipped data, the verdict calibration's datasets and the coverage
study's (the committed settings), the readings and the nearest landing: where no
reading lands within 1 um of the tip, the two floors give the same numbers.

Run: ``python docs/calibration/scripts/wedge_tip.py`` (prints one line per study).
"""

from __future__ import annotations

import numpy as np

from lineload.simulation import coverage, errors, readings, subjects

SEED, VERDICT_DATASETS, COVERAGE_DATASETS = 2026, 200, 40


def main():
    found = {"nearest": np.inf, "n": 0, "below": 0}
    floored = errors.seen_distance_mm

    def spy(distance_mm, side, wedge_shift_mm):
        sign = 1.0 if side == "left" else -1.0
        raw = np.asarray(distance_mm, dtype=float) + sign * wedge_shift_mm
        found["nearest"] = min(found["nearest"], float(raw.min()))
        found["n"] += raw.size
        found["below"] += int(np.count_nonzero(raw < 1e-3))
        return floored(distance_mm, side, wedge_shift_mm)

    def report(what):
        print(
            f"{what}: {found['n']} readings, nearest landing {found['nearest']:.4f} mm "
            f"from the tip, {found['below']} within 1 um"
        )
        found.update(nearest=np.inf, n=0, below=0)

    errors.seen_distance_mm = spy
    for subject in subjects.shipped_subjects():
        readings.profile_table(subject, subjects.DEFAULT_SEED)
    report(f"shipped data (seed {subjects.DEFAULT_SEED})")
    for k in range(VERDICT_DATASETS):
        for subject in subjects.shipped_subjects():
            readings.profile_table(subject, (SEED, k))
    report(f"verdict calibration ({VERDICT_DATASETS} datasets, seed {SEED})")
    for i, scenario in enumerate(coverage.SCENARIOS):
        for j, model in enumerate(coverage.CHECKED):
            for k in range(COVERAGE_DATASETS):
                coverage.simulate_dataset(model, (SEED, i, j, k), 3.0, scenario)
    report(f"coverage study ({COVERAGE_DATASETS} datasets per scenario and model, seed {SEED})")


if __name__ == "__main__":
    main()
