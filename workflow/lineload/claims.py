"""The paper's quantitative claims, recomputed from the fits and the averaged profiles.

Each claim C1-C10 of the paper (text in :data:`CLAIM_TEXT`) has one function that computes numbers
from the fit table and the left/right mean profiles, then applies a rule
stated in words (with its thresholds) to reach a verdict: ``holds``,
``does not hold`` or ``cannot be checked on these data``.  No verdict is
written in advance; a claim the data cannot test says why in ``our_value``.

Inputs
------
fits : pandas.DataFrame
    The fit table, one row per subject and depth (columns of
    :data:`lineload.fitting.FIT_COLUMNS`; ``fit_window_mm`` says which points
    were fitted).
averaged : pandas.DataFrame
    The averaged profiles of every subject, stacked (columns of
    :data:`lineload.averaging.AVERAGED_COLUMNS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import brentq, least_squares

from .fitting import in_fit_window
from .models import waterbed_deflection_mm, waterbed_shift_mm
from .tables import SPECIES_ORDER, format_fixed, markdown_table

__all__ = [
    "CLAIM_COLUMNS",
    "CLAIM_FUNCTIONS",
    "CLAIM_IDS",
    "VERDICTS",
    "ClaimSettings",
    "circle_fit",
    "claims_markdown",
    "compute_claims",
    "deformed_extent_mm",
    "waterbed_zero_crossing_mm",
]

HOLDS = "holds"
FAILS = "does not hold"
UNTESTABLE = "cannot be checked on these data"
#: The only verdicts a claim can get.
VERDICTS = (HOLDS, FAILS, UNTESTABLE)

#: Columns of the claims table, in order.
CLAIM_COLUMNS = [
    "claim",
    "statement",
    "paper_location",
    "paper_value",
    "our_value",
    "verdict",
    "rule",
]

#: Numbers the paper states; they are part of the claims, not tuning thresholds.
PAPER_L_RANGE_MM = (10.0, 15.0)
PAPER_MAX_SHIFT_FRACTION = 0.08

#: The claim in our words, where the paper makes it, and what the paper gives.
CLAIM_TEXT = {
    "C1": (
        "At the same indentation depth the skin is deformed over a wider region in humans "
        "than in monkeys.",
        "Results, first paragraph; Fig. 7 caption",
        "humans 6-12 mm vs monkeys 3-7 mm from the wedge",
    ),
    "C2": (
        "The deflection profile is close to symmetric about the wedge (left side vs right side).",
        "Results, first paragraph (last sentence); Fig. 1 caption",
        "generally symmetrical (no number given)",
    ),
    "C3": (
        "Close to the load (within about 3 mm) the waterbed profile fits the data better than "
        "the modified Boussinesq profile.",
        "Abstract; Fig. 2 caption; Results, 'Comparison of theoretical and experimental "
        "results', end of paragraph; Discussion, second paragraph",
        "waterbed much better than Boussinesq up to about 3 mm (no number given)",
    ),
    "C4": (
        "Beyond about 3 mm from the load the waterbed is wrong: it predicts an upward bulge "
        "(W < 0) between L/3 and L which the measured skin does not show.",
        "Discussion, second paragraph",
        "bulge W < 0 on L/3 < X < L predicted, not observed",
    ),
    "C5": (
        "The fitted membrane half-width L lies between 10 and 15 mm.",
        "Results, 'Comparison of theoretical and experimental results' (Figs 6 and 7)",
        "10-15 mm",
    ),
    "C6": (
        "The horizontal shift U of the membrane is negligible: at X = L/3, where it is "
        "largest (8 W0^2 / (9 L)), it is a small fraction of X.",
        "Results, 'Comparison of theoretical and experimental results'",
        "< 8 % of X",
    ),
    "C7": (
        "Each fitted waterbed curve crosses the zero line at X = L/3, where U is largest.",
        "Results, 'Comparison of theoretical and experimental results' (from eqs 19-20)",
        "X = L/3",
    ),
    "C8": (
        "The waterbed describes the data less well the deeper the indentation.",
        "Discussion, third (last) paragraph",
        "accuracy falls as depth increases (no number given)",
    ),
    "C9": (
        "At the larger depths the measured deflection within about 3 mm of the load is "
        "smaller than the waterbed predicts, i.e. the fingertip is stiffer than the model.",
        "Discussion, third (last) paragraph (last sentence); Figs 6 and 7",
        "data within 3 mm below the model curve at the higher depths, in all cases shown",
    ),
    "C10": (
        "Skin that does not touch the indenter takes a circular (constant-curvature) shape.",
        "Discussion, third (last) paragraph (eqs 4-5); Fig. 1 caption",
        "approximately circular on either side of the load (no number given)",
    ),
}

#: Claim ids in table order.
CLAIM_IDS = list(CLAIM_TEXT)


@dataclass(frozen=True)
class ClaimSettings:
    """Thresholds of the verdict rules (the first three: config key ``claims``).

    Attributes
    ----------
    noise_mm : float
        Digitising noise of one reading (tissue mm); ``2 noise_mm`` is the
        smallest deflection taken as real.
    large_depth_mm : float
        Depths at or above this are the 'larger depths' of C9.
    symmetry_tolerance : float
        C2: largest RMS left-right difference, as a fraction of the depth.
    zero_crossing_rtol : float
        C7: largest relative distance between the numerical zero and L/3.  A
        bound on floating-point error, not on the data, so not a config key.
    """

    noise_mm: float = 0.01
    large_depth_mm: float = 1.5
    symmetry_tolerance: float = 0.05
    zero_crossing_rtol: float = 1e-6


# --------------------------------------------------------------------------- helpers


def _mm(value, decimals=2):
    return f"{format_fixed(value, decimals)} mm"


def _span(values, decimals=2, unit=" mm"):
    """'a to b mm' for the finite values (a single value if they are equal)."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return "none"
    low, high = format_fixed(values.min(), decimals), format_fixed(values.max(), decimals)
    return f"{low}{unit}" if low == high else f"{low} to {high}{unit}"


def _pct(fraction, decimals=1):
    return f"{format_fixed(100.0 * fraction, decimals)} %"


def _row(claim, our_value, verdict, rule):
    statement, location, paper_value = CLAIM_TEXT[claim]
    if verdict not in VERDICTS:
        raise ValueError(f"{claim}: unknown verdict {verdict!r}")
    return {
        "claim": claim,
        "statement": statement,
        "paper_location": location,
        "paper_value": paper_value,
        "our_value": our_value,
        "verdict": verdict,
        "rule": rule,
    }


def _trial_key(subject, depth_mm):
    return (str(subject), round(float(depth_mm), 9))


def _profiles_by_trial(averaged):
    """Averaged points of each (subject, depth), sorted by distance."""
    out = {}
    for (subject, depth_mm), group in averaged.groupby(["subject", "depth_mm"], sort=False):
        out[_trial_key(subject, depth_mm)] = group.sort_values("distance_mm", kind="stable")
    return out


def _trials(fits, averaged):
    """Pairs (fit row, averaged points) for every row of the fit table, in its order.

    A trial without averaged points gets an empty frame.
    """
    profiles = _profiles_by_trial(averaged)
    empty = averaged.iloc[0:0]
    for _, fit in fits.iterrows():
        yield fit, profiles.get(_trial_key(fit["subject"], fit["depth_mm"]), empty)


def _label(fit):
    return f"{fit['subject']} at {float(fit['depth_mm']):g} mm"


def _finite_L(fit):
    L_mm = float(fit["waterbed_L_mm"])
    return math.isfinite(L_mm) and L_mm > 0


# --------------------------------------------------------------------------- numerics


def deformed_extent_mm(distance_mm, deflection_mm, threshold_mm):
    """Distance from the load at which the deflection last falls through a threshold.

    After the farthest point whose deflection exceeds the threshold, the
    profile is interpolated linearly to the next point to find where it
    crosses the threshold.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        One averaged profile (mm), any order.
    threshold_mm : float
        Deflection taken as a real displacement (mm).

    Returns
    -------
    float
        The distance (mm); 0 when no point exceeds the threshold.  When the
        farthest reading still exceeds it, that reading's distance is returned
        (a lower bound: the readings stop while the skin is still displaced).
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    keep = np.isfinite(distance_mm) & np.isfinite(deflection_mm)
    order = np.argsort(distance_mm[keep], kind="stable")
    x, w = distance_mm[keep][order], deflection_mm[keep][order]
    above = np.flatnonzero(w > threshold_mm)
    if above.size == 0:
        return 0.0
    last = int(above[-1])
    if last == x.size - 1:
        return float(x[last])
    step = (w[last] - threshold_mm) / (w[last] - w[last + 1])
    return float(x[last] + step * (x[last + 1] - x[last]))


def waterbed_zero_crossing_mm(depth_mm, L_mm):
    """Zero of the fitted small-slope waterbed curve inside the membrane, found numerically.

    Brent's method on ``lineload.models.waterbed_deflection_mm`` over
    ``[0, 2 L / 3]``: the curve equals ``W0 > 0`` at the load and ``-W0 / 3`` at
    ``2 L / 3`` (the bottom of the bulge), so the bracket holds exactly one
    sign change.  Analytically the zero is ``L / 3``; this function does not
    use that.

    Parameters
    ----------
    depth_mm : float
        W0 (mm, > 0).
    L_mm : float
        Fitted half-width (mm, finite, > 0).

    Returns
    -------
    float
        The zero crossing (mm).
    """

    def deflection(distance_mm):
        return float(waterbed_deflection_mm(distance_mm, depth_mm, L_mm))

    return float(brentq(deflection, 0.0, 2.0 * L_mm / 3.0, xtol=1e-14 * L_mm, rtol=1e-15))


def circle_fit(x_mm, z_mm):
    """Best-fitting free circle through a set of points (orthogonal least squares).

    An algebraic (Kåsa) fit on centred coordinates gives the start; the
    geometric distances of the points from the circle are then minimised with
    ``scipy.optimize.least_squares`` (Levenberg-Marquardt) over centre and radius.

    Parameters
    ----------
    x_mm, z_mm : array_like
        Point coordinates (mm), at least three points not on one line.

    Returns
    -------
    dict
        ``centre_x_mm``, ``centre_z_mm``, ``radius_mm`` and ``rms_distance_mm``
        (root-mean-square perpendicular distance of the points from the circle).
    """
    x_mm = np.asarray(x_mm, dtype=float)
    z_mm = np.asarray(z_mm, dtype=float)
    if x_mm.size < 3:
        raise ValueError(f"a circle needs at least 3 points, got {x_mm.size}")
    x0, z0 = x_mm.mean(), z_mm.mean()
    u, v = x_mm - x0, z_mm - z0
    design = np.column_stack([u, v, np.ones_like(u)])
    (d, e, f), *_ = np.linalg.lstsq(design, -(u**2 + v**2), rcond=None)
    centre = np.array([-d / 2.0, -e / 2.0])
    radius = math.sqrt(max(centre @ centre - f, 0.0))
    if not (np.all(np.isfinite(centre)) and math.isfinite(radius) and radius > 0):
        raise ValueError("the points do not define a circle")

    def distances(p):
        return np.hypot(u - p[0], v - p[1]) - p[2]

    fit = least_squares(distances, [centre[0], centre[1], radius], method="lm", x_scale="jac")
    a, b, r = fit.x
    residual = distances(fit.x)
    return {
        "centre_x_mm": float(a + x0),
        "centre_z_mm": float(b + z0),
        "radius_mm": float(abs(r)),
        "rms_distance_mm": float(np.sqrt(np.mean(residual**2))),
    }


# --------------------------------------------------------------------------- claims


def claim_c1(fits, averaged, settings):
    """C1: wider deformed region in humans than in monkeys at the same depth."""
    threshold_mm = 2.0 * settings.noise_mm
    extents = {}
    for fit, points in _trials(fits, averaged):
        if points.empty:
            continue
        extent = deformed_extent_mm(points["distance_mm"], points["deflection_mm"], threshold_mm)
        key = round(float(fit["depth_mm"]), 9)
        extents.setdefault(key, {}).setdefault(str(fit["species"]), []).append(extent)
    rule = (
        "Extent of a trial = distance at which the averaged deflection last falls through "
        f"2 x noise_mm = {format_fixed(threshold_mm, 3)} mm (linear interpolation between "
        "readings). Holds if, at every depth measured "
        "in both species, the smallest human extent is larger than the largest monkey extent."
    )
    by_species = {
        sp: [e for depth in extents.values() for e in depth.get(sp, [])] for sp in SPECIES_ORDER
    }
    ranges = (
        f"monkeys {_span(by_species['monkey'])} ({len(by_species['monkey'])} trials), "
        f"humans {_span(by_species['human'])} ({len(by_species['human'])} trials)"
    )
    shared = sorted(d for d, sp in extents.items() if "monkey" in sp and "human" in sp)
    if not shared:
        missing = [sp for sp in SPECIES_ORDER if not by_species[sp]]
        reason = (
            f"no {' and no '.join(missing)} trials"
            if missing
            else "no depth measured in both species"
        )
        return _row("C1", f"{ranges}; {reason}", UNTESTABLE, rule)
    wider = [d for d in shared if min(extents[d]["human"]) > max(extents[d]["monkey"])]
    verdict = HOLDS if len(wider) == len(shared) else FAILS
    per_depth = "; ".join(
        f"{d:g} mm: monkeys {_span(extents[d]['monkey'])}, humans {_span(extents[d]['human'])}"
        for d in shared
    )
    our = f"{ranges}; humans wider at {len(wider)} of {len(shared)} shared depths"
    narrow = [f"{d:g}" for d in shared if d not in wider]
    if narrow:
        our += f" (not at {', '.join(narrow)} mm)"
    our += f" ({per_depth})"
    return _row("C1", our, verdict, rule)


def claim_c2(fits, averaged, settings):
    """C2: left and right profiles nearly the same."""
    tolerance = settings.symmetry_tolerance
    rule = (
        "Per trial: RMS of (left - right) over the distances read on both sides "
        "(left_source and right_source both 'measured'), divided by the depth. Holds if the "
        f"largest value over all trials is at most symmetry_tolerance = {tolerance:g}."
    )
    values = []
    for fit, points in _trials(fits, averaged):
        if points.empty:
            continue
        both = (points["left_source"] == "measured") & (points["right_source"] == "measured")
        difference = (points.loc[both, "left_mm"] - points.loc[both, "right_mm"]).to_numpy(float)
        if difference.size:
            rms = float(np.sqrt(np.mean(difference**2)))
            values.append((rms / float(fit["depth_mm"]), _label(fit)))
    if not values:
        return _row("C2", "no distance read on both sides in any trial", UNTESTABLE, rule)
    fractions = np.array([v for v, _ in values])
    worst = values[int(np.argmax(fractions))][1]
    our = (
        f"RMS left-right difference / depth: median {_pct(np.median(fractions))}, "
        f"largest {_pct(fractions.max())} ({worst}); {len(values)} trials"
    )
    verdict = HOLDS if fractions.max() <= tolerance else FAILS
    return _row("C2", our, verdict, rule)


def claim_c3(fits, averaged, settings):
    """C3: waterbed better than Boussinesq within the fit window."""
    w_rmse = fits["waterbed_rmse_mm"].to_numpy(float)
    b_rmse = fits["boussinesq_rmse_mm"].to_numpy(float)
    w_aicc = fits["waterbed_aicc"].to_numpy(float)
    b_aicc = fits["boussinesq_aicc"].to_numpy(float)
    rule = (
        "Same points for both models (the fit window). Holds if in every trial with both fits "
        "the waterbed has the lower RMSE and the lower AICc than the Boussinesq form."
    )
    usable = np.isfinite(w_rmse) & np.isfinite(b_rmse) & np.isfinite(w_aicc) & np.isfinite(b_aicc)
    if not usable.any():
        return _row("C3", "no trial has both fits", UNTESTABLE, rule)
    better = (w_rmse < b_rmse) & (w_aicc < b_aicc)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = b_rmse[usable] / w_rmse[usable]
    windows = pd.unique(fits["fit_window_mm"].dropna())
    window = f" within {float(windows[0]):g} mm" if len(windows) == 1 else ""
    our = (
        f"waterbed better{window} in {int(better[usable].sum())} of {int(usable.sum())} trials; "
        f"RMSE ratio Boussinesq/waterbed median {format_fixed(np.median(ratio), 2)} "
        f"(range {_span(ratio, 2, '')})"
    )
    verdict = HOLDS if better[usable].all() else FAILS
    return _row("C3", our, verdict, rule)


def claim_c4(fits, averaged, settings):
    """C4: the predicted bulge beyond L/3 is not in the data."""
    threshold_mm = 2.0 * settings.noise_mm
    rule = (
        "Per trial: the averaged points with L/3 < distance < L at which the fitted waterbed "
        f"curve is below -2 x noise_mm = -{format_fixed(threshold_mm, 3)} mm (a bulge the "
        "readings could resolve). The data show the bulge if their mean over those points is "
        f"below -{format_fixed(threshold_mm, 3)} mm. Holds if no such trial shows it; cannot "
        "be checked if no trial has such points."
    )
    model_means, data_means, lowest, showing = [], [], [], []
    n_trials = 0
    for fit, points in _trials(fits, averaged):
        if points.empty or not _finite_L(fit):
            continue
        n_trials += 1
        L_mm, depth_mm = float(fit["waterbed_L_mm"]), float(fit["depth_mm"])
        x = points["distance_mm"].to_numpy(float)
        w = points["deflection_mm"].to_numpy(float)
        model = waterbed_deflection_mm(x, depth_mm, L_mm)
        bulge = (x > L_mm / 3.0) & (x < L_mm) & np.isfinite(w) & (model < -threshold_mm)
        if not bulge.any():
            continue
        model_means.append(float(model[bulge].mean()))
        data_means.append(float(w[bulge].mean()))
        lowest.append(float(w[bulge].min()))
        if data_means[-1] < -threshold_mm:
            showing.append(_label(fit))
    if not model_means:
        return _row(
            "C4",
            f"none of {n_trials} trials has readings where the fitted curve dips below "
            f"-{format_fixed(threshold_mm, 3)} mm",
            UNTESTABLE,
            rule,
        )
    our = (
        f"{len(model_means)} of {n_trials} trials have readings in the predicted bulge; mean "
        f"of the fitted curve there {_span(model_means, 3)}, mean of the data "
        f"{_span(data_means, 3)} (lowest single point {_mm(min(lowest), 3)}); "
        f"bulge seen in {len(showing)}"
    )
    if showing:
        our += f" ({', '.join(showing)})"
    return _row("C4", our, FAILS if showing else HOLDS, rule)


def claim_c5(fits, averaged, settings):
    """C5: fitted L between 10 and 15 mm."""
    low, high = PAPER_L_RANGE_MM
    L_mm = fits["waterbed_L_mm"].to_numpy(float)
    L_mm = L_mm[~np.isnan(L_mm)]
    rule = f"Holds if every fitted waterbed L is within [{low:g}, {high:g}] mm (the paper's range)."
    if L_mm.size == 0:
        return _row("C5", "no waterbed fit", UNTESTABLE, rule)
    inside = (L_mm >= low) & (L_mm <= high)
    our = f"L = {_span(L_mm)}; {int(inside.sum())} of {L_mm.size} trials inside"
    return _row("C5", our, HOLDS if inside.all() else FAILS, rule)


def claim_c6(fits, averaged, settings):
    """C6: the horizontal shift at L/3 is under 8 % of X."""
    limit = PAPER_MAX_SHIFT_FRACTION
    rule = (
        "Per trial with a finite fitted L: |U(L/3)| / (L/3), with U from eq. 20 "
        "(lineload.models.waterbed_shift_mm) at W0 = depth. Holds if the largest value is "
        f"below {_pct(limit, 0)} (the paper's bound)."
    )
    fractions, labels = [], []
    for _, fit in fits.iterrows():
        if not _finite_L(fit):
            continue
        L_mm, depth_mm = float(fit["waterbed_L_mm"]), float(fit["depth_mm"])
        shift_mm = float(waterbed_shift_mm(L_mm / 3.0, depth_mm, L_mm))
        fractions.append(abs(shift_mm) / (L_mm / 3.0))
        labels.append(_label(fit))
    if not fractions:
        return _row("C6", "no trial with a finite fitted L", UNTESTABLE, rule)
    fractions = np.array(fractions)
    worst = int(np.argmax(fractions))
    our = (
        f"|U(L/3)| / (L/3) = {_pct(fractions.min())} to {_pct(fractions.max())} "
        f"(largest: {labels[worst]})"
    )
    return _row("C6", our, HOLDS if fractions.max() < limit else FAILS, rule)


def claim_c7(fits, averaged, settings):
    """C7: the fitted curve crosses zero at L/3 (found numerically)."""
    rtol = settings.zero_crossing_rtol
    rule = (
        "Per trial with a finite fitted L: the zero of the fitted waterbed curve found by "
        "Brent's method on [0, 2L/3] (not from the formula). Holds if it equals L/3 within a "
        f"relative {rtol:.0e} (floating-point accuracy) in every trial."
    )
    deviations = []
    for _, fit in fits.iterrows():
        if not _finite_L(fit) or not float(fit["depth_mm"]) > 0:
            continue
        L_mm = float(fit["waterbed_L_mm"])
        root_mm = waterbed_zero_crossing_mm(float(fit["depth_mm"]), L_mm)
        deviations.append(abs(root_mm / (L_mm / 3.0) - 1.0))
    if not deviations:
        return _row("C7", "no trial with a finite fitted L", UNTESTABLE, rule)
    deviations = np.array(deviations)
    our = (
        f"numerical zero / (L/3) - 1: largest |deviation| {deviations.max():.1e} over "
        f"{deviations.size} trials"
    )
    return _row("C7", our, HOLDS if deviations.max() <= rtol else FAILS, rule)


def claim_c8(fits, averaged, settings):
    """C8: the waterbed fits worse at larger depths."""
    rule = (
        "Holds if, in every subject with at least two depths, the waterbed RMSE (mm, within "
        "the fit window) increases at every step to a larger depth. Shown beside it, not "
        "deciding: the same count for RMSE / depth, which at the smallest depths is "
        "dominated by the digitising noise."
    )
    rmse_mm = fits["waterbed_rmse_mm"].to_numpy(float)
    table = fits.assign(_rmse=rmse_mm, _relative=rmse_mm / fits["depth_mm"].to_numpy(float))
    table = table[np.isfinite(table["_rmse"])]
    subjects, increasing, increasing_relative = [], [], []
    for subject, group in table.groupby("subject", sort=False):
        group = group.sort_values("depth_mm", kind="stable")
        if group["depth_mm"].nunique() < 2:
            continue
        subjects.append(str(subject))
        increasing.append(bool(np.all(np.diff(group["_rmse"].to_numpy(float)) > 0)))
        increasing_relative.append(bool(np.all(np.diff(group["_relative"].to_numpy(float)) > 0)))
    if not subjects:
        return _row("C8", "no subject measured at two or more depths", UNTESTABLE, rule)
    means = ", ".join(
        f"{d:g} mm {_mm(m, 4)}"
        for d, m in table.groupby("depth_mm", sort=True)["_rmse"].mean().items()
    )
    failing = [s for s, ok in zip(subjects, increasing, strict=True) if not ok]
    our = f"RMSE increasing with depth in {sum(increasing)} of {len(subjects)} subjects"
    if failing:
        our += f" (not in {', '.join(failing)})"
    failing_relative = [s for s, ok in zip(subjects, increasing_relative, strict=True) if not ok]
    our += f"; mean RMSE per depth: {means}; RMSE/depth increasing in {sum(increasing_relative)}"
    if failing_relative:
        our += f" (not in {', '.join(failing_relative)})"
    return _row("C8", our, HOLDS if all(increasing) else FAILS, rule)


def claim_c9(fits, averaged, settings):
    """C9: at the larger depths the data lie below the waterbed curve near the load."""
    large = settings.large_depth_mm
    rule = (
        f"Per trial at depth >= large_depth_mm = {large:g} mm: the fraction of the fitted "
        "averaged points (the fit window) whose deflection is smaller than the fitted waterbed "
        "curve. Holds if it is above 50 % in every such trial."
    )
    fractions, labels = [], []
    for fit, points in _trials(fits, averaged):
        if float(fit["depth_mm"]) < large or points.empty or not _finite_L(fit):
            continue
        x = points["distance_mm"].to_numpy(float)
        w = points["deflection_mm"].to_numpy(float)
        keep = in_fit_window(x, float(fit["fit_window_mm"])) & np.isfinite(w)
        if not keep.any():
            continue
        model = waterbed_deflection_mm(x[keep], float(fit["depth_mm"]), float(fit["waterbed_L_mm"]))
        fractions.append(float(np.mean(w[keep] < model)))
        labels.append(_label(fit))
    if not fractions:
        return _row("C9", f"no trial at a depth of {large:g} mm or more", UNTESTABLE, rule)
    fractions = np.array(fractions)
    majority = fractions > 0.5
    our = (
        f"points below the curve: {_pct(fractions.min(), 0)} to {_pct(fractions.max(), 0)} "
        f"per trial; majority below in {int(majority.sum())} of {fractions.size} trials"
    )
    failing = [label for label, ok in zip(labels, majority, strict=True) if not ok]
    if failing:
        our += f" (not in {', '.join(failing)})"
    return _row("C9", our, HOLDS if majority.all() else FAILS, rule)


def claim_c10(fits, averaged, settings):
    """C10: the free skin near the load is a circular arc (curved, with constant curvature)."""
    threshold_mm = 2.0 * settings.noise_mm
    rule = (
        "Per trial: a circle with free centre and radius fitted to the averaged points of the "
        "fit window (orthogonal least squares, algebraic start); its misfit is the RMS "
        "perpendicular distance of the points. Unlike the exact-arc model it is not tied to "
        "the depth or to zero net area, so it tests the shape alone. A nearly straight "
        "profile fits a circle of huge radius as well as a line, so it says nothing about "
        "curvature: trials where a straight line also fits within the threshold are left "
        "out. Holds if, in every remaining trial (4 or more points), the circle's misfit is "
        f"at most 2 x noise_mm = {format_fixed(threshold_mm, 3)} mm; cannot be checked if "
        "no trial remains."
    )
    misfits, line_misfits, labels = [], [], []
    for fit, points in _trials(fits, averaged):
        if points.empty:
            continue
        x = points["distance_mm"].to_numpy(float)
        w = points["deflection_mm"].to_numpy(float)
        keep = in_fit_window(x, float(fit["fit_window_mm"])) & np.isfinite(w)
        if keep.sum() < 4:
            continue
        try:
            circle = circle_fit(x[keep], -w[keep])
        except ValueError:
            continue
        slope, intercept = np.polyfit(x[keep], w[keep], 1)
        line_residual = w[keep] - (slope * x[keep] + intercept)
        misfits.append(circle["rms_distance_mm"])
        line_misfits.append(float(np.sqrt(np.mean(line_residual**2))))
        labels.append(_label(fit))
    if not misfits:
        return _row("C10", "no trial with 4 or more points in the fit window", UNTESTABLE, rule)
    misfits, line_misfits = np.array(misfits), np.array(line_misfits)
    curved = line_misfits > threshold_mm
    straight = [label for label, c in zip(labels, curved, strict=True) if not c]
    left_out = f"; nearly straight, left out: {', '.join(straight)}" if straight else ""
    if not curved.any():
        our = (
            f"a straight line fits every trial within {format_fixed(threshold_mm, 3)} mm "
            f"(RMS {_span(line_misfits, 3)}): the curvature is not resolved"
        )
        return _row("C10", our, UNTESTABLE, rule)
    within = misfits[curved] <= threshold_mm
    our = (
        f"free-circle misfit {_span(misfits[curved], 4)} (median "
        f"{_mm(np.median(misfits[curved]), 4)}) in the {int(curved.sum())} trials where a "
        f"straight line misses by more than {format_fixed(threshold_mm, 3)} mm; within it in "
        f"{int(within.sum())} of {int(curved.sum())}{left_out}"
    )
    failing = [
        label for label, c, m in zip(labels, curved, misfits, strict=True) if c and m > threshold_mm
    ]
    if failing:
        our += f" (circle misses in {', '.join(failing)})"
    return _row("C10", our, HOLDS if within.all() else FAILS, rule)


CLAIM_FUNCTIONS = {
    "C1": claim_c1,
    "C2": claim_c2,
    "C3": claim_c3,
    "C4": claim_c4,
    "C5": claim_c5,
    "C6": claim_c6,
    "C7": claim_c7,
    "C8": claim_c8,
    "C9": claim_c9,
    "C10": claim_c10,
}


def compute_claims(fits, averaged, settings=None):
    """The claims table: one row per claim C1-C10, each verdict from its stated rule.

    Parameters
    ----------
    fits : pandas.DataFrame
        Fit table (one row per subject and depth).
    averaged : pandas.DataFrame
        Averaged profiles of the subjects in ``fits``, stacked.
    settings : ClaimSettings, optional
        Thresholds of the rules; defaults as in the config schema.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`CLAIM_COLUMNS`, rows C1 to C10 in order.
    """
    settings = settings or ClaimSettings()
    rows = [CLAIM_FUNCTIONS[claim](fits, averaged, settings) for claim in CLAIM_IDS]
    return pd.DataFrame(rows, columns=CLAIM_COLUMNS)


def claims_markdown(claims, notice=""):
    """The claims table as Markdown: a table of verdicts, then the rule of each claim.

    Parameters
    ----------
    claims : pandas.DataFrame
        Output of :func:`compute_claims`.
    notice : str, optional
        Data notice; when non-empty it is added as a footer line.

    Returns
    -------
    str
    """
    headers = ["Claim", "Statement", "Where in the paper", "Paper", "Ours", "Verdict"]
    rows = [
        [
            r["claim"],
            r["statement"],
            r["paper_location"],
            r["paper_value"],
            r["our_value"],
            f"**{r['verdict']}**",
        ]
        for _, r in claims.iterrows()
    ]
    text = (
        "# Claims of Srinivasan (1989), recomputed\n\n"
        "Each verdict comes from applying the rule below to numbers computed from the data "
        "this table was built from; it describes those data, not the paper's fingertips.\n\n"
    )
    text += markdown_table(headers, rows, "llllll")
    text += "\n## Rules\n\n"
    text += "".join(
        f"- **{r['claim']}**: {' '.join(r['rule'].split())}\n" for _, r in claims.iterrows()
    )
    if notice:
        text += f"\nNote: {' '.join(notice.split())}\n"
    return text
