"""How dense the minimiser's grid over L must be, and how many evaluations Brent's method takes.

The fits without a closed form (the shifted parabola and the exact arc) search L over
``[L_lo, 1000 L_lo]``: a log-spaced grid finds the basin of the least sum of squares, and
Brent's method refines it (:func:`lineload.fitting.optimize.minimize_bounded`).  The grid
only has to land in the deepest basin.  This study fits profiles of the shipped design
(:func:`lineload.simulation.coverage.simulate_dataset`: the waterbed's, the exact arc's and
Boussinesq's shapes, the stated digitising errors) in three windows (2 mm, 3 mm, all
points), as read and with further noise added (every point, or every fourth: fewer
points and more noise give objectives with several minima), and for each fit compares:

- how many local minima the objective has on a grid of 1,000 values of L;
- the sum of squares the fit reaches with grids of 12 to 200 values, against the least
  on a dense grid of 4,000 values: a fit "misses" when it ends more than 1e-6 (relative)
  above it, in a shallower basin;
- how many evaluations Brent's method takes after the default grid.

Nothing here is tuned: the seeds are fixed, every fit is counted.

Run: ``python docs/calibration/scripts/search_grid.py [n_seeds]`` (default 6; writes
``docs/calibration/search_grid.md``).
"""

from __future__ import annotations

import sys
from collections import Counter
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from lineload.fitting import optimize, search
from lineload.fitting.batch import fit_windowed
from lineload.simulation.coverage import simulate_dataset

OUT = Path(__file__).resolve().parents[1] / "search_grid.md"
SHAPES = ("waterbed", "arc", "boussinesq")
WINDOWS_MM = (2.0, 3.0, np.inf)
ADDED_NOISE_MM = (0.0, 0.02, 0.1, 0.3)
GRIDS = (12, 25, 50, 100, 200)
DENSE = 4000
MODALITY_GRID = 1000
MISS = 1e-6


class _Recorder:
    """Stands in for the minimiser inside the fits: runs it, and beside it the grids
    of other sizes and the dense grid on the same objective."""

    def __init__(self):
        self.fits = 0
        self.multimodal = 0
        self.missed = Counter()
        self.evaluations = Counter()

    def __call__(self, objective, low, high, lower_bound=None, **kwargs):
        counts = np.zeros(low.size, dtype=int)
        brent = optimize._brent

        def counted_brent(objective_, rows_, *args, **kwargs_):
            def counted(values, which):
                np.add.at(counts, which, 1)
                return objective_(values, which)

            return brent(counted, rows_, *args, **kwargs_)

        optimize._brent = counted_brent  # Brent's steps alone (not the grid's points)
        try:
            found_mm, found = optimize.minimize_bounded(
                objective, low, high, lower_bound=lower_bound, **kwargs
            )
        finally:
            optimize._brent = brent
        rows = np.flatnonzero(found)
        self.evaluations.update(counts[rows].tolist())
        self.fits += rows.size
        dense = np.geomspace(low[rows], high[rows], DENSE, axis=-1)
        values = np.concatenate(
            [objective(dense[i : i + 20], rows[i : i + 20]) for i in range(0, rows.size, 20)]
        )
        least = np.min(np.where(np.isfinite(values), values, np.inf), axis=1)
        coarse = values[:, :: DENSE // MODALITY_GRID]
        coarse = np.where(np.isfinite(coarse), coarse, np.inf)
        inner = (coarse[:, 1:-1] < coarse[:, :-2]) & (coarse[:, 1:-1] <= coarse[:, 2:])
        minima = inner.sum(axis=1) + (coarse[:, 0] < coarse[:, 1]) + (coarse[:, -1] < coarse[:, -2])
        self.multimodal += int(np.sum(minima > 1))
        for n_grid in GRIDS:
            other, _ = optimize.minimize_bounded(
                objective, low, high, n_grid=n_grid, lower_bound=lower_bound, **kwargs
            )
            reached = objective(other[rows, None], rows)[:, 0]
            self.missed[n_grid] += int(np.sum(reached > least * (1.0 + MISS) + 1e-15))
        return found_mm, found


@contextmanager
def _recording():
    """A fresh :class:`_Recorder` standing in for the fits' minimiser while in use."""
    original = search.minimize_bounded
    search.minimize_bounded = recorder = _Recorder()
    try:
        yield recorder
    finally:
        search.minimize_bounded = original


def _table(first_column, rows, first_align="--:"):
    """Markdown lines of a table: one row per ``(label, recorder)``."""
    lines = [
        f"| {first_column} | fits | objectives with two or more minima | "
        + " | ".join(f"missed, grid of {n}" for n in GRIDS)
        + " |",
        f"|{first_align}|--:|--:|" + "--:|" * len(GRIDS),
    ]
    for label, recorder in rows:
        share = 100.0 * recorder.multimodal / max(recorder.fits, 1)
        lines.append(
            f"| {label} | {recorder.fits:,} | {recorder.multimodal:,} ({share:.1f} %) | "
            + " | ".join(str(recorder.missed[n]) for n in GRIDS)
            + " |"
        )
    return lines


def study(n_seeds):
    """Rows of the table: one per added noise, every shape, window and thinning."""
    rows = []
    evaluations = Counter()
    for added_mm in ADDED_NOISE_MM:
        with _recording() as recorder:
            rng = np.random.default_rng(2026)
            for shape in SHAPES:
                for seed in range(n_seeds):
                    trials = simulate_dataset(shape, seed)
                    x = [t["distance_mm"] for t in trials]
                    y = [
                        t["mean_mm"] + rng.normal(0.0, added_mm, t["mean_mm"].size) for t in trials
                    ]
                    depth = [t["depth_mm"] for t in trials]
                    for every in (1, 4):
                        xs, ys = [v[::every] for v in x], [v[::every] for v in y]
                        for window_mm in WINDOWS_MM:
                            fit_windowed(
                                xs, ys, depth, window_mm, ("shifted", "arc"), intervals=False
                            )
        rows.append((f"{added_mm:g}", recorder))
        evaluations.update(recorder.evaluations)
    return rows, evaluations


#: Short, very noisy profiles (ten points, ~1 mm deflections, noise of 0.1-0.3 mm):
#: the hardest objectives seen, a dip just above the smallest admissible L among them.
SPARSE_DESIGNS = {
    "10 points to 1 mm": np.arange(0.1, 1.01, 0.1),
    "10 points to 2 mm": np.arange(0.2, 2.01, 0.2),
}
SPARSE_TRIALS = 300


def sparse_study(n_seeds):
    """Rows for arc-made short profiles (depth 0.5-1.5 mm, L 3-6 mm), noise added."""
    from lineload.models import arc_deflection_mm

    rows = []
    for name, x_mm in SPARSE_DESIGNS.items():
        for noise_mm in (0.1, 0.3):
            with _recording() as recorder:
                for seed in range(n_seeds):
                    rng = np.random.default_rng([seed, int(1000 * noise_mm)])
                    depth = rng.uniform(0.5, 1.5, SPARSE_TRIALS)
                    L_mm = rng.uniform(3.0, 6.0, SPARSE_TRIALS)
                    y = [
                        arc_deflection_mm(x_mm, d, L) + rng.normal(0.0, noise_mm, x_mm.size)
                        for d, L in zip(depth, L_mm, strict=True)
                    ]
                    fit_windowed(
                        [x_mm] * SPARSE_TRIALS, y, depth, np.inf, ("shifted", "arc"),
                        intervals=False,
                    )  # fmt: skip
            rows.append((f"{name}, {noise_mm:g} mm", recorder))
    return rows


def markdown(rows, evaluations, n_seeds, sparse=()):
    lines = [
        "# How dense the search grid over L must be",
        "",
        "Made by `python docs/calibration/scripts/search_grid.py "
        f"{n_seeds}` (the script's docstring says how). Profiles of the shipped design made "
        f"by {', '.join(SHAPES)} ({n_seeds} datasets of each), fitted by the shifted "
        "parabola and the exact arc in windows of 2 mm, 3 mm and all points, each as read "
        "and with every fourth point only. A fit misses when it ends more than "
        f"{MISS:g} (relative) above the least sum of squares on a grid of {DENSE:,} values.",
        "",
        *_table("noise added (mm)", rows),
    ]
    if sparse:
        lines += [
            "",
            f"Short, very noisy profiles: {SPARSE_TRIALS} arc-made trials per dataset (depth "
            f"0.5-1.5 mm, L 3-6 mm), {n_seeds} datasets per row, all points fitted.",
            "",
            *_table("design, noise", sparse, first_align="---"),
        ]
    counts = np.repeat(list(evaluations), list(evaluations.values()))
    lines += [
        "",
        f"Brent's method after the default grid of {optimize.minimize_bounded.__defaults__[0]}: "
        f"median {np.median(counts):.0f} evaluations per fit, 5th-95th percentile "
        f"{np.percentile(counts, 5):.0f}-{np.percentile(counts, 95):.0f}, at most "
        f"{counts.max()} (over the {counts.size:,} fits of the first table).",
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 6
    table_rows, counted = study(seeds)
    OUT.write_text(markdown(table_rows, counted, seeds, sparse_study(seeds)), encoding="utf-8")
    print(OUT.read_text(encoding="utf-8"))
