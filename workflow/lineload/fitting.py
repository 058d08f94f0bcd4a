"""Least-squares fits of the deflection models to one averaged profile.

Every fit takes the same points (distance and deflection in mm) and returns a
:class:`FitResult` with its parameters and the same goodness-of-fit measures,
so that models can be compared on equal terms.

The waterbed fits keep ``W0`` fixed to the indentation depth, as in the paper,
and fit ``L`` alone, constrained to ``L >= max(distance)`` so that every fitted
point lies on the membrane (inside the wall).  Three waterbed variants are
fitted:

``waterbed``
    The paper's procedure: eq. 19, W(X), compared with readings taken at the
    deformed position x as if X were x.
``shifted``
    The same small-slope solution in measured coordinates: W(X) placed at
    ``x = X + U(X)`` (eqs 19-20).  It exists only while that map is one-to-one,
    ``L > sqrt(6) W0``; the fit searches that range only, and when the data
    would want a narrower membrane it stops at the bound (the fitted ``L`` then
    equals ``sqrt(6) W0`` to within the search tolerance and the interval's
    lower end is that bound).
``arc``
    The exact solution, a circular arc in the deformed plane.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .models import (
    MAX_ONE_TO_ONE_RATIO,
    arc_deflection_mm,
    arc_geometry,
    boussinesq_deflection_mm,
    shifted_deflection_mm,
    waterbed_deflection_mm,
)

__all__ = [
    "FitResult",
    "fit_arc",
    "fit_boussinesq",
    "fit_shifted",
    "fit_waterbed",
    "fit_waterbed_free_depth",
    "goodness_of_fit",
    "in_fit_window",
    "minimise_in_L",
]

#: 95 % quantile of the chi-square distribution with one degree of freedom
#: (``scipy.stats.chi2.ppf(0.95, 1)``; a test checks the value).
CHI2_1DOF_95 = 3.841458820694124

#: Largest membrane half-width searched by the iterative fits (exact arc, and the
#: parabola with W0 free), as a multiple of the smallest admissible one. The
#: fixed-W0 parabola needs no such bound: its minimum is found exactly.
L_SEARCH_SPAN = 1000.0


@dataclass(frozen=True)
class FitResult:
    """Outcome of one least-squares fit.

    Attributes
    ----------
    model : str
        ``"waterbed"``, ``"shifted"``, ``"arc"``, ``"waterbed_free_depth"`` or
        ``"boussinesq"``.
    params : dict of str to float
        Fitted parameters, units in their names (``L_mm``, ``A_mm``, ``x0_mm``).
    n_points : int
        Number of points fitted.
    n_params : int
        Number of free model parameters (the noise variance not included).
    sse_mm2 : float
        Sum of squared residuals (mm^2).
    rmse_mm : float
        Root-mean-square residual (mm).
    max_abs_residual_mm : float
        Largest absolute residual (mm).
    aicc : float
        Small-sample corrected Akaike information criterion (see
        :func:`goodness_of_fit`).
    residual_mm : numpy.ndarray
        Data minus model at each point, in input order.
    """

    model: str
    params: dict
    n_points: int
    n_params: int
    sse_mm2: float
    rmse_mm: float
    max_abs_residual_mm: float
    aicc: float
    residual_mm: np.ndarray = field(repr=False)


def in_fit_window(distance_mm, window_mm):
    """Mask of the points used in every fit: ``0 < distance <= window``.

    Parameters
    ----------
    distance_mm : array_like
        Distances from the load (mm).
    window_mm : float
        Outer edge of the fitted region (mm); ``inf`` keeps the whole profile.

    Returns
    -------
    numpy.ndarray of bool
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    return (distance_mm > 0) & (distance_mm <= window_mm)


def goodness_of_fit(residual_mm, n_params):
    """RMSE, largest absolute residual and AICc of a least-squares fit.

    The AICc assumes independent Gaussian errors of unknown variance, which
    counts as one more parameter: with ``k = n_params + 1``,
    ``AICc = n ln(SSE / n) + 2 k + 2 k (k + 1) / (n - k - 1)``.

    Parameters
    ----------
    residual_mm : array_like
        Data minus model (mm).
    n_params : int
        Number of free model parameters.

    Returns
    -------
    dict
        ``sse_mm2``, ``rmse_mm``, ``max_abs_residual_mm`` and ``aicc`` (NaN when
        there are too few points for the correction).
    """
    residual_mm = np.asarray(residual_mm, dtype=float)
    n = residual_mm.size
    sse = float(np.sum(residual_mm**2))
    k = n_params + 1
    if n - k - 1 > 0:
        with np.errstate(divide="ignore"):
            aicc = n * np.log(sse / n) + 2 * k + 2 * k * (k + 1) / (n - k - 1)
    else:
        aicc = np.nan
    return {
        "sse_mm2": sse,
        "rmse_mm": float(np.sqrt(sse / n)) if n else np.nan,
        "max_abs_residual_mm": float(np.max(np.abs(residual_mm))) if n else np.nan,
        "aicc": float(aicc),
    }


def _result(model, params, residual_mm, n_params):
    return FitResult(
        model=model,
        params=params,
        n_points=int(np.size(residual_mm)),
        n_params=n_params,
        residual_mm=np.asarray(residual_mm, dtype=float),
        **goodness_of_fit(residual_mm, n_params),
    )


def _as_points(distance_mm, deflection_mm, minimum):
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    if distance_mm.shape != deflection_mm.shape or distance_mm.ndim != 1:
        raise ValueError("distance_mm and deflection_mm must be 1-D arrays of equal length")
    if distance_mm.size < minimum:
        raise ValueError(f"at least {minimum} points are needed, got {distance_mm.size}")
    if not (np.all(np.isfinite(distance_mm)) and np.all(np.isfinite(deflection_mm))):
        raise ValueError("distances and deflections must be finite")
    if np.any(distance_mm <= 0):
        raise ValueError("distances must be > 0 (the load point itself is not fitted)")
    return distance_mm, deflection_mm


def profile_interval(sse_of_L, L_best, L_min, L_max, sse_min, n_points, chi2=CHI2_1DOF_95):
    """Profile-likelihood confidence interval of a one-parameter fit in L.

    With Gaussian errors of unknown variance, the likelihood-ratio statistic
    of a value L is ``n ln(SSE(L) / SSE_min)``; the interval holds the L where
    it stays below the chi-square quantile.  Each end is found by stepping out
    from the best fit until the statistic exceeds the quantile, then bisecting.
    An end that reaches the admissible range without crossing is reported as
    that bound (``L_min``) or as infinity (``L_max``).

    The interval assumes independent errors; where the model misfits
    systematically, neighbouring residuals are correlated and the interval is
    too narrow.

    Parameters
    ----------
    sse_of_L : callable
        Sum of squared residuals as a function of L (mm), for a 1-D array of L.
    L_best : float
        Best-fit L (mm).
    L_min, L_max : float
        Admissible range of L (mm).
    sse_min : float
        ``SSE(L_best)``.
    n_points : int
        Number of fitted points.
    chi2 : float, optional
        Chi-square quantile (one degree of freedom); the default gives 95 %.

    Returns
    -------
    tuple of float
        ``(L_low_mm, L_high_mm)``.
    """
    if not np.isfinite(L_best) or n_points < 2:
        return (np.nan, np.nan)
    threshold = max(sse_min, np.finfo(float).tiny) * np.exp(chi2 / n_points)

    def too_far(L):
        return sse_of_L(np.array([L]))[0] > threshold

    def log_ratio(L):
        # an exact quartic can round to 0 or a hair below at a perfect fit
        return np.log(max(sse_of_L(np.array([L]))[0], np.finfo(float).tiny) / threshold)

    ends = []
    for bound, step in ((L_min, 1 / 1.05), (L_max, 1.05)):
        inside, outside = L_best, L_best
        while not too_far(outside):
            inside = outside
            if outside == bound:
                outside = None
                break
            outside = min(outside * step, bound) if step > 1 else max(outside * step, bound)
        if outside is None:
            ends.append(bound if step < 1 else np.inf)
            continue
        if inside == outside:  # the best fit itself is past the threshold (no noise)
            ends.append(inside)
            continue
        ends.append(_crossing(log_ratio, inside, outside))
    return (float(ends[0]), float(ends[1]))


def _crossing(g, inside, outside, rtol=1e-10):
    """Root of ``g`` between ``inside`` (g <= 0) and ``outside`` (g > 0).

    The Illinois variant of regula falsi: superlinear on smooth functions and,
    unlike Newton's method, never leaves the bracket.
    """
    a, b = inside, outside
    fa, fb = g(a), g(b)
    last = 0
    for _ in range(100):
        c = (a * fb - b * fa) / (fb - fa)
        fc = g(c)
        if fc > 0:
            b, fb = c, fc
            if last == -1:
                fa /= 2.0
            last = -1
        else:
            a, fa = c, fc
            if last == 1:
                fb /= 2.0
            last = 1
        if abs(b - a) <= rtol * abs(c) or abs(fc) <= 1e-14:
            break
    return c


def fit_waterbed(distance_mm, deflection_mm, depth_mm):
    """Fit the small-slope waterbed (eq. 19) with W0 fixed: exact global least squares.

    With ``u = 1 / L`` the model ``W0 (3 u**2 x**2 - 4 u x + 1)`` is quadratic
    in ``u``, so the sum of squared residuals is a quartic in ``u``.  Its global
    minimum over ``0 <= u <= 1 / max(x)`` is at a real root of the cubic
    derivative or at an end of that interval; all candidates are compared
    exactly, so no start value or iterative optimiser is involved.  ``u = 0``
    means a flat membrane (``L`` infinite).

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}``, the
        last two the 95 % profile-likelihood interval (:func:`profile_interval`).
    """
    x, y = _as_points(distance_mm, deflection_mm, minimum=1)
    a = y - depth_mm
    b = 4.0 * depth_mm * x
    c = -3.0 * depth_mm * x**2
    # S(u) = sum (a + b u + c u^2)^2, coefficients from the highest power down
    quartic = np.array(
        [
            np.sum(c * c),
            2.0 * np.sum(b * c),
            np.sum(b * b + 2.0 * a * c),
            2.0 * np.sum(a * b),
            np.sum(a * a),
        ]
    )
    u_max = 1.0 / x.max()
    roots = np.roots(np.polyder(quartic))
    scale = max(1.0, float(np.max(np.abs(roots)))) if roots.size else 1.0
    real = roots[np.abs(roots.imag) <= 1e-9 * scale].real
    candidates = np.concatenate([[0.0, u_max], real[(real > 0) & (real < u_max)]])
    sse = np.polyval(quartic, candidates)
    u_best = float(candidates[np.argmin(sse)])
    L_mm = np.inf if u_best == 0.0 else 1.0 / u_best
    residual = y - waterbed_deflection_mm(x, depth_mm, L_mm)
    low, high = profile_interval(
        lambda L: np.polyval(quartic, 1.0 / np.asarray(L)),
        L_mm,
        x.max(),
        np.inf,
        float(np.sum(residual**2)),
        x.size,
    )
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _result("waterbed", params, residual, n_params=1)


def _arc_sse(x, y, depth_mm, L_mm):
    """Sum of squared residuals of the arc model for each L (vectorised over L)."""
    L_mm = np.atleast_1d(np.asarray(L_mm, dtype=float))
    geometry = arc_geometry(depth_mm, L_mm[:, None])
    dx = x[None, :] - geometry["centre_x_mm"]
    z = geometry["centre_z_mm"] + np.sqrt(np.maximum(geometry["radius_mm"] ** 2 - dx**2, 0.0))
    model = np.where(x[None, :] <= L_mm[:, None], -z, 0.0)
    sse = np.sum((y[None, :] - model) ** 2, axis=1)
    return np.where(geometry["is_graph"][:, 0], sse, np.inf)


def minimise_in_L(sse_of_L, L_min, L_max, n_grid=200, rtol=1e-9):
    """Minimise a least-squares objective over one length, ``L_min <= L <= L_max``.

    A dense log-spaced grid finds the basin of the global minimum; a zoom then
    refines it inside the two grid cells around the best grid point (17 evenly
    spaced values per step, keeping the two cells around the best each time)
    until the bracket is ``rtol`` wide.

    Parameters
    ----------
    sse_of_L : callable
        Objective for a 1-D array of L (mm); ``inf`` marks inadmissible values.
    L_min, L_max : float
        Search range (mm).
    n_grid : int, optional
        Number of grid points.
    rtol : float, optional
        Relative width of the final bracket.

    Returns
    -------
    float
        The minimising L (mm).

    Raises
    ------
    ValueError
        If the objective is infinite over the whole grid.
    """
    grid = np.geomspace(L_min, L_max, n_grid)
    sse = sse_of_L(grid)
    if not np.any(np.isfinite(sse)):
        raise ValueError(f"no admissible L between {L_min:g} and {L_max:g} mm")
    best = int(np.argmin(sse))
    lo, hi = grid[max(best - 1, 0)], grid[min(best + 1, n_grid - 1)]
    while hi - lo > rtol * hi:
        points = np.linspace(lo, hi, 17)
        k = int(np.argmin(sse_of_L(points)))
        lo, hi = points[max(k - 1, 0)], points[min(k + 1, 16)]
    candidates = np.array([grid[best], 0.5 * (lo + hi)])
    return float(candidates[np.argmin(sse_of_L(candidates))])


def _fit_L_by_search(model, x, y, sse_of_L, deflection, L_lo):
    """One-parameter fit in L by :func:`minimise_in_L` over ``[L_lo, L_SEARCH_SPAN max(x)]``.

    Shared by the fixed-depth fits that have no closed form (exact arc,
    shifted parabola): the minimum, the fitted curve's residuals and the
    profile-likelihood interval.
    """
    L_hi = L_SEARCH_SPAN * x.max()
    try:
        L_mm = minimise_in_L(sse_of_L, L_lo, L_hi)
    except ValueError as error:
        raise ValueError(f"no valid {model} curve: {error}") from None
    residual = y - deflection(x, L_mm)
    low, high = profile_interval(sse_of_L, L_mm, L_lo, L_hi, float(np.sum(residual**2)), x.size)
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _result(model, params, residual, n_params=1)


def fit_arc(distance_mm, deflection_mm, depth_mm):
    """Fit the exact circular-arc waterbed with W0 fixed and L free.

    The one-dimensional least-squares problem in ``L`` over
    ``[max(x), 1000 max(x)]`` is solved by :func:`minimise_in_L`.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}`` with
        the 95 % profile-likelihood interval (:func:`profile_interval`).
    """
    x, y = _as_points(distance_mm, deflection_mm, minimum=1)
    return _fit_L_by_search(
        "arc",
        x,
        y,
        lambda L: _arc_sse(x, y, depth_mm, L),
        lambda x, L: arc_deflection_mm(x, depth_mm, L),
        x.max(),
    )


def _shifted_sse(x, y, depth_mm, L_mm):
    """Sum of squared residuals of the shifted parabola for each L (vectorised over L)."""
    L_mm = np.atleast_1d(np.asarray(L_mm, dtype=float))
    model = shifted_deflection_mm(x[None, :], depth_mm, L_mm[:, None])
    sse = np.sum((y[None, :] - model) ** 2, axis=1)
    return np.where(np.isfinite(sse), sse, np.inf)


def fit_shifted(distance_mm, deflection_mm, depth_mm):
    """Fit the small-slope waterbed in measured coordinates, W0 fixed and L free.

    The model is eq. 19's ``W(X)`` at ``x = X + U(X)`` (eq. 20), i.e.
    :func:`lineload.models.shifted_deflection_mm`.  It is defined for
    ``L > sqrt(6) W0`` only (where ``x(X)`` is one-to-one), so the search runs
    over ``[max(max(x), sqrt(6) W0 (1 + 1e-9)), 1000 max(x)]`` with
    :func:`minimise_in_L`.  A fit that ends on the lower bound means the data
    want a membrane too narrow for the small-slope solution.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}`` with
        the 95 % profile-likelihood interval (:func:`profile_interval`).
    """
    x, y = _as_points(distance_mm, deflection_mm, minimum=1)
    fold_mm = abs(float(depth_mm)) / MAX_ONE_TO_ONE_RATIO * (1.0 + 1e-9)
    return _fit_L_by_search(
        "shifted",
        x,
        y,
        lambda L: _shifted_sse(x, y, depth_mm, L),
        lambda x, L: shifted_deflection_mm(x, depth_mm, L),
        max(x.max(), fold_mm),
    )


def fit_waterbed_free_depth(distance_mm, deflection_mm):
    """Fit the small-slope waterbed with both W0 and L free.

    For a given L the model ``W0 g(x)``, ``g = 3 s**2 - 4 s + 1``, is linear in
    W0, whose best value is ``sum(y g) / sum(g**2)``; what remains is a
    one-dimensional problem in L (:func:`minimise_in_L`, ``L >= max(x)``).
    The interval on L profiles W0 out.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two.

    Returns
    -------
    FitResult
        ``params = {"L_mm", "L_ci_low_mm", "L_ci_high_mm", "W0_mm"}``.
    """
    x, y = _as_points(distance_mm, deflection_mm, minimum=2)
    L_lo, L_hi = x.max(), L_SEARCH_SPAN * x.max()

    def shape_and_depth(L):
        s = x[None, :] / np.atleast_1d(np.asarray(L, dtype=float))[:, None]
        g = 3.0 * s**2 - 4.0 * s + 1.0
        return g, np.sum(y * g, axis=1) / np.sum(g * g, axis=1)

    def sse_of_L(L):
        g, W0 = shape_and_depth(L)
        return np.sum((y[None, :] - W0[:, None] * g) ** 2, axis=1)

    L_mm = minimise_in_L(sse_of_L, L_lo, L_hi)
    W0_mm = float(shape_and_depth(L_mm)[1][0])
    residual = y - waterbed_deflection_mm(x, W0_mm, L_mm)
    low, high = profile_interval(sse_of_L, L_mm, L_lo, L_hi, float(np.sum(residual**2)), x.size)
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high, "W0_mm": W0_mm}
    return _result("waterbed_free_depth", params, residual, n_params=2)


def fit_boussinesq(distance_mm, deflection_mm):
    """Fit the modified Boussinesq profile ``A ln(x0 / x)``: linear least squares.

    The model is a straight line in ``ln x``: ``w = A ln x0 - A ln x``, so the
    fit is an exact linear regression.  ``x0`` is reported as NaN when the
    slope has the wrong sign (``A <= 0``), where the form has no zero crossing.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two distinct.

    Returns
    -------
    FitResult
        ``params = {"A_mm": A, "x0_mm": x0}``.
    """
    x, y = _as_points(distance_mm, deflection_mm, minimum=2)
    log_x = np.log(x)
    design = np.column_stack([np.ones_like(log_x), -log_x])
    (intercept, A_mm), *_ = np.linalg.lstsq(design, y, rcond=None)
    residual = y - design @ np.array([intercept, A_mm])
    x0_mm = float(np.exp(intercept / A_mm)) if A_mm > 0 else np.nan
    if A_mm > 0:
        residual = y - boussinesq_deflection_mm(x, A_mm, x0_mm)
    return _result("boussinesq", {"A_mm": float(A_mm), "x0_mm": x0_mm}, residual, n_params=2)


#: Columns of the fit table, in order (one row per subject and depth).
FIT_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "fit_window_mm",
    "n_points",
    "max_distance_mm",
    "waterbed_L_mm",
    "waterbed_L_ci_low_mm",
    "waterbed_L_ci_high_mm",
    "waterbed_rmse_mm",
    "waterbed_max_abs_residual_mm",
    "waterbed_aicc",
    "shifted_L_mm",
    "shifted_L_ci_low_mm",
    "shifted_L_ci_high_mm",
    "shifted_rmse_mm",
    "shifted_max_abs_residual_mm",
    "shifted_aicc",
    "arc_L_mm",
    "arc_L_ci_low_mm",
    "arc_L_ci_high_mm",
    "arc_rmse_mm",
    "arc_max_abs_residual_mm",
    "arc_aicc",
    "boussinesq_A_mm",
    "boussinesq_x0_mm",
    "boussinesq_rmse_mm",
    "boussinesq_max_abs_residual_mm",
    "boussinesq_aicc",
]


def fit_trial(distance_mm, deflection_mm, depth_mm, window_mm):
    """Fit every model to one trial on the same points.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        The averaged profile of one subject at one depth (mm).
    depth_mm : float
        Indentation depth (mm), W0 of both waterbed fits.
    window_mm : float
        Points with ``0 < distance <= window_mm`` are fitted.

    Returns
    -------
    dict
        The model columns of :data:`FIT_COLUMNS` (all but ``subject`` and
        ``species``).  A model that needs more points than the window holds
        gets NaN.
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    keep = in_fit_window(distance_mm, window_mm) & np.isfinite(deflection_mm)
    x, y = distance_mm[keep], deflection_mm[keep]
    row = {
        "depth_mm": float(depth_mm),
        "fit_window_mm": float(window_mm),
        "n_points": int(x.size),
        "max_distance_mm": float(x.max()) if x.size else np.nan,
    }
    fits = {
        "waterbed": (lambda: fit_waterbed(x, y, depth_mm), ["L_mm", "L_ci_low_mm", "L_ci_high_mm"]),
        "shifted": (lambda: fit_shifted(x, y, depth_mm), ["L_mm", "L_ci_low_mm", "L_ci_high_mm"]),
        "arc": (lambda: fit_arc(x, y, depth_mm), ["L_mm", "L_ci_low_mm", "L_ci_high_mm"]),
        "boussinesq": (lambda: fit_boussinesq(x, y), ["A_mm", "x0_mm"]),
    }
    for model, (fit, names) in fits.items():
        try:
            result = fit()
        except ValueError:
            result = None
        for name in names:
            row[f"{model}_{name}"] = result.params[name] if result else np.nan
        for measure in ("rmse_mm", "max_abs_residual_mm", "aicc"):
            row[f"{model}_{measure}"] = getattr(result, measure) if result else np.nan
    return row
