"""How closely two fits of the same points must agree, derived from rounding.

Two code paths (a trial alone or in a batch, one CPU's vector kernels or
another's) evaluate the same least-squares objective with different rounding.
The objective's rounding error is bounded here from the sizes of the numbers it
is made of; :func:`lineload.fitting.optimize.solution_tolerance` turns that bound into how
far the minimiser and the interval's ends may move.  Nothing here is tuned to
make a comparison pass: every term has its reason in a docstring.
"""

from __future__ import annotations

import math

import numpy as np

from lineload import models
from lineload.fitting import batch as fitting
from lineload.fitting.optimize import CHI2_1DOF_95, solution_tolerance

EPS = np.finfo(float).eps

#: Floating-point operations that round between a reading and its residual (model
#: evaluation included: a handful for the parabola, a few more through the circle's
#: geometry); a bound, used as the factor of machine epsilon per point.
OPERATIONS_PER_POINT = 16

#: Relative width of the final bracket of the grid-and-Brent search
#: (``minimize_bounded``'s ``rtol``) and of the root finder (``find_roots``).
SEARCH_RTOL = 1e-9
ROOT_RTOL = 1e-10
#: The root finder also stops when ``|ln(S / S_threshold)|`` is below this.
ROOT_FTOL = 1e-14

CURVES = {
    "waterbed": models.waterbed_deflection_mm,
    "shifted": models.shifted_deflection_mm,
    "arc": models.arc_deflection_mm,
}


def fit_rounding_mm2(y_mm, model_mm, scale_mm=None):
    """A bound on the rounding error of ``sum((y - model)**2)``.

    Each residual is off by at most ``OPERATIONS_PER_POINT eps S`` (``S`` the
    largest magnitude in its computation, at least ``|y|`` and ``|model|``; the
    arc's circle adds its radius), which changes the sum by twice that times
    ``|r|``; the summation itself adds ``(n + 2) eps`` of the sum.
    """
    y_mm, model_mm = np.asarray(y_mm, dtype=float), np.asarray(model_mm, dtype=float)
    residual = y_mm - model_mm
    size = np.maximum(np.abs(y_mm), np.abs(model_mm))
    if scale_mm is not None:
        size = np.maximum(size, scale_mm)
    per_point = OPERATIONS_PER_POINT * EPS * size
    sse = float(np.sum(residual**2))
    return (
        float(np.sum(2.0 * np.abs(residual) * per_point + per_point**2))
        + (y_mm.size + 2) * EPS * sse
    )


#: Relative step of the central differences that give the sandwich's Jacobian
#: (``lineload.fitting.intervals._sandwich_delta``).
SANDWICH_STEP = 1e-4


def _jacobian(curve, x, depth, L_mm):
    """The curve's derivative in L by central differences, as the sandwich takes it;
    one-sided where the curve is not defined below L (the shifted fit at its bound)."""
    step = SANDWICH_STEP * L_mm
    with np.errstate(invalid="ignore"):
        below = curve(x, depth, L_mm - step)
    above = curve(x, depth, L_mm + step)
    if np.all(np.isfinite(below)):
        return (below - above) / (2 * step)
    return (curve(x, depth, L_mm) - above) / step


def _sandwich_rise(curve, x, y, depth, L_mm, sse_min, ends, rounding, jacobian):
    """How far the sum of squares rises at the interval's ends (the sandwich's
    ``delta``), and a bound on the part of two paths' difference in ``delta`` that
    rounding makes.

    The rise is read off the row itself: the sum of squares at each finite end
    minus at the minimum.  ``delta`` is ``chi2 J'CJ / H`` with ``J`` from central
    differences at ``L (1 +- SANDWICH_STEP)``: each residual's rounding, divided by
    the step, errs by ``OPERATIONS_PER_POINT eps size / (step |J|)`` relative to
    ``J``, twice that in ``J'CJ`` and in ``H``.  (The other part, the two paths'
    L being apart, is :func:`_sandwich_shift`.)
    """
    rises = [
        float(np.sum((y - curve(x, depth, end)) ** 2)) - sse_min for end in ends if np.isfinite(end)
    ]
    rises = [r for r in rises if r > 0]
    if not rises:
        return None, 0.0
    step = SANDWICH_STEP * L_mm
    size = float(np.max(np.maximum(np.abs(y), np.abs(curve(x, depth, L_mm)))))
    j_rms = max(float(np.sqrt(np.mean(jacobian**2))), np.finfo(float).tiny)
    relative = 4.0 * OPERATIONS_PER_POINT * EPS * size / (step * j_rms)
    rise = min(rises)
    # the ends' own sums of squares round too (both paths): the rise is known to that
    return rise, rise * relative + 2.0 * rounding


def _sandwich_shift(curve, x, depth, L_mm, tol_L, jacobian):
    """Relative change of the sandwich's ``delta`` when L moves by ``tol_L``.

    Two paths find L only to ``tol_L`` (the minimum of a sum of squares is flat) and
    evaluate ``J`` and ``H`` there.  ``J'CJ`` and ``J'J`` (the bulk of ``H``) are
    quadratic in ``J``: each moves by at most twice ``|dJ| / |J|`` relative (for a
    covariance that does not single out the direction of ``dJ``), their ratio by
    the sum, and the misfit term of ``H`` (residuals times the curvature, the
    residuals moving by ``J tol_L``) by about as much again: six times in all.
    """
    moved = _jacobian(curve, x, depth, L_mm + tol_L)
    norm = max(float(np.linalg.norm(jacobian)), np.finfo(float).tiny)
    return 6.0 * float(np.linalg.norm(moved - jacobian)) / norm


def _one_parameter_tolerances(row, model, x, y, rounding, sandwich=False):
    """Tolerances of L, its interval's ends and the fit measures of one model.

    ``sandwich``: the interval comes from the points' covariance (a noise model),
    its ends where the sum of squares has risen by the sandwich's ``delta``, not by
    the profile likelihood's ``SSE_min (exp(chi2 / n) - 1)``.
    """
    n = x.size
    L_mm = row[f"{model}_L_mm"]
    low, high = row[f"{model}_L_ci_low_mm"], row[f"{model}_L_ci_high_mm"]
    sse_min = n * row[f"{model}_rmse_mm"] ** 2
    threshold = max(sse_min, np.finfo(float).tiny) * math.exp(CHI2_1DOF_95 / max(n, 1))
    curve, depth, jacobian, delta_error = CURVES[model], row["depth_mm"], None, 0.0
    if sandwich and np.isfinite(L_mm):
        jacobian = _jacobian(curve, x, depth, L_mm)
        rise, delta_error = _sandwich_rise(
            curve, x, y, depth, L_mm, sse_min, (low, high), rounding, jacobian
        )
        if rise is not None:
            threshold = sse_min + rise
    half = (high - low) / 2.0
    if not np.isfinite(half):
        half = abs(L_mm) if np.isfinite(L_mm) else 1.0
    # both paths round: twice the bound; the root finder's own stop adds its share
    both = 2.0 * rounding
    error = both + ROOT_FTOL * threshold + delta_error
    tol_L = solution_tolerance(sse_min, threshold, half, error)[0]
    if jacobian is not None and threshold > sse_min:
        # the ends also follow delta, evaluated at each path's own L
        error += (threshold - sse_min) * _sandwich_shift(
            curve, x, depth, L_mm, float(tol_L), jacobian
        )
    tol_end = solution_tolerance(sse_min, threshold, half, error)[1]
    tol_L = float(tol_L) + 2.0 * SEARCH_RTOL * abs(L_mm)
    rise = max(threshold - sse_min, np.finfo(float).tiny)
    d_sse = both + rise * min((tol_L / half) ** 2, 1.0)
    rmse = row[f"{model}_rmse_mm"]
    return {
        f"{model}_L_mm": tol_L,
        f"{model}_L_ci_low_mm": float(tol_end) + 2.0 * ROOT_RTOL * abs(low),
        f"{model}_L_ci_high_mm": float(tol_end) + 2.0 * ROOT_RTOL * abs(high),
        f"{model}_rmse_mm": d_sse / (2.0 * n * rmse) if rmse > 0 else math.sqrt(d_sse / n),
        f"{model}_max_abs_residual_mm": math.sqrt(d_sse) + OPERATIONS_PER_POINT * EPS,
        f"{model}_aicc": n * d_sse / sse_min if sse_min > 0 else math.inf,
    }


def _boussinesq_tolerances(row, x, y, rounding, sandwich=False):
    """Tolerances of the log-linear regression's parameters and measures."""
    n = x.size
    log_x = -np.log(x)
    hessian = 2.0 * np.array([[n, log_x.sum()], [log_x.sum(), np.sum(log_x**2)]])
    eigenvalues = np.linalg.eigvalsh(hessian)
    A, x0 = row["boussinesq_A_mm"], row["boussinesq_x0_mm"]
    intercept = A * math.log(x0) if np.isfinite(x0) else float(np.mean(y))
    size = abs(A) + abs(intercept)
    # a change of the objective by `rounding` moves the minimum by sqrt(2 rounding /
    # lambda_min); the closed form's sums add n eps times the condition number
    condition = eigenvalues[-1] / max(eigenvalues[0], np.finfo(float).tiny)
    shift = math.sqrt(4.0 * rounding / max(eigenvalues[0], np.finfo(float).tiny))
    shift += (n + 2) * EPS * condition * size
    sse = n * row["boussinesq_rmse_mm"] ** 2
    d_sse = 4.0 * rounding
    rmse = row["boussinesq_rmse_mm"]
    tolerances = {
        "boussinesq_A_mm": shift,
        "boussinesq_rmse_mm": d_sse / (2.0 * n * rmse) if rmse > 0 else math.sqrt(d_sse / n),
        "boussinesq_max_abs_residual_mm": math.sqrt(d_sse) + OPERATIONS_PER_POINT * EPS * size,
        "boussinesq_aicc": n * d_sse / sse if sse > 0 else math.inf,
    }
    if np.isfinite(x0) and A > 0:
        # x0 = exp(intercept / A): relative error of the ratio's change
        tolerances["boussinesq_x0_mm"] = x0 * (shift + abs(intercept / A) * shift) / A
    if sandwich:
        tolerances.update(_boussinesq_sandwich_tolerances(row, x, shift, condition))
    else:
        tolerances.update(_boussinesq_interval_tolerances(row, x, y, shift, d_sse, condition))
    return tolerances


def _boussinesq_sandwich_tolerances(row, x, shift, condition):
    """Tolerances of the ends of the sandwich intervals on A and x0 (with a covariance).

    The ends are ``A +- z sd_A`` and ``exp(ln x0 +- z sd)``; the standard deviations
    come from ``V = (X'X)^-1 X'CX (X'X)^-1``, computed from the same sums in both
    paths: ``V`` errs by ``(n + 2) eps`` times twice the condition number of
    ``X'X`` (each inverse) plus once (``X'CX``), relative, and ``sd`` by half that;
    x0's ``sd`` also moves with ``A`` and the intercept (``shift``) through its
    gradient ``(1 / A, -a / A^2)``.
    """
    n = x.size
    out = {}
    relative = 0.5 * (n + 2) * EPS * (2.0 * condition + 1.0)
    A = row["boussinesq_A_mm"]
    low, high = row["boussinesq_A_ci_low_mm"], row["boussinesq_A_ci_high_mm"]
    sd = (high - low) / 2.0 if np.isfinite(low) and np.isfinite(high) else 0.0
    for name in ("A_ci_low_mm", "A_ci_high_mm"):
        out[f"boussinesq_{name}"] = shift + sd * relative
    ends = [row["boussinesq_x0_ci_low_mm"], row["boussinesq_x0_ci_high_mm"]]
    if not (np.isfinite(A) and A > 0 and all(np.isfinite(ends))):
        return out
    log_x0 = math.log(row["boussinesq_x0_mm"])
    half_log = (math.log(ends[1]) - math.log(ends[0])) / 2.0
    tol_log = (shift + abs(log_x0) * shift) / A  # of ln x0 = a / A
    # the gradient's relative move: shift / A, twice (through 1 / A and a / A^2)
    tol_half = half_log * (relative + 2.0 * shift / A)
    for name, end in zip(("x0_ci_low_mm", "x0_ci_high_mm"), ends, strict=True):
        out[f"boussinesq_{name}"] = end * (tol_log + tol_half)
    return out


def _boussinesq_interval_tolerances(row, x, y, shift, d_sse, condition):
    """Tolerances of the ends of the profile intervals on A and x0 (no covariance).

    A's ends are ``A +- sqrt(delta / D)`` with ``delta`` proportional to the
    minimum sum of squares and ``D = s22 - s12**2 / s11``: the end moves with A
    (``shift``), and the half-width by half the relative error of ``delta``
    (``d_sse / SSE``) and of ``D`` (its sums, times the condition number).

    x0's ends are ``exp(z)`` for the roots ``z`` of ``F(z) = a2 z^2 + 2 a1 z + a0``,
    whose coefficients are products of sums over the points.  An error ``dF`` in
    ``F`` at the root moves it by ``dF / |F'(z)|`` (``F' = 2 (a2 z + a1)``); ``dF``
    is bounded by the rounding of each coefficient (``(n + 2) eps`` times the sizes
    of the terms it is made of, and the threshold's own error ``d_sse`` through
    ``c``), each times ``|z|`` to its power.
    """
    n = x.size
    names = ("A_ci_low_mm", "A_ci_high_mm", "x0_ci_low_mm", "x0_ci_high_mm")
    out = {f"boussinesq_{name}": 0.0 for name in names}
    low, high = row["boussinesq_A_ci_low_mm"], row["boussinesq_A_ci_high_mm"]
    sse = n * row["boussinesq_rmse_mm"] ** 2
    if np.isfinite(low) and np.isfinite(high):
        half = (high - low) / 2.0
        relative = 0.5 * (d_sse / sse if sse > 0 else 1.0) + (n + 2) * EPS * condition
        out["boussinesq_A_ci_low_mm"] = shift + half * relative
        out["boussinesq_A_ci_high_mm"] = shift + half * relative
    ends = [row["boussinesq_x0_ci_low_mm"], row["boussinesq_x0_ci_high_mm"]]
    if not all(np.isfinite(ends)):
        return out
    logs = -np.log(x)
    s11, s12, s22 = float(n), float(np.sum(logs)), float(np.sum(logs**2))
    t1, t2, total = float(np.sum(y)), float(np.sum(logs * y)), float(np.sum(y**2))
    threshold = max(sse, np.finfo(float).tiny) * math.exp(CHI2_1DOF_95 / n)
    c = total - threshold
    k = (n + 2) * EPS
    # sizes of the terms each coefficient is made of, and the error of c
    size_t1, size_t2 = float(np.sum(np.abs(y))), float(np.sum(np.abs(logs * y)))
    size_s12 = float(np.sum(np.abs(logs)))
    dc = k * (total + threshold) + 2.0 * d_sse
    d_a2 = 3 * k * (size_t1**2 + abs(c) * s11) + dc * s11
    d_a1 = 3 * k * (size_t1 * size_t2 + abs(c) * size_s12) + dc * size_s12
    d_a0 = 3 * k * (size_t2**2 + abs(c) * s22) + dc * s22
    a2, a1 = t1**2 - c * s11, t1 * t2 - c * s12
    for name, end in zip(("x0_ci_low_mm", "x0_ci_high_mm"), ends, strict=True):
        z = math.log(end)
        slope = 2.0 * abs(a2 * z + a1)
        d_f = d_a2 * z * z + 2.0 * d_a1 * abs(z) + d_a0
        # the quadratic formula's own rounding: a few eps of the largest term
        d_f += 4 * EPS * (abs(a2) * z * z + 2.0 * abs(a1 * z) + abs(t2**2 - c * s22))
        d_z = d_f / slope if slope > 0 else math.inf
        out[f"boussinesq_{name}"] = end * d_z
    return out


def fit_row_tolerances(row, x_mm, y_mm, sandwich=False):
    """Absolute tolerance of each numeric column of a fit-table row.

    Parameters
    ----------
    row : dict
        A row of :func:`lineload.fitting.batch.fit_trials` (the reference).
    x_mm, y_mm : array_like
        The trial's averaged profile (all of its points).
    sandwich : bool, optional
        The fit was given a noise model (the intervals are the sandwich's), as the
        workflow's fit tables are.

    Returns
    -------
    dict
        Column name to tolerance (0 for counts and settings).
    """
    x_mm, y_mm = np.asarray(x_mm, dtype=float), np.asarray(y_mm, dtype=float)
    keep = fitting.in_fit_window(x_mm, row["fit_window_mm"]) & np.isfinite(y_mm)
    x, y = x_mm[keep], y_mm[keep]
    tolerances = {name: 0.0 for name in row}
    if x.size == 0:
        return tolerances
    depth = row["depth_mm"]
    for model, curve in CURVES.items():
        L_mm = row[f"{model}_L_mm"]
        if not np.isfinite(L_mm):
            continue
        model_mm = curve(x, depth, L_mm)
        rounding = fit_rounding_mm2(y, model_mm, L_mm**2 / depth)
        tolerances.update(_one_parameter_tolerances(row, model, x, y, rounding, sandwich))
        tol_L = tolerances[f"{model}_L_mm"]
        for end in ("min", "max"):
            # L refitted in other windows: the same search, stopped at the same relative
            # tolerance; its rounding part taken as this window's
            name = f"{model}_L_window_{end}_mm"
            if name in row and np.isfinite(row[name]):
                tolerances[name] = tol_L + 2.0 * SEARCH_RTOL * abs(row[name])
        # a ratio of two quadratic forms in the curve's slope at L, which moves by tol_L
        # (relative 1e-8 or less): far below this
        tolerances[f"{model}_L_prior_share"] = 1e-6
    tolerances["boussinesq_A_prior_share"] = 1e-6
    tolerances["boussinesq_A_wedge_share"] = 1e-6  # a ratio of the same variances
    if np.isfinite(row["boussinesq_A_mm"]):
        A, x0 = row["boussinesq_A_mm"], row["boussinesq_x0_mm"]
        # without a zero crossing (A <= 0) the row has no intercept: size from the data
        model_mm = A * np.log(x0 / x) if np.isfinite(x0) else y.copy()
        rounding = fit_rounding_mm2(y, model_mm)
        tolerances.update(_boussinesq_tolerances(row, x, y, rounding, sandwich))
    return tolerances


def assert_rows_agree(rows, expected_rows, distance_mm, deflection_mm, sandwich=False):
    """Rows of two fits of the same trials agree within :func:`fit_row_tolerances`.

    NaN must meet NaN and an infinity the same infinity.
    """
    assert len(rows) == len(expected_rows)
    for i, (row, expected) in enumerate(zip(rows, expected_rows, strict=True)):
        assert list(row) == list(expected)
        tolerances = fit_row_tolerances(expected, distance_mm[i], deflection_mm[i], sandwich)
        for name, value in expected.items():
            actual = row[name]
            if isinstance(value, str):
                assert actual == value, (i, name)
                continue
            if not np.isfinite(value) or not np.isfinite(actual):
                same = (np.isnan(value) and np.isnan(actual)) or actual == value
                assert same, (i, name, actual, value)
                continue
            gap = abs(actual - value)
            assert gap <= tolerances[name], (i, name, actual, value, gap, tolerances[name])
