"""Bounded one-dimensional minimisation and root finding for many problems at once.

The fits of :mod:`lineload.fitting.batch` each reduce to a least-squares objective in one
length, the membrane half-width L.  The routines here solve thousands of such
problems together (one row per problem), in the manner of :mod:`scipy.optimize`
but vectorised across problems, which is what makes fitting 10,000 subjects cheap.

Every routine takes the objective as a function ``objective(values, rows)``:
``values`` is an array of shape ``(R, K)`` of trial values for the problems
``rows`` (shape ``(R,)``, indices into the batch), and it returns an array of the
same shape; ``inf`` marks an inadmissible value.

Functions
---------
minimize_bounded
    Global minimum over ``[low, high]``: a log-spaced grid, then Brent's method.
find_roots
    Illinois regula falsi between brackets.
likelihood_interval
    Ends of a profile-likelihood interval of a one-parameter least-squares fit.
solution_tolerance
    How far apart two correct evaluations of the same problem may place the
    minimiser and the interval's ends (rounding of the objective).

Accuracy
--------
The minimiser is found to a bracket of relative width ``rtol``; the ends of an
interval to ``rtol_root``.  Below that, the answers are limited by the rounding of
the objective itself: a minimum is flat, so an objective known to ``dS`` fixes its
minimiser only to about ``h sqrt(dS / (S_threshold - S_min))``, where ``h`` is the
interval's half-width (:func:`solution_tolerance`).  Two code paths that round the
objective differently (another batch, another CPU's vector unit) agree to that,
not to the last bit.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "CHI2_1DOF_95",
    "find_roots",
    "likelihood_interval",
    "minimize_bounded",
    "solution_tolerance",
]

#: 95 % quantile of the chi-square distribution with one degree of freedom
#: (``scipy.stats.chi2.ppf(0.95, 1)``; a test checks the value).
CHI2_1DOF_95 = 3.841458820694124

_TINY = np.finfo(float).tiny


def _grid_values(objective, grid, lower_bound, per_round=4):
    """The objective on each problem's grid, or enough of it to find its smallest value.

    With ``lower_bound(grid, rows)``, a valid lower bound of the objective at each
    point, the points are visited in order of increasing bound, ``per_round`` at a
    time, until the next bound exceeds the best value found (with a relative margin
    of 1e-9 for rounding): the points left are provably worse, and are given as inf.
    """
    count, n_grid = grid.shape
    rows = np.arange(count)
    if lower_bound is None:
        return objective(grid, rows)
    bound = lower_bound(grid, rows)
    bound = np.where(np.isnan(bound), 0.0, bound)
    order = np.argsort(bound, axis=1, kind="stable")
    values = np.full(grid.shape, np.inf)
    best = np.full(count, np.inf)
    spared = np.ones(grid.shape, dtype=bool)
    steps = np.arange(per_round)
    first = np.zeros(count, dtype=np.intp)
    going = rows
    while going.size:
        column = first[going, None] + steps
        inside = column < n_grid
        point = order[going[:, None], np.minimum(column, n_grid - 1)]
        with np.errstate(invalid="ignore"):
            wanted = inside & ~(bound[going[:, None], point] * (1.0 - 1e-9) > best[going, None])
        r, j = np.nonzero(wanted)
        r, c = going[r], point[r, j]
        values[r, c] = objective(grid[r, c][:, None], r)[:, 0]
        spared[r, c] = False
        best[going] = np.min(np.where(spared[going], np.inf, values[going]), axis=1)
        first[going] += per_round
        going = going[wanted[:, -1]]  # the points after a refused one have larger bounds
    return values


_GOLDEN = 0.3819660112501051  # (3 - sqrt(5)) / 2


def _brent(objective, rows, a, b, x, fx, rtol, fa=None, fb=None, max_steps=200):
    """Brent's minimisation inside brackets ``[a, b]`` from their best points ``x``, many at once.

    Golden-section steps safeguard parabolic interpolation through the three best
    points (Brent 1973, ch. 5; the algorithm of :func:`scipy.optimize.fminbound`),
    one evaluation per problem and step; each problem stops when its bracket is
    ``rtol |x|`` wide around ``x``.  ``x`` must be no worse than the objective
    anywhere else known in the bracket; given the values ``fa`` and ``fb`` at the
    bracket's ends, the first step is a parabola through the three points.  Returns
    the best point and its value.
    """
    a, b, x, fx = (np.array(v, dtype=float) for v in (a, b, x, fx))
    w, v, fw, fv = x.copy(), x.copy(), fx.copy(), fx.copy()
    d, e = np.zeros_like(x), np.zeros_like(x)
    if fa is not None and fb is not None:
        w, v, fw, fv = a.copy(), b.copy(), np.array(fa, dtype=float), np.array(fb, dtype=float)
        e = b - a  # lets the first step be parabolic
    active = np.arange(x.size)
    for _ in range(max_steps):
        xm = 0.5 * (a[active] + b[active])
        xa = x[active]
        tol1 = 0.25 * rtol * np.abs(xa) + _TINY
        tol2 = 2.0 * tol1
        going = np.abs(xa - xm) > tol2 - 0.5 * (b[active] - a[active])
        active, xm, xa, tol1, tol2 = (u[going] for u in (active, xm, xa, tol1, tol2))
        if not active.size:
            break
        aa, bb, ww, vv = a[active], b[active], w[active], v[active]
        fxa, fwa, fva = fx[active], fw[active], fv[active]
        ea, da = e[active], d[active]
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            r = (xa - ww) * (fxa - fva)
            q = (xa - vv) * (fxa - fwa)
            p = (xa - vv) * q - (xa - ww) * r
            q = 2.0 * (q - r)
            p = np.where(q > 0.0, -p, p)
            q = np.abs(q)
            parabolic = (
                (np.abs(ea) > tol1)
                & (np.abs(p) < np.abs(0.5 * q * ea))
                & (p > q * (aa - xa))
                & (p < q * (bb - xa))
            )
            step = p / q
        u = xa + step
        near_end = (u - aa < tol2) | (bb - u < tol2)
        step = np.where(near_end, np.where(xm >= xa, tol1, -tol1), step)
        golden_e = np.where(xa >= xm, aa - xa, bb - xa)
        new_e = np.where(parabolic, da, golden_e)
        new_d = np.where(parabolic, step, _GOLDEN * golden_e)
        new_d = np.where(np.abs(new_d) >= tol1, new_d, np.where(new_d >= 0.0, tol1, -tol1))
        u = xa + new_d
        fu = objective(u[:, None], rows[active])[:, 0]
        fu = np.where(np.isnan(fu), np.inf, fu)
        e[active], d[active] = new_e, new_d
        better = fu <= fxa
        # the bracket: the better of x and u stays inside, the worse becomes an end
        a[active] = np.where(better, np.where(u >= xa, xa, aa), np.where(u < xa, u, aa))
        b[active] = np.where(better, np.where(u >= xa, bb, xa), np.where(u < xa, bb, u))
        # the three best points
        second = ~better & ((fu <= fwa) | (ww == xa))
        third = ~better & ~second & ((fu <= fva) | (vv == xa) | (vv == ww))
        v[active] = np.where(better | second, ww, np.where(third, u, vv))
        fv[active] = np.where(better | second, fwa, np.where(third, fu, fva))
        w[active] = np.where(better, xa, np.where(second, u, ww))
        fw[active] = np.where(better, fxa, np.where(second, fu, fwa))
        x[active] = np.where(better, u, xa)
        fx[active] = np.where(better, fu, fxa)
    return x, fx


def minimize_bounded(objective, low, high, n_grid=100, rtol=1e-9, lower_bound=None):
    """Global minimum of many one-dimensional objectives, each on ``[low, high]``.

    A log-spaced grid of ``n_grid`` points finds the basin of each problem's global
    minimum; Brent's method (:func:`_brent`: parabolic steps, golden-section steps
    where those fail) then refines it inside the two grid cells around the best grid
    point until the bracket is ``rtol`` wide, relative: one evaluation per step
    (``docs/calibration/search_grid.md`` counts them on the fits' objectives), where a
    zoom of 17 evenly spaced values per step took about 150 evaluations.  The
    problems that need more steps go on while the others stop.

    Parameters
    ----------
    objective : callable
        ``objective(values, rows)``, see the module's notes.
    low, high : numpy.ndarray
        Search range of each problem (> 0), shape ``(n,)``.
    n_grid : int, optional
        Number of grid points (100: 7.2 % apart over the fits' range of 1000).  The
        grid only has to land in the deepest basin; ``docs/calibration/search_grid.md``
        counts how often grids of 12 to 200 values miss it on profiles with noise
        added, where objectives have several minima, and a test holds the default to
        a dense grid on such objectives.
    rtol : float, optional
        Relative width of the final bracket.
    lower_bound : callable, optional
        ``lower_bound(values, rows)``, a valid lower bound of the objective, cheaper
        to evaluate: grid points it proves worse than one already seen are skipped.

    Returns
    -------
    minimiser : numpy.ndarray
        The minimising value of each problem; NaN where the grid holds no finite
        value of the objective.
    found : numpy.ndarray of bool
        Which problems have a minimiser.
    """
    low, high = np.asarray(low, dtype=float), np.asarray(high, dtype=float)
    count = low.size
    minimiser = np.full(count, np.nan)
    if count == 0:
        return minimiser, np.zeros(0, dtype=bool)
    grid = np.geomspace(low, high, n_grid, axis=-1)
    values = _grid_values(objective, grid, lower_bound)
    found = np.any(np.isfinite(values), axis=1)
    best = np.argmin(np.where(np.isnan(values), np.inf, values), axis=1)
    if found.any():
        active = np.flatnonzero(found)
        before = np.maximum(best[active] - 1, 0)
        after = np.minimum(best[active] + 1, n_grid - 1)
        minimiser[active], _ = _brent(
            objective,
            active,
            grid[active, before],
            grid[active, after],
            grid[active, best[active]],
            values[active, best[active]],
            rtol,
            # a NaN is inadmissible, as in the steps (inf)
            fa=np.where(np.isnan(values[active, before]), np.inf, values[active, before]),
            fb=np.where(np.isnan(values[active, after]), np.inf, values[active, after]),
        )
    return minimiser, found


def find_roots(g, a, b, ga, gb, rtol=1e-10, max_steps=100):
    """Roots of many functions, each bracketed: ``g <= 0`` at ``a`` and ``g > 0`` at ``b``.

    The Illinois variant of regula falsi, for all problems together (each stops on
    its own): superlinear on smooth functions and, unlike Newton's method, never
    leaves the bracket.

    Parameters
    ----------
    g : callable
        ``g(values, which)`` for a 1-D array of values of the problems ``which``
        (indices into ``a``).
    a, b : numpy.ndarray
        The brackets' ends.
    ga, gb : numpy.ndarray
        ``g`` at ``a`` and at ``b``.
    rtol : float, optional
        Stop when the bracket is narrower than ``rtol`` times the root.
    max_steps : int, optional
        Most steps taken.

    Returns
    -------
    numpy.ndarray
        The last estimate of each root.
    """
    a, b, ga, gb = (np.array(v, dtype=float) for v in (a, b, ga, gb))
    root = np.full(a.size, np.nan)
    last = np.zeros(a.size, dtype=int)
    active = np.arange(a.size)
    for _ in range(max_steps):
        if active.size == 0:
            break
        a_, b_, ga_, gb_ = a[active], b[active], ga[active], gb[active]
        with np.errstate(invalid="ignore", divide="ignore"):
            c = (a_ * gb_ - b_ * ga_) / (gb_ - ga_)
        gc = g(c, active)
        right = gc > 0
        previous = last[active]
        a[active] = np.where(right, a_, c)
        ga[active] = np.where(right, np.where(previous == -1, ga_ / 2.0, ga_), gc)
        b[active] = np.where(right, c, b_)
        gb[active] = np.where(right, gc, np.where(previous == 1, gb_ / 2.0, gb_))
        last[active] = np.where(right, -1, 1)
        root[active] = c
        done = (np.abs(b[active] - a[active]) <= rtol * np.abs(c)) | (np.abs(gc) <= 1e-14)
        active = active[~done]
    return root


def likelihood_interval(objective, best, low, high, threshold, factor=1.05):
    """Both ends of ``{v : objective(v) <= threshold}`` around a minimiser, many at once.

    Each end is found by stepping out from ``best`` by ``factor`` (a block of 4, then
    8, 16, ... steps at a time, so that a problem needing thousands of steps costs a
    few rounds only) until the objective exceeds ``threshold``, then by
    :func:`find_roots` on ``ln(objective / threshold)`` between the last value inside
    and the first outside.  An end that reaches the admissible range without
    crossing is reported as ``low``, or as infinity for ``high``.

    Parameters
    ----------
    objective : callable
        ``objective(values, rows)``, see the module's notes.
    best, low, high, threshold : numpy.ndarray
        Minimiser, admissible range and the objective's value at the interval's
        ends, by problem.  A problem whose ``best`` is not finite gets NaN ends.
    factor : float, optional
        Step-out factor (> 1).

    Returns
    -------
    tuple of numpy.ndarray
        ``(lower_end, upper_end)``.
    """
    count = best.size
    lower, upper_end = np.full(count, np.nan), np.full(count, np.nan)
    rows = np.flatnonzero(np.isfinite(best))
    if not rows.size:
        return lower, upper_end
    # one problem per end: first the lower ends of all rows, then the upper ends
    problem_rows = np.concatenate([rows, rows])
    problem_threshold = np.concatenate([threshold[rows], threshold[rows]])
    upper = np.repeat([False, True], rows.size)
    bound = np.concatenate([low[rows], high[rows]])
    step = np.where(upper, factor, 1.0 / factor)
    n_problems = problem_rows.size
    end = np.full(n_problems, np.nan)
    inside = best[problem_rows].astype(float)
    outside = np.full(n_problems, np.nan)
    value_inside = np.full(n_problems, np.nan)
    value_outside = np.full(n_problems, np.nan)
    crossed = np.zeros(n_problems, dtype=bool)
    following = inside.copy()  # the next value to test
    pending = np.arange(n_problems)
    length = 4
    while pending.size:
        sequence = np.empty((pending.size, length))
        sequence[:, 0] = following[pending]
        sequence[:, 1:] = step[pending, None]
        with np.errstate(over="ignore"):
            sequence = np.cumprod(sequence, axis=1)
        limit = bound[pending, None]
        sequence[:, 1:] = np.where(
            upper[pending, None],
            np.minimum(sequence[:, 1:], limit),
            np.maximum(sequence[:, 1:], limit),
        )
        values = objective(sequence, problem_rows[pending])
        too_far = values > problem_threshold[pending, None]
        stop = too_far | (sequence == limit)
        stops = stop.any(axis=1)
        first = np.argmax(stop, axis=1)
        # problems that crossed, or reached their bound, in this block
        j = np.flatnonzero(stops)
        done, f = pending[j], first[j]
        crossed[done] = too_far[j, f]
        earlier = f > 0
        inside[done[earlier]] = sequence[j[earlier], f[earlier] - 1]
        value_inside[done[earlier]] = values[j[earlier], f[earlier] - 1]
        outside[done] = sequence[j, f]
        value_outside[done] = values[j, f]
        at_bound = done[~crossed[done]]
        end[at_bound] = np.where(upper[at_bound], np.inf, bound[at_bound])
        # the others go on from their last value
        j = np.flatnonzero(~stops)
        going = pending[j]
        inside[going] = sequence[j, -1]
        value_inside[going] = values[j, -1]
        with np.errstate(over="ignore"):
            following[going] = sequence[j, -1] * step[going]
        following[going] = np.where(
            upper[going],
            np.minimum(following[going], bound[going]),
            np.maximum(following[going], bound[going]),
        )
        pending = going
        length = min(2 * length, 4096)
    same = crossed & (inside == outside)  # the minimum itself is past the threshold
    end[same] = inside[same]
    bracketed = np.flatnonzero(crossed & ~same)
    if bracketed.size:

        def log_ratio(values, which):
            # an objective can round to 0 or a hair below at a perfect fit
            return np.log(np.maximum(values, _TINY) / problem_threshold[bracketed[which]])

        end[bracketed] = find_roots(
            lambda v, which: log_ratio(
                objective(v[:, None], problem_rows[bracketed[which]])[:, 0], which
            ),
            inside[bracketed],
            outside[bracketed],
            log_ratio(value_inside[bracketed], slice(None)),
            log_ratio(value_outside[bracketed], slice(None)),
        )
    lower[rows] = end[: rows.size]
    upper_end[rows] = end[rows.size :]
    return lower, upper_end


def solution_tolerance(value_min, threshold, half_width, rounding):
    """How far two correct solutions of the same problem may lie apart.

    Two evaluations of one objective that round differently (another batch size,
    another CPU's vector kernels) differ by up to ``rounding`` in the objective.
    Near its minimum the objective is ``S_min + (S_threshold - S_min) (v - v*)^2 / h^2``
    to second order (``h`` the interval's half-width), so a change ``rounding`` moves
    the minimiser by up to ``h sqrt(2 rounding / (S_threshold - S_min))`` and an
    interval end, where the slope is ``2 (S_threshold - S_min) / h``, by
    ``h rounding / (S_threshold - S_min)`` (the threshold moves with ``S_min`` too).
    The search's own tolerance (``rtol`` of :func:`minimize_bounded` and
    :func:`find_roots`, relative) adds to both.

    Parameters
    ----------
    value_min, threshold : array_like
        The objective at the minimum and at the interval's ends.
    half_width : array_like
        Half-width of the interval (same units as the minimiser); where it is not
        finite (an open interval), the minimiser's size stands in.
    rounding : array_like
        A bound on the objective's rounding error (e.g. the number of terms summed
        times machine epsilon times the sum of the terms' sizes).

    Returns
    -------
    tuple of numpy.ndarray
        ``(minimiser_tolerance, end_tolerance)``, absolute, to which the search's
        relative tolerance times the value itself is still to be added.
    """
    value_min, threshold, half_width, rounding = (
        np.asarray(v, dtype=float) for v in (value_min, threshold, half_width, rounding)
    )
    rise = np.maximum(threshold - value_min, _TINY)
    ratio = np.minimum(rounding / rise, 1.0)
    minimiser = half_width * np.sqrt(2.0 * ratio)
    end = half_width * np.minimum(2.0 * ratio, 1.0)
    return minimiser, end
