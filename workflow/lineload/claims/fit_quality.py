"""Claims on how well the waterbed describes the readings: better than the Boussinesq
form near the load (C3), no bulge beyond L/3 (C4), worse the deeper the wedge (C8), the
skin stiffer than the model at depth (C9)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from lineload.claims.rows import (
    COORDINATES_FIGURE,
    _every,
    _list,
    _mm,
    _n,
    _p_text,
    _row,
    _too_few_subjects,
)
from lineload.claims.statistics import _around_L, _L_sensitivity, _slopes_across_subjects
from lineload.claims.trials import (
    CONSISTENT_FITS,
    FIT_WORDS,
    PAPER_FIT,
    _averaged_covariance_mm2,
    _finite_L,
    _label,
    _trials,
    _window_points,
)
from lineload.claims.verdicts import FAILS, HOLDS, UNTESTABLE
from lineload.distributions import normal_quantile
from lineload.fitting.families import family
from lineload.fitting.windows import in_fit_window
from lineload.models import boussinesq_deflection_mm, waterbed_deflection_mm
from lineload.publishing.tables import counted, format_fixed
from lineload.publishing.tables import span_text as _span

__all__ = [
    "claim_c3",
    "claim_c4",
    "claim_c8",
    "claim_c9",
]


def claim_c3(fits, averaged, settings):
    """C3: waterbed better than Boussinesq within the fit window, a test per trial."""
    alpha = settings.significance
    rule = (
        "Same points for both models (the fit window). Per trial, D = SSE_Boussinesq - "
        "SSE_waterbed (the paper's procedure, one parameter, against the Boussinesq form, "
        "two): D = sum (f_w - f_B)(2 y - f_w - f_B) is linear in the readings, so its "
        "standard error is 2 sqrt(d' C d), d = f_w - f_B, with C the covariance of the "
        "averaged points from the measured noise (correlated errors included). The waterbed "
        f"is better in a trial if D exceeds zero by {format_fixed(normal_quantile(1 - alpha), 2)} "
        f"standard errors (one-sided, significance = {alpha:g}); the Boussinesq form is "
        "better if D is below zero by the one-sided Bonferroni quantile over the trials. "
        "Holds if the waterbed is better in every trial with both fits; does not hold if "
        "the Boussinesq form is better in some trial; cannot be checked otherwise. The "
        "comparison favours the Boussinesq form by its extra parameter. Shown beside it, "
        "not deciding: the RMSE ratio, and the count for the shifted parabola."
    )
    w_rmse = fits["waterbed_rmse_mm"].to_numpy(float)
    b_rmse = fits["boussinesq_rmse_mm"].to_numpy(float)
    tests = []
    for fit, points in _trials(fits, averaged):
        A_mm, x0_mm = float(fit["boussinesq_A_mm"]), float(fit["boussinesq_x0_mm"])
        if not (_finite_L(fit) and math.isfinite(A_mm) and math.isfinite(x0_mm)):
            continue
        if points.empty:
            continue
        x, y, sides = _window_points(fit, points)
        if x.size < 3:
            continue
        depth_mm = float(fit["depth_mm"])
        f_w = waterbed_deflection_mm(x, depth_mm, float(fit["waterbed_L_mm"]))
        f_b = boussinesq_deflection_mm(x, A_mm, x0_mm)
        gap = f_w - f_b
        covariance = _averaged_covariance_mm2(x, sides, y, fit, settings)
        sd = 2.0 * math.sqrt(max(float(gap @ covariance @ gap), 0.0))
        tests.append((_label(fit), float(gap @ (2 * y - f_w - f_b)), sd))
    if not tests:
        return _row(
            "C3",
            "no trial has both fits",
            UNTESTABLE,
            "No trial has enough points for both the waterbed and the Boussinesq fit.",
            rule,
        )
    labels = [t[0] for t in tests]
    D = np.array([t[1] for t in tests])
    sd = np.array([t[2] for t in tests])
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(sd > 0, D / sd, np.sign(D) * np.inf)
    waterbed = z > normal_quantile(1 - alpha)
    boussinesq = z < -normal_quantile(1 - alpha / len(tests))
    usable = np.isfinite(w_rmse) & np.isfinite(b_rmse)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = b_rmse[usable] / w_rmse[usable]
    shifted_better = fits["shifted_rmse_mm"].to_numpy(float) < b_rmse
    windows = pd.unique(fits["fit_window_mm"].dropna())
    window = f" within {float(windows[0]):g} mm" if len(windows) == 1 else ""
    our = (
        f"waterbed better{window} in {int(waterbed.sum())} of {_n(len(tests), 'trial')}, "
        f"the Boussinesq form in {int(boussinesq.sum())} (D / SE {_span(z, 1, '')}); "
        f"RMSE ratio Boussinesq/waterbed median {format_fixed(np.median(ratio), 2)} "
        f"(range {_span(ratio, 2, '')}); shifted parabola smaller RMSE in "
        f"{int(shifted_better[usable].sum())} of {int(usable.sum())}"
    )
    if boussinesq.any():
        worse = [lab for lab, b in zip(labels, boussinesq, strict=True) if b]
        reason = (
            f"The Boussinesq form fits better, beyond the noise, in {_list(worse)}, "
            "despite its extra parameter counting for nothing here."
        )
        return _row("C3", our, FAILS, reason, rule)
    if waterbed.all():
        reason = (
            f"In {_every(len(tests), 'trial')} the waterbed leaves smaller residuals than the "
            "Boussinesq form on the same points, beyond the noise, with one parameter fewer "
            f"(RMSE ratio {format_fixed(np.median(ratio), 1)}, median)."
        )
        return _row("C3", our, HOLDS, reason, rule)
    open_ = [lab for lab, w in zip(labels, waterbed, strict=True) if not w]
    reason = (
        f"In {_list(open_)} the two fits differ by less than the noise can resolve; "
        "no trial favours the Boussinesq form beyond it."
    )
    return _row("C3", our, UNTESTABLE, reason, rule)


def _bulge_errors(fit, x, w, sides, bulge, settings):
    """Standard errors of the readings' mean ``m`` over the bulge points, and of ``m -
    f``, ``f`` the fitted curve's mean there: ``f`` moves with the readings of the fit
    window through L (``dL = J' dy``), which the noise may correlate with the bulge's."""
    finite = np.isfinite(w)
    x, w, sides, bulge = x[finite], w[finite], sides[finite], bulge[finite]
    covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
    depth_mm, L_mm = float(fit["depth_mm"]), float(fit["waterbed_L_mm"])
    mean_of = np.where(bulge, 1.0 / bulge.sum(), 0.0)
    window = in_fit_window(x, float(fit["fit_window_mm"]))
    through_L = np.zeros_like(x)
    if window.sum() >= 1:
        J = _L_sensitivity(waterbed_deflection_mm, x[window], depth_mm, L_mm, w[window])
        below, _, above, step = _around_L(waterbed_deflection_mm, x[bulge], depth_mm, L_mm)
        slope = float(np.mean(above - below) / (2 * step))
        through_L[window] = slope * J
    var_m = float(mean_of @ covariance @ mean_of)
    gap = mean_of - through_L
    var_gap = float(gap @ covariance @ gap)
    return math.sqrt(max(var_m, 0.0)), math.sqrt(max(var_gap, 0.0))


def claim_c4(fits, averaged, settings):
    """C4: the predicted bulge beyond L/3 is not in the data, a test per trial."""
    alpha = settings.significance
    z_one = float(normal_quantile(1.0 - alpha))
    rule = (
        "Deflection W is positive downward, so the waterbed's bulge is W < 0: skin raised "
        "above its resting surface. Per trial: the averaged points with L/3 < distance < L "
        "at which the fitted waterbed curve is negative (its predicted bulge). Statistic: "
        "the mean of the readings there, m, against the curve's mean there, f (< 0), with "
        "standard errors from the covariance of the averaged points under the measured "
        "noise (correlated errors included), f's through the fitted L. The bulge is "
        f"resolvable in a trial if f lies more than {format_fixed(2 * z_one, 2)} standard "
        "errors of m - f below zero (readings at the resting surface then refute it with "
        f"probability {format_fixed(1 - alpha, 2)}), refuted if m exceeds f by more than "
        f"{format_fixed(z_one, 2)} of them (one-sided, significance = {alpha:g}), and seen "
        "if m is negative by more than the one-sided Bonferroni quantile over the trials "
        "times its standard error. Holds if no trial shows the bulge and every trial where "
        "it is resolvable refutes it; does not hold if some trial shows it; cannot be "
        "checked otherwise."
    )
    rows, n_trials = [], 0
    for fit, points in _trials(fits, averaged):
        if points.empty or not _finite_L(fit):
            continue
        n_trials += 1
        L_mm, depth_mm = float(fit["waterbed_L_mm"]), float(fit["depth_mm"])
        x = points["distance_mm"].to_numpy(float)
        w = points["deflection_mm"].to_numpy(float)
        sides = points["n_sides"].to_numpy(float)
        model = waterbed_deflection_mm(x, depth_mm, L_mm)
        bulge = (x > L_mm / 3.0) & (x < L_mm) & np.isfinite(w) & (model < 0.0)
        if not bulge.any():
            continue
        se_m, se_gap = _bulge_errors(fit, x, w, sides, bulge, settings)
        rows.append(
            {
                "label": _label(fit),
                "m": float(w[bulge].mean()),
                "f": float(model[bulge].mean()),
                "se_m": se_m,
                "se_gap": se_gap,
                "lowest": float(w[bulge].min()),
            }
        )
    if not rows:
        return _row(
            "C4",
            f"none of {_n(n_trials, 'trial')} has readings where the fitted curve is negative "
            "(a bulge above the resting surface)",
            UNTESTABLE,
            "No reading lies where the fitted curve predicts a bulge.",
            rule,
        )
    m = np.array([r["m"] for r in rows])
    f = np.array([r["f"] for r in rows])
    se_m = np.array([r["se_m"] for r in rows])
    se_gap = np.array([r["se_gap"] for r in rows])
    z_all = float(normal_quantile(1.0 - alpha / len(rows)))
    with np.errstate(divide="ignore", invalid="ignore"):
        seen = np.where(se_m > 0, m / se_m < -z_all, m < 0)
        # the least bulge that readings at the resting surface refute with power 1 - alpha
        resolvable = np.where(se_gap > 0, f / se_gap < -2.0 * z_one, f < 0)
        refuted = np.where(se_gap > 0, (m - f) / se_gap > z_one, m > f)
    labels = [r["label"] for r in rows]
    our = (
        f"{len(rows)} of {_n(n_trials, 'trial')} {'has' if len(rows) == 1 else 'have'} "
        "readings in the predicted bulge; mean of the "
        f"fitted curve there {_span(f, 3)}, mean of the data {_span(m, 3)} (standard error "
        f"{_span(se_m, 3)}, of the difference {_span(se_gap, 3)}; lowest single point "
        f"{_mm(min(r['lowest'] for r in rows), 3)}); resolvable in {int(resolvable.sum())}, "
        f"refuted in {int((resolvable & refuted).sum())}, bulge seen in {int(seen.sum())}"
    )
    if seen.any():
        showing = [lab for lab, s_ in zip(labels, seen, strict=True) if s_]
        our += f" ({_list(showing)})"
        reason = (
            "The readings rise above the resting surface, beyond the noise, where the curve "
            f"predicts a bulge, in {_list(showing)}."
        )
        return _row("C4", our, FAILS, reason, rule)
    if resolvable.any() and refuted[resolvable].all():
        reason = (
            f"In the {int(resolvable.sum())} of {_n(len(f), 'trial')} where the noise could "
            "show a bulge (a subset of the ranges above), the fitted curves predict one of "
            f"{_span(-f[resolvable], 3)} on average and the readings average "
            f"{_span(m[resolvable], 3)} of deflection: in each of them the skin stays below "
            "the predicted bulge beyond the noise. No bulge."
        )
        return _row("C4", our, HOLDS, reason, rule)
    open_ = [lab for lab, r_, q in zip(labels, resolvable, refuted, strict=True) if r_ and not q]
    reason = (
        f"In {_list(open_)} the readings cannot be told from the predicted bulge"
        if open_
        else "The predicted bulge is smaller than the noise can resolve in every trial"
    ) + "; no trial shows it either."
    return _row("C4", our, UNTESTABLE, reason, rule)


def _residual_noise_mm2(fit, x, w, sides, settings):
    """The mean square the noise alone leaves in the waterbed's residuals over the window.

    Fitting L removes the part of the noise along ``g = dm/dL``: under a covariance
    ``C`` the expected residual sum of squares of a one-parameter least-squares fit is
    ``trace(C) - g' C g / g' g`` to first order (``trace((I - H) C)``, ``H`` the fit's
    hat matrix ``g g' / g' g``); over ``n`` points, that over ``n``.  Without the
    second term, errors the fit absorbs through L (a depth error scales the profile,
    much as a change of L does) would be subtracted although they never reach the
    residuals, and the correction, largest relative to W0² at the smallest depth, would
    tilt the relative misfit against depth.
    """
    covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
    depth_mm = float(fit["depth_mm"])
    below, _, above, step = _around_L(
        waterbed_deflection_mm, x, depth_mm, float(fit["waterbed_L_mm"])
    )
    g = (above - below) / (2 * step)
    absorbed = float(g @ covariance @ g) / float(g @ g) if float(g @ g) > 0 else 0.0
    return (float(np.trace(covariance)) - absorbed) / x.size


def claim_c8(fits, averaged, settings):
    """C8: the waterbed's misfit relative to the depth grows with depth, tested across
    subjects.

    The statistic of a trial is ``q = (RMSE**2 - s**2) / W0**2``: the waterbed's mean
    square misfit beyond the noise (``s**2`` the mean noise variance of the fitted
    points, from the trial's covariance) over the depth squared.  The small-slope
    waterbed is linear in W0 at a fixed L, so a finger whose profile keeps one shape
    at every depth (``w = W0 f(x)``) has a misfit ``W0 (f - g)`` of fixed shape: its
    ``RMSE**2 - s**2`` grows as W0**2 although the model is no worse relative to the
    deformation, and ``q`` stays constant.  ``q`` grows only where the shape of the
    profile departs further from the waterbed's the deeper the indentation, which is
    what "describes the data less well" means for a model of the deformation.

    The correction ``s**2 / W0**2`` is largest at the smallest depth: a noise level
    stated too high makes ``q`` rise towards zero with depth and can make the claim
    hold on a model without misfit (a test shows it), so ``s**2`` comes from the
    measured noise table, never from a guess.

    Each subject with two or more depths gives the least-squares slope of ``q``
    against depth; the slopes are tested across subjects, species a fixed effect, by
    Student's t.  The t-test needs a degree of freedom for the spread between
    subjects, and with one or two that spread rests on one or two differences: the
    claim cannot be checked with fewer than ``settings.slope_min_df`` (subjects with
    two depths less the species; the config schema gives the reasons).
    """
    alpha = settings.significance
    min_df = settings.slope_min_df
    rule = (
        "Per trial: the waterbed's relative excess misfit q = (RMSE² − s²) / W₀², with "
        "RMSE over the fit window and s² the mean noise variance of the averaged points "
        "there under the trial's covariance from the noise table, less the part the fit of L "
        "absorbs (trace(C) − g'Cg/g'g over n, g = dm/dL); not truncated at zero, so "
        "noise averages out. Relative to W₀² because the waterbed is linear in W₀ at a "
        "fixed L: a profile that keeps one shape at every depth has an excess growing as "
        "W₀² but a constant q. Per subject with two or more depths: the least-squares "
        "slope of q against depth (per mm). Across subjects: the slopes regressed on "
        "species (a fixed effect), and the mean of the species' mean slopes tested "
        f"one-sided with Student's t (significance = {alpha:g}). Holds if the slope is "
        "significantly above zero (the relative misfit grows with depth); does not hold if "
        f"its upper one-sided {format_fixed(100 * (1 - alpha), 0)} % bound is below zero; "
        "cannot be checked otherwise, or with fewer subjects measured at two depths than "
        f"species + {min_df} (config claims: slope_min_df: the spread between subjects "
        f"must rest on at least {_n(min_df, 'degree of freedom', 'degrees of freedom')})."
    )
    relative = {}
    species_of = {}
    for fit, points in _trials(fits, averaged):
        rmse_mm = float(fit["waterbed_rmse_mm"])
        depth_mm = float(fit["depth_mm"])
        if points.empty or not math.isfinite(rmse_mm) or not depth_mm > 0:
            continue
        x, w, sides = _window_points(fit, points)
        variance = _residual_noise_mm2(fit, x, w, sides, settings) if x.size >= 2 else 0.0
        subject = str(fit["subject"])
        species_of[subject] = str(fit["species"])
        relative.setdefault(subject, []).append((depth_mm, (rmse_mm**2 - variance) / depth_mm**2))
    test = _slopes_across_subjects(relative, species_of, alpha)
    slopes, species, df = test["slopes"], test["species"], test["df"]
    per_depth = {}
    for values in relative.values():
        for depth_mm, value in values:
            per_depth.setdefault(depth_mm, []).append(value)
    means = ", ".join(
        f"{d:g} mm {format_fixed(100 * np.mean(v), 3)}" for d, v in sorted(per_depth.items())
    )
    if df < min_df:
        return _too_few_subjects("C8", slopes, species, rule, min_df)
    estimate, se, t_value = test["estimate"], test["se"], test["t"]
    p_value, upper = test["p"], test["upper"]
    per_subject = ", ".join(f"{s} {format_fixed(100 * v, 3)}" for s, v in slopes.items())
    our = (
        f"relative excess misfit (RMSE² − s²) / W₀² (%), mean per depth: {means}; slope "
        f"per subject (% per mm of depth): {per_subject}; mean slope "
        f"{format_fixed(100 * estimate, 3)} ± {format_fixed(100 * se, 3)} (t = "
        f"{format_fixed(t_value, 2)}, "
        f"{counted(df, 'degree of freedom', 'degrees of freedom')}, one-sided p {_p_text(p_value)})"
    )
    if p_value < alpha:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the waterbed's misfit beyond the noise, "
            f"relative to the depth, grows with depth, by {format_fixed(100 * estimate, 3)} % "
            f"of W₀² per mm on average (one-sided p {_p_text(p_value)})."
        )
        return _row("C8", our, HOLDS, reason, rule)
    if upper < 0:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the misfit beyond the noise, relative to "
            f"the depth, shrinks with depth (upper bound {format_fixed(100 * upper, 3)} % of "
            "W₀² per mm)."
        )
        return _row("C8", our, FAILS, reason, rule)
    reason = (
        f"Across {_n(len(slopes), 'subject')} the mean slope of the relative misfit "
        f"({format_fixed(100 * estimate, 3)} ± {format_fixed(100 * se, 3)} % of W₀² per mm) is "
        "neither shown to be above zero nor below it."
    )
    return _row("C8", our, UNTESTABLE, reason, rule)


def _mean_residual(fit, x, w, sides, model, settings):
    """A trial's mean residual (readings minus the fitted curve) over the fit window
    and its standard error under the trial's covariance.

    The residual moves with the readings directly and through the fitted L
    (:func:`_L_sensitivity`): ``a = 1/n - mean(dm/dL) J``, so its variance is
    ``a' C a`` with ``C`` the covariance of the averaged points.
    """
    depth_mm, L_mm = float(fit["depth_mm"]), float(fit[f"{model}_L_mm"])
    curve = family(model).curve
    below, middle, above, step = _around_L(curve, x, depth_mm, L_mm)
    J = _L_sensitivity(curve, x, depth_mm, L_mm, w)
    a = np.full(x.size, 1.0 / x.size) - float(np.mean((above - below) / (2 * step))) * J
    covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
    se = math.sqrt(max(float(a @ covariance @ a), 0.0))
    return float(np.mean(w - middle)), se, float(np.mean(w < middle))


def claim_c9(fits, averaged, settings):
    """C9: at larger depths the data are deflected less than the waterbed near the load, in any
    coordinates; a test per trial of the mean residual under the trial's covariance."""
    large = settings.large_depth_mm
    alpha = settings.significance
    models = (PAPER_FIT, *CONSISTENT_FITS)
    rule = (
        f"Per trial at depth >= large_depth_mm = {large:g} mm, for the paper's procedure and "
        "the two fits in measured coordinates (shifted parabola, exact arc): the mean "
        "residual m (readings minus the fitted curve) over the fit window, with its standard "
        "error under the trial's covariance (the noise table: every measured part and "
        "prior), the fitted L's response to the readings included. The readings fall short "
        f"of a curve if m is below zero by z(1 - {alpha:g}) standard errors (one-sided, "
        f"significance = {alpha:g}; in the figures, whose deflection axis points down, such "
        "points sit above the curve); they exceed it if m is above zero by the one-sided "
        "Bonferroni quantile over the trials and the three curves. Holds if the readings "
        "fall short of all three curves in every such trial (each at significance "
        f"{alpha:g}: a claim of all is wrong only if some trial's test is); does not hold if "
        "they exceed some curve in some trial; cannot be checked otherwise, and the reason "
        "says where they fall short of the paper's curve only (then 'stiffer than the "
        "model' is an artefact of the coordinates). Beside it: the fraction of points "
        "deflected less than each curve."
    )
    results = {m: [] for m in models}
    labels = []
    for fit, points in _trials(fits, averaged):
        if float(fit["depth_mm"]) < large or points.empty:
            continue
        if not all(_finite_L(fit, m) for m in models):
            continue
        x, w, sides = _window_points(fit, points)
        if x.size < 2:
            continue
        labels.append(_label(fit))
        for model in models:
            results[model].append(_mean_residual(fit, x, w, sides, model, settings))
    if not labels:
        return _row(
            "C9",
            f"no trial at a depth of {large:g} mm or more with all three fits",
            UNTESTABLE,
            f"No trial reaches {large:g} mm with the three waterbed fits.",
            rule,
        )
    z_one = float(normal_quantile(1.0 - alpha))
    z_all = float(normal_quantile(1.0 - alpha / (len(labels) * len(models))))
    short, over = {}, {}
    for model in models:
        m = np.array([r[0] for r in results[model]])
        se = np.array([r[1] for r in results[model]])
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(se > 0, m / se, np.sign(m) * np.inf)
        short[model], over[model] = z < -z_one, z > z_all
    our = "; ".join(
        f"{FIT_WORDS[m]}: mean residual "
        f"{_span([1e3 * r[0] for r in results[m]], 1, ' µm')} (standard error "
        f"{_span([1e3 * r[1] for r in results[m]], 1, ' µm')}), "
        f"{_span([100 * r[2] for r in results[m]], 0, ' %')} of points deflected less; "
        f"short of the curve in {int(short[m].sum())} of "
        f"{_n(len(labels), 'trial')}, beyond it in {int(over[m].sum())}"
        for m in models
    )
    everywhere = np.logical_and.reduce([short[m] for m in models])
    if everywhere.all():
        reason = (
            f"In {_every(len(labels), 'trial')} at {large:g} mm or deeper the readings are "
            "deflected less than the fitted curve on average, beyond the noise, whichever "
            "coordinates the curve is placed in."
        )
        return _row("C9", our, HOLDS, reason, rule)
    parts = []
    exceeding = np.logical_or.reduce([over[m] for m in models])
    if exceeding.any():
        parts.append(
            "the readings are deflected more than a fitted curve, beyond the noise, in "
            + _list([lab for lab, e in zip(labels, exceeding, strict=True) if e])
        )
    coordinates = short[PAPER_FIT] & ~short["shifted"]
    finite = short[PAPER_FIT] & short["shifted"] & ~short["arc"]
    open_ = ~short[PAPER_FIT] & ~exceeding
    if coordinates.any():
        parts.append(
            f"in {_list([lab for lab, c in zip(labels, coordinates, strict=True) if c])} they "
            "fall short of the paper's curve but not, beyond the noise, of the same parabola "
            "placed in measured coordinates, so there the 'stiffer' reading may be an "
            f"artefact of the paper's coordinates ({COORDINATES_FIGURE})"
        )
    if finite.any():
        parts.append(
            f"in {_list([lab for lab, c in zip(labels, finite, strict=True) if c])} they fall "
            "short of both parabolas but not, beyond the noise, of the exact arc, so there it "
            "may come from the small-slope approximation rather than the fingertip"
        )
    if open_.any():
        parts.append(
            f"in {_list([lab for lab, c in zip(labels, open_, strict=True) if c])} the noise "
            "cannot tell the readings from the paper's curve on average"
        )
    reason = "; ".join(parts)
    verdict = FAILS if exceeding.any() else UNTESTABLE
    return _row("C9", our, verdict, reason[0].upper() + reason[1:] + ".", rule)
