"""The wedge's position: whether the readings can tell it, and what its prior does to A.

Two parts, both on Boussinesq profiles ``A ln(x0 / x)`` (A = 0.4 mm, x0 = 4 mm) read on the
paper's grid (:func:`lineload.rawdata.readings.reading_distances_mm`, 0.05-3 mm):

1. Identification.  The noise fit's fixed effects (offset, rotation, quadratic and the
   wedge's ``2 d w'(x)``) fitted by least squares to the noise-free left-minus-right
   difference of (a) a symmetric finger read with the wedge 10 um off, (b) fingers one of
   whose sides has an A larger by 5, 10 or 20 %, read with the wedge in place.  The fitted
   shift and the RMS misfit say whether the readings could tell (b) from a misplaced wedge.
2. Coverage of A's 95 % interval and the wedge's share of its variance
   (``boussinesq_A_wedge_share``) when each trial's two sides are read at ``x +- d``, ``d``
   normal with a true SD, and the prior states another SD (0 to 3x the true).  Reading
   noise 5 um per side, measured (stated as it is); no other prior, so the share is the
   wedge's alone.  Coverage with a Clopper-Pearson 95 % interval.

Run: ``python docs/calibration/scripts/wedge_study.py [n_trials]`` (writes
``docs/calibration/wedge.md``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.stats import binomtest

from lineload.fitting.batch import fit_trials
from lineload.noise import NoiseModel
from lineload.rawdata.readings import reading_distances_mm

A_MM, X0_MM = 0.4, 4.0
DISTANCE_MM = reading_distances_mm(3.0, first_mm=0.05)
READING_SD_MM = 0.005
#: The config's default wedge prior (mm).
DEFAULT_WEDGE_MM = 0.01
TRUE_SD_MM = (0.01, 0.02)
STATED_MULTIPLES = (0.0, 0.5, 1.0, 1.5, 2.0, 3.0)
ASYMMETRIES = (0.05, 0.10, 0.20)
SEED = 2031


def profile_mm(x):
    return A_MM * np.log(X0_MM / np.abs(x))


def fitted_shift(difference_mm):
    """Shift (mm) and RMS misfit (mm) of the noise fit's fixed effects on one difference."""
    x = DISTANCE_MM
    design = np.stack([np.ones_like(x), x, x**2, 2 * (-A_MM / x)], axis=1)
    coef, *_ = np.linalg.lstsq(design, difference_mm, rcond=None)
    return coef[3], float(np.sqrt(np.mean((difference_mm - design @ coef) ** 2)))


def identification_rows():
    x = DISTANCE_MM
    shift = DEFAULT_WEDGE_MM
    rows = [
        ("symmetric, wedge 10 um off", *fitted_shift(profile_mm(x + shift) - profile_mm(x - shift)))
    ]
    for asymmetry in ASYMMETRIES:
        rows.append(
            (
                f"one side's A {100 * asymmetry:.0f} % larger, wedge in place",
                *fitted_shift(asymmetry * profile_mm(x)),
            )
        )
    return rows


def coverage_row(true_sd_mm, stated_sd_mm, n_trials, seed):
    rng = np.random.default_rng(seed)
    x = DISTANCE_MM
    shifts = rng.normal(0.0, true_sd_mm, n_trials)
    readings = [
        (profile_mm(x + s) + profile_mm(x - s)) / 2
        + rng.normal(0.0, READING_SD_MM / np.sqrt(2), x.size)
        for s in shifts
    ]
    noise = NoiseModel(reading_sd_mm=READING_SD_MM, wedge_position_sd_mm=stated_sd_mm)
    rows = fit_trials(
        [x] * n_trials,
        readings,
        [1.0] * n_trials,
        3.0,
        noise=noise,
        n_sides=[np.full(x.size, 2)] * n_trials,
    )
    low = np.array([r["boussinesq_A_ci_low_mm"] for r in rows])
    high = np.array([r["boussinesq_A_ci_high_mm"] for r in rows])
    share = np.array([r["boussinesq_A_wedge_share"] for r in rows])
    covered = int(np.sum((low <= A_MM) & (A_MM <= high)))
    ci = binomtest(covered, n_trials).proportion_ci(0.95, method="exact")
    return covered, ci.low, ci.high, float(np.median(share))


def main(n_trials=1000):
    lines = [
        "# The wedge's position: not identifiable, a prior with its weight shown",
        "",
        "Made by `docs/calibration/scripts/wedge_study.py` (its docstring says how); "
        f"{n_trials} trials per row, seed {SEED}.",
        "",
        "## 1. Can the left-right difference tell a misplaced wedge from an asymmetric finger?",
        "",
        "| Finger | fitted shift (um) | RMS misfit of the fixed effects (um) |",
        "|---|---|---|",
    ]
    identification = identification_rows()
    for name, shift, misfit in identification:
        lines.append(f"| {name} | {1000 * shift:.1f} | {1000 * misfit:.2f} |")
    difference_sd_um = 1000 * np.sqrt(2) * READING_SD_MM
    asymmetric = identification[1:]
    below = [name for name, _, misfit in asymmetric if 1000 * misfit < difference_sd_um]
    lines += [
        "",
        f"A difference of two readings has noise {difference_sd_um:.1f} um (two sides of "
        f"{1000 * READING_SD_MM:g} um). {len(below)} of the {len(asymmetric)} asymmetric "
        "fingers are fitted by a wedge shift with an RMS misfit below that: on such a trial "
        "the readings cannot say whether the wedge was misplaced or the finger is "
        "asymmetric, so the shift is not estimated from it but stays a prior.",
        "",
        "## 2. Coverage of Boussinesq A's 95 % interval and the wedge's share of its variance",
        "",
        "| true wedge SD (um) | stated prior (um) | covered | 95 % interval | median wedge share |",
        "|---|---|---|---|---|",
    ]
    for i, true_sd in enumerate(TRUE_SD_MM):
        for j, multiple in enumerate(STATED_MULTIPLES):
            stated = multiple * true_sd
            covered, low, high, share = coverage_row(true_sd, stated, n_trials, SEED + 100 * i + j)
            lines.append(
                f"| {1000 * true_sd:g} | {1000 * stated:g} | {100 * covered / n_trials:.1f} % "
                f"({covered}/{n_trials}) | {100 * low:.1f}-{100 * high:.1f} % | {share:.3f} |"
            )
    lines += [
        "",
        "A prior of 0 gives a share of 0 whatever the wedge did: the share is the weight of "
        "what is stated, not a measurement of the wedge.",
        "",
    ]
    out = Path(__file__).resolve().parents[1] / "wedge.md"
    out.write_text("\n".join(lines), encoding="utf-8")
    print(out.read_text(encoding="utf-8"))


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1000)
