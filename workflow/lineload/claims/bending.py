"""The paper's closing suggestion (C13): the bending skin's advantage over the waterbed
grows with depth (:mod:`lineload.bending`)."""

from __future__ import annotations

import math

import numpy as np

from lineload.claims.rows import _n, _p_text, _row, _too_few_subjects
from lineload.claims.statistics import _slopes_across_subjects
from lineload.claims.trials import _averaged_covariance_mm2, _trials, _window_points
from lineload.claims.verdicts import FAILS, HOLDS, UNTESTABLE
from lineload.publishing.tables import counted, format_fixed

__all__ = [
    "claim_c13",
]


def claim_c13(fits, averaged, settings):
    """C13: the bending skin's advantage over the waterbed, relative to the deformation,
    grows with depth (the paper's closing suggestion, :mod:`lineload.bending`).

    The statistic of a trial is ``b = (RMSE_w**2 - RMSE_b**2 - s**2 / (2 n)) / W0**2``:
    how much less mean square misfit the bending skin leaves than the waterbed (the
    waterbed being the bending skin's limit ``l_b -> 0``, the difference is never
    negative beyond rounding), over W0**2 as C8 measures the waterbed's misfit.  Fitting
    pure noise, the extra parameter takes ``s**2 / 2`` of the sum of squares on average
    (half the time the fit stays at the membrane, the range's end, and takes nothing;
    Self and Liang 1987), ``s**2`` the mean noise variance of the points: that is
    subtracted, so noise alone gives no trend on average.  A trial whose bending length
    stays at the membrane has ``b = -s**2 / (2 n W0**2)`` exactly, a value that rises with
    depth alike in every subject: the slopes' standard error is therefore at least what
    the noise gives them (``n b W0**2 / s**2`` varies as ``1/2 chi2_0 + 1/2 chi2_1``,
    variance 1.25), not only their spread between subjects.  The slopes of ``b`` against
    depth are tested across subjects as C8's
    (:func:`lineload.claims.statistics._slopes_across_subjects`).
    """
    alpha = settings.significance
    min_df = settings.slope_min_df
    rule = (
        "Per trial: the bending skin's advantage b = (RMSE²(waterbed) − RMSE²(bending) − "
        "s²/(2n)) / W₀² over the same fit window, s² the mean noise variance of the averaged "
        "points under the trial's covariance (s²/2 is what the extra parameter takes from "
        "noise alone, on average). Per subject with two or more depths: the least-squares "
        "slope of b against depth; across subjects: the slopes regressed on species, the "
        "mean of the species' mean slopes tested one-sided with Student's t (significance "
        f"= {alpha:g}), as in C8, its standard error at least what the noise alone gives "
        "the slopes (noise alone makes n(RMSE²(waterbed) − RMSE²(bending)) vary as 1.25 s⁴). "
        "Holds if the slope is significantly above zero (bending "
        "accounts for more of the misfit the deeper the wedge); does not hold if its upper "
        f"one-sided {format_fixed(100 * (1 - alpha), 0)} % bound is below zero; cannot be "
        "checked otherwise, without bending fits, or with fewer subjects measured at two "
        f"depths than species + {min_df} (config claims: slope_min_df)."
    )
    if "bending_rmse_mm" not in fits:
        return _row(
            "C13",
            "no bending fits",
            UNTESTABLE,
            "The bending skin was not fitted to these data.",
            rule,
        )
    relative, species_of, variances = {}, {}, {}
    for fit, points in _trials(fits, averaged):
        waterbed, bending = float(fit["waterbed_rmse_mm"]), float(fit["bending_rmse_mm"])
        depth_mm = float(fit["depth_mm"])
        if points.empty or not (math.isfinite(waterbed) and math.isfinite(bending)):
            continue
        if not depth_mm > 0:
            continue
        x, w, sides = _window_points(fit, points)
        if x.size < 2:
            continue
        noise = float(np.mean(np.diag(_averaged_covariance_mm2(x, sides, w, fit, settings))))
        value = (waterbed**2 - bending**2 - noise / (2 * x.size)) / depth_mm**2
        subject = str(fit["subject"])
        species_of[subject] = str(fit["species"])
        relative.setdefault(subject, []).append((depth_mm, value))
        # noise alone: n (RMSE_w² - RMSE_b²) ~ s² (½χ²₀ + ½χ²₁), variance 1.25 s⁴
        variances.setdefault(subject, []).append(1.25 * (noise / (x.size * depth_mm**2)) ** 2)
    test = _slopes_across_subjects(relative, species_of, alpha, variances)
    slopes, species, df = test["slopes"], test["species"], test["df"]
    if df < min_df:
        return _too_few_subjects("C13", slopes, species, rule, min_df)
    estimate, se, p_value, upper = test["estimate"], test["se"], test["p"], test["upper"]
    per_subject = ", ".join(f"{s} {format_fixed(100 * v, 3)}" for s, v in slopes.items())
    our = (
        f"bending skin's advantage over the waterbed, slope against depth per subject "
        f"(% of W₀² per mm): {per_subject}; mean slope {format_fixed(100 * estimate, 3)} ± "
        f"{format_fixed(100 * se, 3)} (t = {format_fixed(test['t'], 2)}, "
        f"{counted(df, 'degree of freedom', 'degrees of freedom')}, one-sided p "
        f"{_p_text(p_value)})"
    )
    if p_value < alpha:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the bending skin's advantage over the "
            "membrane, relative to the depth, grows with depth (one-sided p "
            f"{_p_text(p_value)})."
        )
        return _row("C13", our, HOLDS, reason, rule)
    if upper < 0:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the bending skin's advantage, relative to "
            f"the depth, shrinks with depth (upper bound {format_fixed(100 * upper, 3)} % of "
            "W₀² per mm): bending does not account for the worsening."
        )
        return _row("C13", our, FAILS, reason, rule)
    reason = (
        f"Across {_n(len(slopes), 'subject')} the mean slope of the bending skin's advantage "
        f"({format_fixed(100 * estimate, 3)} ± {format_fixed(100 * se, 3)} % of W₀² per mm) "
        "is neither shown to be above zero nor below it."
    )
    return _row("C13", our, UNTESTABLE, reason, rule)
