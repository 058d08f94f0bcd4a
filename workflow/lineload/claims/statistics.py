"""Statistics the claims share: a profile's deformed extent, the sides' asymmetry, a
stretch's curvature, a fitted curve's zero, how a fitted L moves with the readings, and
slopes against depth tested across subjects.  Pure functions on arrays, with the
standard error of each under the readings' noise.
"""

from __future__ import annotations

import math

import numpy as np

from lineload.distributions import student_t_quantile, student_t_survival
from lineload.models import waterbed_deflection_mm

__all__ = [
    "asymmetry_excess",
    "chord_curvature",
    "deformed_extent_mm",
    "deformed_extent_se_mm",
    "waterbed_zero_crossing_mm",
]


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


def deformed_extent_se_mm(distance_mm, deflection_mm, threshold_mm, covariance_mm2):
    """:func:`deformed_extent_mm` with its standard error under the readings' noise.

    The extent is where the line between the last point above the threshold and
    the next one crosses it.  To first order an error ``e`` of the interpolated
    deflection there moves the crossing by ``e / |slope|``; ``e`` has the variance
    of ``(1 - s) w_i + s w_(i+1)`` (``s`` the crossing's fraction of the step)
    under the covariance.  Where the farthest reading is still above the threshold
    the extent is a lower bound and its error is taken from the last step's slope.
    First order only: where the noise is comparable to the drop over one step, the
    last point above the threshold can change and the spread is larger (by 15 % on
    a straight decay with noise a quarter of a step's drop).

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        One averaged profile (mm), sorted by distance, all finite.
    threshold_mm : float
        As for :func:`deformed_extent_mm`.
    covariance_mm2 : array_like
        ``(n, n)`` covariance of the deflections (mm^2).

    Returns
    -------
    tuple of float
        ``(extent_mm, se_mm)``; ``(0, 0)`` when no point exceeds the threshold.
    """
    x = np.asarray(distance_mm, dtype=float)
    w = np.asarray(deflection_mm, dtype=float)
    c = np.asarray(covariance_mm2, dtype=float)
    extent = deformed_extent_mm(x, w, threshold_mm)
    above = np.flatnonzero(w > threshold_mm)
    if above.size == 0 or x.size < 2:
        return extent, 0.0
    i = int(above[-1])
    i, j = (i, i + 1) if i + 1 < x.size else (i - 1, i)
    s = float(np.clip((extent - x[i]) / (x[j] - x[i]), 0.0, 1.0))
    a = np.array([1.0 - s, s])
    variance = float(a @ c[np.ix_([i, j], [i, j])] @ a)
    slope = abs((w[j] - w[i]) / (x[j] - x[i]))
    if not slope > 0:
        return extent, math.inf
    return extent, math.sqrt(max(variance, 0.0)) / slope


def waterbed_zero_crossing_mm(depth_mm, L_mm, deflection=None):
    """Zero of a fitted small-slope waterbed curve inside the membrane, found numerically.

    Brent's method over ``[0, 2 L / 3]``: eq. 19 equals ``W0 > 0`` at the load and
    ``-W0 / 3`` at ``2 L / 3`` (the bottom of the bulge), so the bracket holds
    exactly one sign change.  Analytically the zero is ``L / 3``; this function
    does not use that.

    Parameters
    ----------
    depth_mm : float
        W0 (mm, > 0).
    L_mm : float
        Fitted half-width (mm, finite, > 0).
    deflection : callable, optional
        The curve ``f(distance_mm, depth_mm, L_mm)``; defaults to
        :func:`lineload.models.waterbed_deflection_mm` (eq. 19).

    Returns
    -------
    float
        The zero crossing (mm).
    """
    from scipy.optimize import brentq  # here: the claims' registry imports without scipy.optimize

    deflection = deflection or waterbed_deflection_mm

    def curve(distance_mm):
        return float(deflection(distance_mm, depth_mm, L_mm))

    return float(brentq(curve, 0.0, 2.0 * L_mm / 3.0, xtol=1e-14 * L_mm, rtol=1e-15))


def _chord_curvature_gls(x, w, covariance):
    """:func:`chord_curvature` with a full covariance of the deflections."""
    weight = np.linalg.inv(covariance)
    design = np.column_stack([np.ones_like(x), x])
    slope = np.linalg.solve(design.T @ weight @ design, design.T @ weight @ w)[1]
    cos, sin = 1.0 / math.hypot(1.0, slope), slope / math.hypot(1.0, slope)
    x_c, w_c = x - x.mean(), w - w.mean()
    u, v = x_c * cos + w_c * sin, -x_c * sin + w_c * cos
    weight = weight / cos**2  # vertical noise seen across the chord
    design = np.column_stack([np.ones_like(u), u, u * u])
    covariance_fit = np.linalg.inv(design.T @ weight @ design)
    _, b, c = covariance_fit @ (design.T @ weight @ v)
    factor = (1.0 + b * b) ** 1.5
    return float(2.0 * c / factor), float(2.0 * math.sqrt(covariance_fit[2, 2]) / factor)


def chord_curvature(distance_mm, deflection_mm, sd_mm):
    """Curvature of the circle that best fits a stretch of profile, with its standard error.

    The points are rotated into the frame of their least-squares chord, where a
    circle ``v = R - sqrt(R**2 - u**2) = u**2 / (2 R) + u**4 / (8 R**3) + ...`` is
    nearly a parabola; a weighted linear fit of ``v = a + b u + c u**2`` gives the
    curvature ``2 c / (1 + b**2)**1.5`` and, with the points' known noise, its
    standard error.  The quartic term biases the curvature of an exact circle
    upward by about ``(3/14) (h / R)**2`` (``h`` half the stretch's length), under
    1 % for the stretches used here.  Being linear, the fit works equally for a
    straight stretch (curvature near 0) and a curved one.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        At least four points of one profile (mm).
    sd_mm : array_like
        Standard deviation of each deflection (mm, vertical noise), or their
        ``(n, n)`` covariance (mm^2): the fit is then generalised least squares
        and the standard error honours correlated errors.

    Returns
    -------
    tuple of float
        ``(curvature_per_mm, standard_error_per_mm)``; the curvature is signed,
        positive where the deflection profile is convex (opens upward).
    """
    x = np.asarray(distance_mm, dtype=float)
    w = np.asarray(deflection_mm, dtype=float)
    if x.size < 4:
        raise ValueError(f"a curvature with an error needs at least 4 points, got {x.size}")
    if np.ndim(sd_mm) == 2:
        return _chord_curvature_gls(x, w, np.asarray(sd_mm, dtype=float))
    sd = np.broadcast_to(np.asarray(sd_mm, dtype=float), x.shape)
    slope = np.polyfit(x, w, 1, w=1.0 / sd)[0]
    cos, sin = 1.0 / math.hypot(1.0, slope), slope / math.hypot(1.0, slope)
    x_c, w_c = x - np.average(x, weights=sd**-2), w - np.average(w, weights=sd**-2)
    u, v = x_c * cos + w_c * sin, -x_c * sin + w_c * cos
    weight = (sd * cos) ** -2  # vertical noise seen across the chord
    design = np.column_stack([np.ones_like(u), u, u * u])
    normal = design.T @ (design * weight[:, None])
    covariance = np.linalg.inv(normal)
    _, b, c = covariance @ (design.T @ (weight * v))
    factor = (1.0 + b * b) ** 1.5
    return float(2.0 * c / factor), float(2.0 * math.sqrt(covariance[2, 2]) / factor)


def asymmetry_excess(difference_mm, covariance_mm2):
    """Mean square of left minus right beyond what the noise gives, with its standard error.

    ``D = mean(d**2) - trace(C) / n`` estimates the mean square of the true
    difference between the sides; under Gaussian noise ``mean(d**2)`` has
    variance ``(2 trace(C C) + 4 a' C a) / n**2`` for a true difference ``a``,
    estimated with ``a' C a ~ max(D, 0) trace(C)``.

    Parameters
    ----------
    difference_mm : array_like
        Left minus right at the distances both sides read (mm).
    covariance_mm2 : array_like
        Their covariance under noise alone (mm^2).

    Returns
    -------
    tuple of float
        ``(D_mm2, se_mm2)``.
    """
    d = np.asarray(difference_mm, dtype=float)
    c = np.asarray(covariance_mm2, dtype=float)
    n = d.size
    excess = float(np.mean(d**2) - np.trace(c) / n)
    variance = (2.0 * float(np.sum(c * c)) + 4.0 * max(excess, 0.0) * float(np.trace(c))) / n**2
    return excess, math.sqrt(variance)


def _around_L(curve, x_mm, depth_mm, L_mm):
    """``curve`` at ``L - step``, ``L`` and ``L + step`` (``step = 1e-4 L``), and the step:
    the central differences in L of :func:`_L_sensitivity` and C4's bulge."""
    step = 1e-4 * L_mm
    return (
        curve(x_mm, depth_mm, L_mm - step),
        curve(x_mm, depth_mm, L_mm),
        curve(x_mm, depth_mm, L_mm + step),
        step,
    )


def _L_sensitivity(curve, x_mm, depth_mm, L_mm, y_mm=None):
    """How a one-parameter least-squares L moves with the readings, to first order.

    At the minimum ``g . (y - m) = 0`` with ``g = dm/dL``; differentiating in the
    readings gives ``dL/dy = g / (g . g - r . h)``, ``r`` the residuals and
    ``h = d2m/dL2`` (central differences).  The ``r . h`` term matters where the
    model misfits the readings; without ``y_mm`` it is left out.
    """
    below, middle, above, step = _around_L(curve, x_mm, depth_mm, L_mm)
    g = (above - below) / (2 * step)
    curvature = 0.0
    if y_mm is not None:
        curvature = float(np.dot(y_mm - middle, (above - 2 * middle + below) / step**2))
    return g / (float(np.dot(g, g)) - curvature)


def _slopes_across_subjects(relative, species_of, alpha, variances=None):
    """Per-subject slopes of a per-trial statistic against depth, tested across subjects.

    Each subject with two or more depths gives the least-squares slope; the slopes are
    regressed on species (a fixed effect) and the mean of the species' mean slopes is
    tested one-sided by Student's t, with ``subjects - species`` degrees of freedom.

    Parameters
    ----------
    relative : dict
        Subject -> list of ``(depth_mm, value)``.
    species_of : dict
        Subject -> species.
    alpha : float
        Significance of the one-sided test.
    variances : dict, optional
        Subject -> list of the noise variance of each trial's value (in the order of
        ``relative``): where given, the slopes' own noise (propagated through each
        least-squares slope) sets a floor under the standard error, so that a value
        whose trend is the noise correction's, alike in every subject, is not taken
        for a finding because the subjects agree.

    Returns
    -------
    dict
        ``slopes`` (subject -> slope), ``species``, ``df``; with ``df >= 1`` also
        ``estimate``, ``se``, ``t``, ``p`` (one-sided, above zero) and ``upper`` (the
        one-sided ``1 - alpha`` upper bound).
    """
    slopes, slope_variances = {}, {}
    for subject, values in relative.items():
        depths = np.array([d for d, _ in values])
        if np.unique(depths).size >= 2:
            slopes[subject] = float(np.polyfit(depths, [q for _, q in values], 1)[0])
            if variances is not None:
                centred = depths - depths.mean()
                c = centred / float(np.sum(centred**2))
                slope_variances[subject] = float(np.sum(c**2 * np.asarray(variances[subject])))
    species = sorted({species_of[s] for s in slopes})
    df = len(slopes) - len(species)
    test = {"slopes": slopes, "species": species, "df": df}
    if df < 1:
        return test
    groups = {sp: np.array([v for s, v in slopes.items() if species_of[s] == sp]) for sp in species}
    group_means = np.array([g.mean() for g in groups.values()])
    residual = np.concatenate([g - g.mean() for g in groups.values()])
    variance = float(np.sum(residual**2)) / df
    # the contrast: mean over species of each species' mean slope
    weights = np.array([1.0 / len(species) / g.size for g in groups.values()])
    estimate = float(group_means.mean())
    se = math.sqrt(variance * float(np.sum(weights**2 * [g.size for g in groups.values()])))
    if slope_variances:
        weight_of = {sp: 1.0 / len(species) / g.size for sp, g in groups.items()}
        noise_se = math.sqrt(
            sum(weight_of[species_of[s]] ** 2 * v for s, v in slope_variances.items())
        )
        se = max(se, noise_se)
    t_value = estimate / se if se > 0 else math.copysign(math.inf, estimate)
    test.update(
        estimate=estimate,
        se=se,
        t=t_value,
        p=float(student_t_survival(t_value, df)),
        upper=estimate + float(student_t_quantile(1.0 - alpha, df)) * se,
    )
    return test
