"""Least-squares fit of the bending skin (:mod:`lineload.bending`) to one averaged profile.

As the paper fits its waterbed, ``W0`` is held at the indentation depth and the
shape parameters are fitted: here two, the half-width ``L`` and the bending
length ``l_b = sqrt(D / N)``.  The fit is ordinary least squares on the same
points as the other models (so that their sums of squares and AICc compare), read
at the measured position as the paper read its parabola.

Ranges
------
``L >= max(distance)``, as for the waterbed (every fitted point lies inside the
wall), up to 1000 times that; ``l_b`` within ``bending_length_bounds_mm``.  Below
about the first reading's distance a bending length is hard to see: the layer in
which the skin turns lies between the wedge and the first reading, and what is
left of it is the profile's shift by about ``4 W0 l_b / L`` (the layer's width
times the membrane's slope at the load).  A fit that ends at a bound says so
(``*_at_bound``) and its interval is one-sided: it runs to that bound.

Intervals
---------
Profile-likelihood intervals, as :mod:`lineload.fitting.intervals` gives the waterbed: for
one parameter, the other is fitted again at each value, and the interval holds
the values whose sum of squares stays within a threshold of the minimum.  Without
a covariance of the points the threshold is ``n ln(SSE / SSE_min) <= chi2`` (errors
independent, of unknown variance).  With one (``covariance_mm2``, measured apart
from the fit) it is the sandwich's: the least-squares estimate moves with the
readings by ``(J'J)^-1 J' dy``, so its covariance is ``V = (J'J)^-1 J'CJ (J'J)^-1``,
and the interval holds the values whose sum of squares exceeds the minimum by less
than ``chi2 V_jj / [(J'J)^-1]_jj``; for a model linear in its parameters that is
exactly the Wald interval with the sandwich's variance.  ``chi2`` is the 95 %
point of chi-square with one degree of freedom.
"""

from __future__ import annotations

import numpy as np

from lineload.bending import bending_deflection_mm
from lineload.fitting.goodness import FitResult, goodness_of_fit
from lineload.fitting.optimize import CHI2_1DOF_95, find_roots
from lineload.fitting.windows import in_fit_window, window_covariance
from lineload.trials import DEPTH_DECIMALS

__all__ = [
    "BENDING_COLUMNS",
    "BENDING_LENGTH_BOUNDS_MM",
    "fit_bending",
    "fit_bending_trials",
    "with_bending",
]

#: Default range of the bending length searched (mm).  The lower end stands for the
#: paper's membrane: there the profile lies within ``4 W0 l_b / L`` (below 0.1 um at
#: these depths and widths) of the parabola, so the waterbed is, to that rounding, a
#: special case and the bending fit's sum of squares never exceeds it.  The upper end
#: is several times the fit window.
BENDING_LENGTH_BOUNDS_MM = (1e-4, 10.0)

#: Largest L searched, as a multiple of the smallest (the farthest point fitted).
_L_SPAN = 1000.0

#: Steps of the profile's grid, in log units of the profiled parameter.
_GRID = 48

#: Points of the grid the fit starts from, in ``ln L`` (over a factor of 1000: steps of
#: 0.07) and ``ln l_b`` (over 1e-4 to 10 mm: steps of 0.5).
_START_GRID = (96, 24)

#: Most steps out from the minimum to an interval's end (0.01 doubling: the last is
#: 0.01 * 2**39, past any range's end).
_MAX_STEPS_OUT = 40

#: Steps out taken first (to 0.15 in log units: most ends lie within); the rest only
#: where no end was found among them.
_FIRST_STEPS = 4

#: Relative width at which an end's bracket stops (log units): far below what the
#: tables print.
_ROOT_RTOL = 1e-10


class _Problem:
    """Sum of squares of one trial in log parameters ``(ln L, ln l_b)``."""

    def __init__(self, x_mm, y_mm, depth_mm, wall, bounds_mm):
        self.x, self.y, self.depth, self.wall = x_mm, y_mm, depth_mm, wall
        self.low = np.log([bounds_mm[0][0], bounds_mm[1][0]])
        self.high = np.log([bounds_mm[0][1], bounds_mm[1][1]])

    def curve(self, theta):
        L_mm, lb_mm = np.exp(theta)
        return bending_deflection_mm(self.x, self.depth, L_mm, lb_mm, self.wall)

    def residual(self, theta):
        return self.y - self.curve(theta)

    def sse(self, theta):
        return float(np.sum(self.residual(theta) ** 2))

    def sse_many(self, log_L, log_lb):
        """Sums of squares for arrays of ``ln L`` and ``ln l_b`` (broadcast), at once."""
        log_L, log_lb = np.broadcast_arrays(np.asarray(log_L), np.asarray(log_lb))
        curves = bending_deflection_mm(
            self.x, self.depth, np.exp(log_L)[..., None], np.exp(log_lb)[..., None], self.wall
        )
        return np.sum((self.y - curves) ** 2, axis=-1)

    def log_jacobian(self, theta):
        """d curve / d (ln L, ln l_b), in mm, by central differences (one evaluation)."""
        step = 1e-6
        shifts = np.array([[step, 0.0], [-step, 0.0], [0.0, step], [0.0, -step]])
        points = theta[None, :] + shifts
        curves = bending_deflection_mm(
            self.x, self.depth, np.exp(points[:, :1]), np.exp(points[:, 1:]), self.wall
        )
        return np.column_stack(
            [(curves[0] - curves[1]) / (2 * step), (curves[2] - curves[3]) / (2 * step)]
        )

    def best_other(self, j, values):
        """Sums of squares minimised over the other parameter, with ``theta_j`` at each value.

        For each value: a grid over the other parameter's whole range, a finer one
        around its best point, then the vertex of the parabola through the best three:
        the minimum's value is what matters, and its error is second order in the
        position's.  Every value is done at once (one evaluation of the curves per
        stage), which is what makes the profile intervals cheap.

        Parameters
        ----------
        j : {0, 1}
            The parameter held: 0 for ``ln L``, 1 for ``ln l_b``.
        values : array_like
            Its values (log units), 1-D.

        Returns
        -------
        numpy.ndarray
            The least sum of squares at each value.
        """
        values = np.atleast_1d(np.asarray(values, dtype=float))
        other = 1 - j
        rows = np.arange(values.size)

        def sse(held, free):  # held (m, 1), free (m, k) -> (m, k)
            pair = [None, None]
            pair[j], pair[other] = held, free
            return self.sse_many(*pair)

        held = values[:, None]
        grid = np.linspace(self.low[other], self.high[other], _GRID)
        i = np.argmin(sse(held, grid[None, :]), axis=1)
        share = np.linspace(0.0, 1.0, _GRID // 2 + 1)
        start, stop = grid[np.maximum(i - 1, 0)], grid[np.minimum(i + 1, _GRID - 1)]
        fine = start[:, None] + (stop - start)[:, None] * share[None, :]
        fine_values = sse(held, fine)
        k = np.argmin(fine_values, axis=1)
        best = fine_values[rows, k]
        interior = (k > 0) & (k < share.size - 1)
        kk = np.clip(k, 1, share.size - 2)
        f0, f1, f2 = (fine_values[rows, kk + d] for d in (-1, 0, 1))
        curvature = f0 - 2 * f1 + f2
        use = interior & (curvature > 0)
        if np.any(use):
            step = fine[use, 1] - fine[use, 0]
            vertex = fine[use, kk[use]] + 0.5 * step * (f0 - f2)[use] / curvature[use]
            at_vertex = sse(held[use], vertex[:, None])[:, 0]
            best[use] = np.minimum(best[use], at_vertex)
        return best


def _minimum(problem, start_grid=_START_GRID):
    """Global least squares: the best of a grid over both parameters, then polished.

    The objective may have more than one valley (a narrow membrane with a stiff skin
    against a wide one with a soft skin), so the start is the best point of a grid
    over the whole range (``start_grid`` points in ``ln L`` and ``ln l_b``), not a
    guess; :func:`_polish` then finds the valley's floor.  A test checks that a grid
    twice as fine each way ends at the same minimum on profiles of several shapes.
    """
    log_L = np.linspace(problem.low[0], problem.high[0], start_grid[0])
    log_lb = np.linspace(problem.low[1], problem.high[1], start_grid[1])
    values = problem.sse_many(log_L[:, None], log_lb[None, :])
    i, k = np.unravel_index(np.argmin(values), values.shape)
    start = np.array([log_L[i], log_lb[k]])
    found = _polish(problem, start)
    return found if problem.sse(found) <= values[i, k] else start


def _polish(problem, theta, max_steps=200):
    """Levenberg-Marquardt in ``(ln L, ln l_b)`` within the ranges, from ``theta``.

    Two parameters, a residual of a few tens of points: each step solves the damped
    2 x 2 normal equations on the parameters free to move (one that sits at an end of
    its range with the gradient pushing it out is held there), and a step that does
    not lower the sum of squares raises the damping tenfold.  It stops when a step
    changes no parameter by more than 1e-13 (log units) or lowers the sum of squares
    by less than 1e-15 of itself.  This replaces ``scipy.optimize.least_squares``,
    whose import alone (about 0.25 s of CPU) cost each bending job more than its
    fits; the tests hold the two to the same minimum.
    """
    theta = np.clip(np.asarray(theta, dtype=float), problem.low, problem.high)
    residual = problem.residual(theta)
    value = float(residual @ residual)
    damping = 1e-3
    for _ in range(max_steps):
        J = problem.log_jacobian(theta)  # d curve / d theta = - d residual / d theta
        gradient = -J.T @ residual  # half the gradient of the sum of squares
        held = ((theta <= problem.low) & (gradient > 0)) | (
            (theta >= problem.high) & (gradient < 0)
        )
        free = ~held
        if not free.any():
            break
        Jf = J[:, free]
        normal = Jf.T @ Jf
        improved = False
        while damping < 1e12:
            system = normal + damping * np.diag(np.diag(normal))
            try:
                step = np.zeros(2)
                step[free] = np.linalg.solve(system, -gradient[free])
            except np.linalg.LinAlgError:
                damping *= 10.0
                continue
            trial = np.clip(theta + step, problem.low, problem.high)
            trial_residual = problem.residual(trial)
            trial_value = float(trial_residual @ trial_residual)
            if trial_value < value:
                moved = np.max(np.abs(trial - theta))
                gain = value - trial_value
                theta, residual, value = trial, trial_residual, trial_value
                damping = max(damping / 10.0, 1e-12)
                improved = True
                break
            damping *= 10.0
        if not improved or moved <= 1e-13 or gain <= 1e-15 * value:
            break
    return theta


def _threshold(problem, theta, j, covariance_mm2):
    """How far above its minimum the sum of squares may rise inside the interval."""
    sse_min = problem.sse(theta)
    n = problem.x.size
    if covariance_mm2 is None:
        return sse_min * np.expm1(CHI2_1DOF_95 / n)
    # in log parameters: the ratio below does not depend on the parameters' scales
    jac = problem.log_jacobian(theta)
    try:
        inverse = np.linalg.inv(jac.T @ jac)
    except np.linalg.LinAlgError:
        return np.inf
    sandwich = inverse @ jac.T @ np.asarray(covariance_mm2) @ jac @ inverse
    return CHI2_1DOF_95 * sandwich[j, j] / inverse[j, j]


def _profile_interval(problem, theta, j, covariance_mm2):
    """Ends of the profile interval of parameter ``j`` (log units) and whether each is a bound.

    Each end is stepped out to from the minimum by steps doubling from 0.01 (the
    first four evaluated at once, then the rest to the range's end) until the profiled
    sum of squares crosses its limit, then found between the last step inside and the first outside
    by :func:`lineload.fitting.optimize.find_roots`, both ends together.  An end that
    reaches the parameter's range without crossing is that bound.
    """
    sse_min = problem.sse(theta)
    limit = sse_min + _threshold(problem, theta, j, covariance_mm2)
    bounds = (problem.low[j], problem.high[j])
    if not np.isfinite(limit):
        return bounds, (True, True)
    # the grid's minimum over the other parameter may lie a rounding above SSE_min: no
    # interval then (a noiseless profile), rather than a bracket without a sign change
    centre = problem.best_other(j, theta[j])[0] - limit
    if centre >= 0:
        return (theta[j], theta[j]), (False, False)
    offsets = 0.01 * (2.0 ** np.arange(_MAX_STEPS_OUT) - 1.0)[1:]
    ends, at_bound, inside, outside, inner_excess, outer_excess = [], [], [], [], [], []
    for direction, bound in zip((-1.0, 1.0), bounds, strict=True):
        steps = theta[j] + direction * offsets
        steps = steps[direction * (steps - bound) < 0]  # short of the bound ...
        steps = np.append(steps, bound)  # ... which is the last step
        # the first few steps, then the rest if the end lies farther out
        excess = problem.best_other(j, steps[:_FIRST_STEPS]) - limit
        if not np.any(excess > 0) and steps.size > _FIRST_STEPS:
            rest = problem.best_other(j, steps[_FIRST_STEPS:]) - limit
            excess = np.concatenate([excess, rest])
        crossed = np.flatnonzero(excess > 0)
        if crossed.size == 0:
            ends.append(bound)
            at_bound.append(True)
            continue
        first = crossed[0]
        ends.append(np.nan)
        at_bound.append(False)
        inside.append(theta[j] if first == 0 else steps[first - 1])
        inner_excess.append(centre if first == 0 else excess[first - 1])
        outside.append(steps[first])
        outer_excess.append(excess[first])
    open_ends = [k for k, end in enumerate(ends) if np.isnan(end)]
    if open_ends:
        inside, outside = np.array(inside), np.array(outside)
        roots = find_roots(
            lambda values, which: problem.best_other(j, values) - limit,
            inside,
            outside,
            np.array(inner_excess),
            np.array(outer_excess),
            rtol=_ROOT_RTOL,
        )
        for k, root in zip(open_ends, roots, strict=True):
            ends[k] = float(root)
    return tuple(ends), tuple(at_bound)


def fit_bending(
    distance_mm,
    deflection_mm,
    depth_mm,
    covariance_mm2=None,
    wall="clamped",
    bending_length_bounds_mm=BENDING_LENGTH_BOUNDS_MM,
):
    """Fit ``L`` and ``l_b`` of the bending skin with ``W0`` held at the depth.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2), measured apart from the fit: the
        intervals honour it (the fit itself stays least squares).
    wall : {"clamped", "pinned"}
        The wall condition (:mod:`lineload.bending`).
    bending_length_bounds_mm : (float, float)
        Range of ``l_b`` searched (mm).

    Returns
    -------
    FitResult
        ``model = "bending"``; ``params``: ``L_mm``, ``bending_length_mm``, each
        with ``*_ci_low_mm`` and ``*_ci_high_mm`` (95 %), and ``L_at_bound`` /
        ``bending_length_at_bound`` (1.0 where the estimate lies at an end of its
        range, else 0.0).
    """
    x = np.asarray(distance_mm, dtype=float)
    y = np.asarray(deflection_mm, dtype=float)
    if x.shape != y.shape or x.ndim != 1 or x.size < 4:
        raise ValueError("need 1-D distance_mm and deflection_mm of equal length, >= 4 points")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y)) and np.all(x > 0)):
        raise ValueError("distances must be finite and > 0, deflections finite")
    L_min_mm = float(x.max())
    problem = _Problem(
        x, y, float(depth_mm), wall, ((L_min_mm, _L_SPAN * L_min_mm), bending_length_bounds_mm)
    )
    theta = _minimum(problem)
    params = {}
    names = ("L", "bending_length")
    for j, name in enumerate(names):
        (low, high), _ = _profile_interval(problem, theta, j, covariance_mm2)
        at_bound = np.isclose(theta[j], problem.low[j], atol=1e-6) or np.isclose(
            theta[j], problem.high[j], atol=1e-6
        )
        params[f"{name}_mm"] = float(np.exp(theta[j]))
        params[f"{name}_ci_low_mm"] = float(np.exp(min(low, theta[j])))
        params[f"{name}_ci_high_mm"] = float(np.exp(max(high, theta[j])))
        params[f"{name}_at_bound"] = float(at_bound)
    residual = problem.residual(theta)
    measures = goodness_of_fit(residual, n_params=2)
    chi2 = np.nan
    if covariance_mm2 is not None:
        chi2 = float(residual @ np.linalg.solve(np.asarray(covariance_mm2), residual))
    return FitResult(
        model="bending",
        params=params,
        n_points=int(x.size),
        n_params=2,
        residual_mm=residual,
        chi2=chi2,
        **measures,
    )


#: Columns of the bending fits' table, one row per trial (units in the names; the
#: flags are 1 where the estimate lies at an end of its range).
BENDING_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "fit_window_mm",
    "wall",
    "n_points",
    "bending_L_mm",
    "bending_L_ci_low_mm",
    "bending_L_ci_high_mm",
    "bending_L_at_bound",
    "bending_length_mm",
    "bending_length_ci_low_mm",
    "bending_length_ci_high_mm",
    "bending_length_at_bound",
    "bending_sse_mm2",
    "bending_rmse_mm",
    "bending_max_abs_residual_mm",
    "bending_aicc",
]


def fit_bending_trials(
    distance_mm, deflection_mm, depth_mm, window_mm, noise=None, n_sides=None, wall="clamped"
):
    """Fit the bending skin to many trials, each on its points inside the fit window.

    The points are those every other model is fitted to (``0 < distance <= window``,
    finite deflection), so sums of squares and AICc compare across the tables.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm).
    depth_mm : sequence of float
        Indentation depth of each trial (mm), held as W0.
    window_mm : float
        Outer edge of the fitted region (mm).
    noise : sequence of lineload.noise.NoiseModel, optional
        One per trial: the intervals honour each trial's covariance.
    n_sides : sequence of array_like, optional
        Sides read at each point (with ``noise``; 2 where not given).
    wall : {"clamped", "pinned"}

    Returns
    -------
    list of dict
        One row per trial with the columns of :data:`BENDING_COLUMNS` but ``subject``
        and ``species``; NaN where a trial has fewer than four points.
    """
    rows = []
    for k, (x, y, depth) in enumerate(zip(distance_mm, deflection_mm, depth_mm, strict=True)):
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        keep = in_fit_window(x, window_mm) & np.isfinite(y)
        row = {
            "depth_mm": float(depth),
            "fit_window_mm": float(window_mm),
            "wall": wall,
            "n_points": int(keep.sum()),
        }
        columns = [c for c in BENDING_COLUMNS if c not in row and c not in ("subject", "species")]
        if keep.sum() < 4:
            rows.append({**row, **dict.fromkeys(columns, np.nan)})
            continue
        covariance = None
        if noise is not None:
            sides = None if n_sides is None else n_sides[k]
            covariance = window_covariance(x, y, depth, window_mm, noise[k], sides)
        fit = fit_bending(x[keep], y[keep], depth, covariance, wall)
        p = fit.params
        rows.append(
            {
                **row,
                **{f"bending_{name}": p[name] for name in p if name.startswith("L_")},
                **{name: p[name] for name in p if name.startswith("bending_length")},
                "bending_sse_mm2": fit.sse_mm2,
                "bending_rmse_mm": fit.rmse_mm,
                "bending_max_abs_residual_mm": fit.max_abs_residual_mm,
                "bending_aicc": fit.aicc,
            }
        )
    return rows


def with_bending(fits, bending):
    """The fit table with the bending fits' columns beside it, row for row.

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``subject``, ``depth_mm``, ...).
    bending : pandas.DataFrame
        A table with the ``bending_*`` columns (:data:`BENDING_COLUMNS`) by subject and
        depth: the bending table, or a fit table that already carries them.

    Returns
    -------
    pandas.DataFrame
        ``fits`` in its order with the ``bending_*`` columns of the same trial (NaN for
        a trial the bending table lacks), replacing any it had.
    """
    columns = [c for c in bending.columns if c.startswith("bending_")]
    keep = fits.drop(columns=[c for c in columns if c in fits.columns])
    right = bending[["subject", "depth_mm", *columns]].copy()
    right["depth_mm"] = right["depth_mm"].astype(float).round(DEPTH_DECIMALS)
    left = keep.assign(_depth=keep["depth_mm"].astype(float).round(DEPTH_DECIMALS))
    merged = left.merge(
        right.rename(columns={"depth_mm": "_depth"}), on=["subject", "_depth"], how="left"
    )
    return merged.drop(columns="_depth").set_axis(fits.index)
