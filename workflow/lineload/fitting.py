"""Least-squares fits of the deflection models to averaged profiles.

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

Batches
-------
Every algorithm here runs on many trials at once (:func:`fit_trials`,
:func:`fit_windowed`, :func:`fit_batch`); the single-trial functions
(:func:`fit_waterbed`, :func:`fit_trial`, :func:`minimise_in_L`, ...) are the
same code with a batch of one.  The trials' points are padded to a common
length, and each step (the exact quartic of the parabola, the grid and zoom in
L, the profile-likelihood interval, the linear regression) is done for all
trials together, in lockstep where trials need different numbers of steps.  A
trial's numbers do not depend on its batch, and are those of the earlier
one-trial code to the last bit (the Boussinesq regression, now in closed form,
to about 1e-14): a sum over a trial's points is rounded as ``numpy.sum`` of
those points alone, and the iterative model solves stop per trial exactly as a
one-trial call stopped them (see ``independent_axes`` in
:mod:`lineload.models`).  Only the grid, whose best point is all that is used,
is evaluated more cheaply: to rounding noise, with an exact recheck where its
two best values nearly tie, and for the shifted parabola only where a lower
bound from eq. 19 does not prove a point worse.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from .models import (
    MAX_ONE_TO_ONE_RATIO,
    TABLE_MODELS,
    arc_deflection_mm,
    arc_geometry,
    boussinesq_deflection_mm,
    shifted_deflection_mm,
    waterbed_deflection_mm,
)

__all__ = [
    "FIT_COLUMNS",
    "MODELS",
    "BatchFits",
    "FitResult",
    "fit_arc",
    "fit_batch",
    "fit_boussinesq",
    "fit_shifted",
    "fit_trial",
    "fit_trials",
    "fit_waterbed",
    "fit_waterbed_free_depth",
    "fit_windowed",
    "goodness_of_fit",
    "in_fit_window",
    "minimise_in_L",
    "profile_interval",
    "window_points",
]

#: 95 % quantile of the chi-square distribution with one degree of freedom
#: (``scipy.stats.chi2.ppf(0.95, 1)``; a test checks the value).
CHI2_1DOF_95 = 3.841458820694124

#: Largest membrane half-width searched by the iterative fits (exact arc, and the
#: parabola with W0 free), as a multiple of the smallest admissible one. The
#: fixed-W0 parabola needs no such bound: its minimum is found exactly.
L_SEARCH_SPAN = 1000.0

#: Trials fitted together in lockstep (after sorting by number of points, so that
#: little is padded).
CHUNK_TRIALS = 1024

#: Largest number of elements of one temporary array while an objective is evaluated
#: for many trials and many L at once (2**17 doubles: 1 MiB, about the size of a core's
#: cache); larger evaluations go in blocks of trials.
BLOCK_ELEMENTS = 1 << 14

_TINY = np.finfo(float).tiny

#: The models :func:`fit_batch` knows (every key of :data:`lineload.models.MODEL_NAMES`),
#: with their parameters (in ``FitResult.params`` order), number of free parameters and
#: the fewest points each needs.
MODELS = {
    "waterbed": (("L_mm", "L_ci_low_mm", "L_ci_high_mm"), 1, 1),
    "shifted": (("L_mm", "L_ci_low_mm", "L_ci_high_mm"), 1, 1),
    "arc": (("L_mm", "L_ci_low_mm", "L_ci_high_mm"), 1, 1),
    "waterbed_free_depth": (("L_mm", "L_ci_low_mm", "L_ci_high_mm", "W0_mm"), 2, 2),
    "boussinesq": (("A_mm", "x0_mm"), 2, 2),
}

_MEASURES = ("sse_mm2", "rmse_mm", "max_abs_residual_mm", "aicc")


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
    window_mm : float or array_like
        Outer edge of the fitted region (mm); ``inf`` keeps the whole profile.

    Returns
    -------
    numpy.ndarray of bool
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    return (distance_mm > 0) & (distance_mm <= window_mm)


def _python_float(value):
    """A float for tables and params; NaN is always the ``numpy.nan`` object."""
    value = float(value)
    return np.nan if value != value else value


# --------------------------------------------------------------------------- padded points


def _padded_width(n_points):
    """Columns of a padded batch: a multiple of 8, at least 8."""
    return max(8, -(-int(n_points) // 8) * 8)


def _row_sums(values, n_points):
    """Sum over the last axis of the first ``n_points[row]`` entries of each row.

    Rounded exactly as ``numpy.sum`` of those entries alone would round them (the
    same pairwise summation over the same count, in C order), so that neither
    padding nor memory layout changes anything: one call per run of rows with equal
    counts (rows come sorted by count).
    """
    n_points = np.asarray(n_points)
    # numpy sums pairwise along an axis only when that axis is contiguous in memory
    values = np.ascontiguousarray(values)
    if n_points.size == 0 or np.all(n_points == n_points[0]):
        count = n_points[0] if n_points.size else 0
        return np.sum(values[..., :count], axis=-1)
    bounds = np.concatenate([[0], np.flatnonzero(np.diff(n_points)) + 1, [n_points.size]])
    total = np.empty(values.shape[:-1])
    for start, stop in itertools.pairwise(bounds):
        total[start:stop] = np.sum(values[start:stop, ..., : n_points[start]], axis=-1)
    return total


class _Trials:
    """Points of many trials padded to a common width (a multiple of 8) with NaN.

    Padded entries cost nothing in the iterative solves (a NaN distance is not
    iterated on) and are left out of every sum (:func:`_row_sums`) and maximum
    (through ``mask``).
    """

    def __init__(self, x, y, mask, n, x_max):
        self.x, self.y, self.mask, self.n, self.x_max = x, y, mask, n, x_max

    @classmethod
    def from_flat(cls, x_mm, y_mm, counts, offsets):
        """Trials ``i`` = ``x_mm[offsets[i]:offsets[i] + counts[i]]`` (each with a point)."""
        width = _padded_width(counts.max())
        column = np.arange(width)
        mask = column < counts[:, None]
        index = offsets[:, None] + np.minimum(column, counts[:, None] - 1)
        x = np.where(mask, x_mm[index], np.nan)
        y = np.where(mask, y_mm[index], np.nan)
        return cls(x, y, mask, counts, np.fmax.reduce(x, axis=1))

    def take(self, rows):
        return _Trials(self.x[rows], self.y[rows], self.mask[rows], self.n[rows], self.x_max[rows])

    @property
    def width(self):
        return self.x.shape[1]


def _in_blocks(evaluate, n_rows, n_L, width):
    """``evaluate(part)`` for slices of rows small enough that a temporary of ``n_L``
    values of L at ``width`` points stays under BLOCK_ELEMENTS; results concatenated."""
    size = max(1, BLOCK_ELEMENTS // max(1, n_L * width))
    if n_rows <= size:
        return evaluate(slice(None))
    return np.concatenate([evaluate(slice(i, i + size)) for i in range(0, n_rows, size)])


def _measures(residual_mm, mask, n_params):
    """:func:`goodness_of_fit` for each row of padded residuals."""
    n = np.sum(mask, axis=-1)
    sse = _row_sums(residual_mm**2, n)
    k = n_params + 1
    aicc = np.full(n.shape, np.nan)
    rmse = np.full(n.shape, np.nan)
    largest = np.full(n.shape, np.nan)
    corrected = n - k - 1 > 0
    with np.errstate(divide="ignore"):
        aicc[corrected] = (
            n[corrected] * np.log(sse[corrected] / n[corrected])
            + 2 * k
            + 2 * k * (k + 1) / (n[corrected] - k - 1)
        )
    some = n > 0
    rmse[some] = np.sqrt(sse[some] / n[some])
    largest[some] = np.max(np.where(mask, np.abs(residual_mm), -np.inf), axis=-1)[some]
    return {"sse_mm2": sse, "rmse_mm": rmse, "max_abs_residual_mm": largest, "aicc": aicc}


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
    residual_mm = np.asarray(residual_mm, dtype=float).reshape(-1)
    width = _padded_width(residual_mm.size)
    padded = np.zeros((1, width))
    padded[0, : residual_mm.size] = residual_mm
    mask = np.arange(width)[None, :] < residual_mm.size
    measures = _measures(padded, mask, n_params)
    return {name: _python_float(values[0]) for name, values in measures.items()}


# --------------------------------------------------------------------------- one-parameter search


def _single_objective(sse_of_L):
    """A one-trial ``sse_of_L(1-D L)`` in the batch form ``(L (1, K), rows, mode) -> (1, K)``.

    In mode ``"alone"`` each L goes in a call of its own, as the single-trial
    interval search has always called it.
    """

    def objective(L_mm, rows, mode="call"):
        if mode == "alone":
            values = [np.asarray(sse_of_L(L_mm[:, j]), dtype=float) for j in range(L_mm.shape[1])]
            return np.column_stack(values).reshape(L_mm.shape)
        return np.asarray(sse_of_L(L_mm.reshape(-1)), dtype=float).reshape(L_mm.shape)

    return objective


def _grid_values(objective, grid, lower_bound, per_round=4):
    """The objective on each trial's grid, or enough of it to find its smallest value.

    Only the smallest value is used, so the grid is evaluated in the cheaper "grid"
    mode (values as accurate, not bit for bit).  With ``lower_bound(grid, rows)``, a
    valid lower bound of the objective at each point, the points are visited in
    order of increasing bound, ``per_round`` at a time, until the next bound exceeds
    the best value found (with a margin of 1e-9 for rounding): the points left are
    provably worse, and are given as inf.
    """
    count, n_grid = grid.shape
    rows = np.arange(count)
    if lower_bound is None:
        return objective(grid, rows, mode="grid")
    bound = lower_bound(grid, rows)
    bound = np.where(np.isnan(bound), 0.0, bound)
    order = np.argsort(bound, axis=1, kind="stable")
    sse = np.full(grid.shape, np.inf)
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
        sse[r, c] = objective(grid[r, c][:, None], r, mode="grid")[:, 0]
        spared[r, c] = False
        best[going] = np.min(np.where(spared[going], np.inf, sse[going]), axis=1)
        first[going] += per_round
        going = going[wanted[:, -1]]  # the points after a refused one have larger bounds
    return sse


def _minimise_batch(objective, L_min, L_max, n_grid=200, rtol=1e-9, lower_bound=None):
    """:func:`minimise_in_L` for many trials in lockstep.

    ``objective(L_mm, rows, mode)`` gives the SSE of trials ``rows`` (R,) at ``L_mm``
    (R, K), each row as one call of a single-trial objective would give it (mode
    ``"call"``).  ``lower_bound`` (see :func:`_grid_values`) spares grid points that
    cannot be the best.  Returns the minimising L (NaN where the grid holds no finite
    value) and a mask of the trials that have one.
    """
    count = L_min.size
    L_mm = np.full(count, np.nan)
    if count == 0:
        return L_mm, np.zeros(0, dtype=bool)
    rows = np.arange(count)
    grid = np.geomspace(L_min, L_max, n_grid, axis=-1)
    sse = _grid_values(objective, grid, lower_bound)
    # where the two best values are within 1e-9 of each other, or a value is unknown
    # (NaN), the grid is evaluated again as one call would: its best point is then
    # exactly the one-call best
    two_best = np.partition(sse, 1, axis=1)[:, :2] if n_grid > 1 else sse[:, :1]
    with np.errstate(invalid="ignore"):
        clear = two_best[:, -1] - two_best[:, 0] > 1e-9 * np.abs(two_best[:, 0])
    recheck = np.flatnonzero((~clear & np.isfinite(two_best[:, 0])) | np.isnan(sse).any(axis=1))
    if recheck.size:
        sse[recheck] = objective(grid[recheck], recheck)
    found = np.any(np.isfinite(sse), axis=1)
    best = np.argmin(sse, axis=1)
    lo = grid[rows, np.maximum(best - 1, 0)]
    hi = grid[rows, np.minimum(best + 1, n_grid - 1)]
    fractions = np.arange(17.0)
    zooming = found & (hi - lo > rtol * hi)
    while zooming.any():
        active = np.flatnonzero(zooming)
        a, b = lo[active], hi[active]
        # 17 even steps from a to b, rounded as numpy.linspace rounds them
        points = fractions * ((b - a) / 16)[:, None] + a[:, None]
        points[:, -1] = b
        k = np.argmin(objective(points, active), axis=1)
        j = np.arange(active.size)
        lo[active] = points[j, np.maximum(k - 1, 0)]
        hi[active] = points[j, np.minimum(k + 1, 16)]
        zooming[active] = hi[active] - lo[active] > rtol * hi[active]
    if found.any():
        active = np.flatnonzero(found)
        candidates = np.column_stack([grid[active, best[active]], 0.5 * (lo[active] + hi[active])])
        choice = np.argmin(objective(candidates, active), axis=1)
        L_mm[active] = candidates[np.arange(active.size), choice]
    return L_mm, found


def minimise_in_L(sse_of_L, L_min, L_max, n_grid=200, rtol=1e-9):
    """Minimise a least-squares objective over one length, ``L_min <= L <= L_max``.

    A dense log-spaced grid finds the basin of the global minimum; a zoom then
    refines it inside the two grid cells around the best grid point (17 evenly
    spaced values per step, keeping the two cells around the best each time)
    until the bracket is ``rtol`` wide.  (The fits run the same steps for many
    trials at once.)

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
    L_mm, found = _minimise_batch(
        _single_objective(sse_of_L),
        np.array([float(L_min)]),
        np.array([float(L_max)]),
        n_grid=n_grid,
        rtol=rtol,
    )
    if not found[0]:
        raise ValueError(f"no admissible L between {L_min:g} and {L_max:g} mm")
    return float(L_mm[0])


def _illinois(g, a, b, fa, fb, rtol=1e-10):
    """Roots of ``g(c, which)`` between ``a`` (g <= 0) and ``b`` (g > 0), one per entry.

    The Illinois variant of regula falsi, in lockstep over the entries (each stops on
    its own): superlinear on smooth functions and, unlike Newton's method, never
    leaves the bracket.  ``fa`` and ``fb`` are ``g`` at ``a`` and ``b``.
    """
    a, b, fa, fb = (np.array(v, dtype=float) for v in (a, b, fa, fb))
    c = np.full(a.size, np.nan)
    last = np.zeros(a.size, dtype=int)
    active = np.arange(a.size)
    for _ in range(100):
        if active.size == 0:
            break
        a_, b_, fa_, fb_ = a[active], b[active], fa[active], fb[active]
        with np.errstate(invalid="ignore", divide="ignore"):
            # an infinite objective outside (an arc folded past the load) gives NaN,
            # as the one-trial search always has
            c_ = (a_ * fb_ - b_ * fa_) / (fb_ - fa_)
        fc = g(c_, active)
        right = fc > 0
        previous = last[active]
        a[active] = np.where(right, a_, c_)
        fa[active] = np.where(right, np.where(previous == -1, fa_ / 2.0, fa_), fc)
        b[active] = np.where(right, c_, b_)
        fb[active] = np.where(right, fc, np.where(previous == 1, fb_ / 2.0, fb_))
        last[active] = np.where(right, -1, 1)
        c[active] = c_
        done = (np.abs(b[active] - a[active]) <= rtol * np.abs(c_)) | (np.abs(fc) <= 1e-14)
        active = active[~done]
    return c


def _profile_batch(objective, L_best, L_min, L_max, sse_min, n_points, chi2=CHI2_1DOF_95):
    """:func:`profile_interval` for many trials; both ends of all trials in lockstep.

    Stepping out by the factor 1.05 is done a block of steps at a time (4, then 8,
    16, ... values per trial, each the previous one times the factor, as a loop
    would make them), so that a trial that needs thousands of steps costs a few
    rounds only.  The SSE at the last value inside and the first outside are kept
    for the regula falsi.  The objective is called in mode ``"alone"``: each value
    as if evaluated by itself, as the one-at-a-time search evaluates it.
    """
    count = L_best.size
    low, high = np.full(count, np.nan), np.full(count, np.nan)
    valid = np.isfinite(L_best) & (n_points >= 2)
    if not valid.any():
        return low, high
    rows = np.flatnonzero(valid)
    threshold = np.maximum(sse_min[rows], _TINY) * np.exp(chi2 / n_points[rows])
    # one problem per end: first the lower ends of all rows, then the upper ends
    problem_rows = np.concatenate([rows, rows])
    problem_threshold = np.concatenate([threshold, threshold])
    upper = np.repeat([False, True], rows.size)
    bound = np.concatenate([L_min[rows], L_max[rows]])
    factor = np.where(upper, 1.05, 1 / 1.05)
    n_problems = problem_rows.size
    end = np.full(n_problems, np.nan)
    inside = L_best[problem_rows].astype(float)
    outside = np.full(n_problems, np.nan)
    sse_inside = np.full(n_problems, np.nan)
    sse_outside = np.full(n_problems, np.nan)
    crossed = np.zeros(n_problems, dtype=bool)
    following = inside.copy()  # the next value to test
    pending = np.arange(n_problems)
    length = 4
    while pending.size:
        sequence = np.empty((pending.size, length))
        sequence[:, 0] = following[pending]
        sequence[:, 1:] = factor[pending, None]
        with np.errstate(over="ignore"):
            sequence = np.cumprod(sequence, axis=1)
        limit = bound[pending, None]
        sequence[:, 1:] = np.where(
            upper[pending, None],
            np.minimum(sequence[:, 1:], limit),
            np.maximum(sequence[:, 1:], limit),
        )
        sse = objective(sequence, problem_rows[pending], mode="alone")
        too_far = sse > problem_threshold[pending, None]
        stop = too_far | (sequence == limit)
        stops = stop.any(axis=1)
        first = np.argmax(stop, axis=1)
        # problems that crossed, or reached their bound, in this block
        j = np.flatnonzero(stops)
        done, f = pending[j], first[j]
        crossed[done] = too_far[j, f]
        earlier = f > 0
        inside[done[earlier]] = sequence[j[earlier], f[earlier] - 1]
        sse_inside[done[earlier]] = sse[j[earlier], f[earlier] - 1]
        outside[done] = sequence[j, f]
        sse_outside[done] = sse[j, f]
        at_bound = done[~crossed[done]]
        end[at_bound] = np.where(upper[at_bound], np.inf, bound[at_bound])
        # the others go on from their last value
        j = np.flatnonzero(~stops)
        going = pending[j]
        inside[going] = sequence[j, -1]
        sse_inside[going] = sse[j, -1]
        with np.errstate(over="ignore"):
            following[going] = sequence[j, -1] * factor[going]
        following[going] = np.where(
            upper[going],
            np.minimum(following[going], bound[going]),
            np.maximum(following[going], bound[going]),
        )
        pending = going
        length = min(2 * length, 4096)
    same = crossed & (inside == outside)  # the best fit itself is past the threshold (no noise)
    end[same] = inside[same]
    bracketed = np.flatnonzero(crossed & ~same)
    if bracketed.size:

        def log_ratio(sse, which):
            # an exact quartic can round to 0 or a hair below at a perfect fit
            return np.log(np.maximum(sse, _TINY) / problem_threshold[bracketed[which]])

        end[bracketed] = _illinois(
            lambda L_mm, which: log_ratio(
                objective(L_mm[:, None], problem_rows[bracketed[which]], mode="alone")[:, 0],
                which,
            ),
            inside[bracketed],
            outside[bracketed],
            log_ratio(sse_inside[bracketed], slice(None)),
            log_ratio(sse_outside[bracketed], slice(None)),
        )
    low[rows] = end[: rows.size]
    high[rows] = end[rows.size :]
    return low, high


def profile_interval(sse_of_L, L_best, L_min, L_max, sse_min, n_points, chi2=CHI2_1DOF_95):
    """Profile-likelihood confidence interval of a one-parameter fit in L.

    With Gaussian errors of unknown variance, the likelihood-ratio statistic
    of a value L is ``n ln(SSE(L) / SSE_min)``; the interval holds the L where
    it stays below the chi-square quantile.  Each end is found by stepping out
    from the best fit by factors of 1.05 until the statistic exceeds the
    quantile, then by regula falsi (Illinois) between the last step inside and
    the first outside.  An end that reaches the admissible range without
    crossing is reported as that bound (``L_min``) or as infinity (``L_max``).
    (The fits run the same steps for many trials at once.)

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
    low, high = _profile_batch(
        _single_objective(sse_of_L),
        *(np.array([float(value)]) for value in (L_best, L_min, L_max, sse_min)),
        np.array([int(n_points)]),
        chi2=chi2,
    )
    return (_python_float(low[0]), _python_float(high[0]))


# --------------------------------------------------------------------------- the fits of a chunk


class _ChunkFit:
    """One model fitted to the trials of a :class:`_Trials` chunk."""

    def __init__(self, model, trials, params, residual_mm, errors=None):
        self.model = model
        self.trials = trials
        self.params = params
        self.residual_mm = residual_mm
        self.errors = errors or {}
        self.measures = _measures(residual_mm, trials.mask, MODELS[model][1])


def _polyval(coefficients, u):
    """Horner's rule, as numpy.polyval: one polynomial per row (highest power first)."""
    value = np.zeros(u.shape)
    for j in range(coefficients.shape[1]):
        value = value * u + coefficients[:, j, None]
    return value


def _polynomial_roots(coefficients):
    """Roots of one polynomial per row, as numpy.roots finds them.

    The eigenvalues of each row's companion matrix, all rows in one call; a row
    with a zero first or last coefficient goes through numpy.roots itself (which
    strips them).  Rows with fewer roots are padded with NaN.
    """
    size, m = coefficients.shape
    roots = np.full((size, m - 1), np.nan, dtype=complex)
    regular = (coefficients[:, 0] != 0) & (coefficients[:, -1] != 0)
    if regular.any():
        c = coefficients[regular]
        companion = np.zeros((c.shape[0], m - 1, m - 1))
        companion[:, 0, :] = -c[:, 1:] / c[:, :1]
        companion[:, np.arange(1, m - 1), np.arange(m - 2)] = 1.0
        roots[regular] = np.linalg.eigvals(companion)
    for i in np.flatnonzero(~regular):
        found = np.roots(coefficients[i])
        roots[i, : found.size] = found
    return roots


def _waterbed_quartic(trials, depth_mm):
    """The paper's parabola's SSE as a quartic in ``u = 1 / L``, per trial.

    With ``W0`` the depth, each residual is ``a + b u + c u^2`` (``a = y - W0``,
    ``b = 4 W0 x``, ``c = -3 W0 x^2``), so ``SSE(u) = sum (a + b u + c u^2)^2``.

    Returns
    -------
    quartic : numpy.ndarray
        Shape ``(n_trials, 5)``: the coefficients, highest power first.
    a, b, c : numpy.ndarray
        The residual's terms, shaped like ``trials.x`` (padding included).
    """
    x, n = trials.x, trials.n
    W0 = depth_mm[:, None]
    a = trials.y - W0
    b = 4.0 * W0 * x
    c = -3.0 * W0 * x**2
    quartic = np.column_stack(
        [
            _row_sums(c * c, n),
            2.0 * _row_sums(b * c, n),
            _row_sums(b * b + 2.0 * a * c, n),
            2.0 * _row_sums(a * b, n),
            _row_sums(a * a, n),
        ]
    )
    return quartic, a, b, c


def _fit_waterbed_chunk(trials, depth_mm):
    x, y, n = trials.x, trials.y, trials.n
    W0 = depth_mm[:, None]
    quartic = _waterbed_quartic(trials, depth_mm)[0]
    x_max = trials.x_max
    u_max = 1.0 / x_max
    roots = _polynomial_roots(quartic[:, :-1] * np.arange(4, 0, -1))
    size = np.abs(roots)
    scale = np.maximum(1.0, np.max(np.where(np.isnan(size), 0.0, size), axis=1))
    real = roots.real
    usable = (np.abs(roots.imag) <= 1e-9 * scale[:, None]) & (real > 0) & (real < u_max[:, None])
    candidates = np.column_stack([np.zeros(x_max.size), u_max, np.where(usable, real, 0.0)])
    sse = _polyval(quartic, candidates)
    sse[:, 2:][~usable] = np.inf
    u_best = candidates[np.arange(x_max.size), np.argmin(sse, axis=1)]
    with np.errstate(divide="ignore"):
        L_mm = np.where(u_best == 0.0, np.inf, 1.0 / u_best)
    residual = y - waterbed_deflection_mm(x, W0, L_mm[:, None])
    low, high = _profile_batch(
        lambda L, rows, mode="call": _polyval(quartic[rows], 1.0 / L),
        L_mm,
        x_max,
        np.full(x_max.size, np.inf),
        _row_sums(residual**2, n),
        n,
    )
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _ChunkFit("waterbed", trials, params, residual)


def _points_sse(model_mm, trials, rows):
    """SSE of a model at the points of trials ``rows`` (R, K, width); not finite -> inf."""
    sse = _row_sums((trials.y[rows, None, :] - model_mm) ** 2, trials.n[rows])
    return np.where(np.isfinite(sse), sse, np.inf)


#: How an objective solves its iterative model, by mode: ``call`` as one call per
#: trial (row) would, ``alone`` as one call per value of L would, ``grid`` each value
#: alone and only to its rounding noise (see :func:`lineload.models.resting_position_mm`).
_SOLVE = {
    "call": {"independent_axes": 1},
    "alone": {"independent_axes": 2},
    "grid": {"independent_axes": 2, "settle": True},
}


def _curve_objective(curve, trials, depth_mm):
    """SSE of ``curve(x, W0, L, ...)`` for trials ``rows`` at L (R, K), solved per ``mode``."""

    def objective(L_mm, rows, mode="call"):
        def evaluate(part):
            r = rows[part]
            model = curve(
                trials.x[r, None, :],
                depth_mm[r, None, None],
                L_mm[part, :, None],
                **_SOLVE[mode],
            )
            return _points_sse(model, trials, r)

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    return objective


def _arc_objective(trials, depth_mm):
    """:func:`_curve_objective` of the arc, its circle solved once per (W0, L)."""

    def objective(L_mm, rows, mode="call"):
        W0 = depth_mm[rows, None]
        geometry = arc_geometry(W0, L_mm, **_SOLVE[mode])

        def evaluate(part):
            r = rows[part]
            model = arc_deflection_mm(
                trials.x[r, None, :],
                depth_mm[r, None, None],
                L_mm[part, :, None],
                geometry={name: values[part, :, None] for name, values in geometry.items()},
            )
            return _points_sse(model, trials, r)

        sse = _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)
        if mode == "grid":
            # whether the arc folds (no SSE) could come out the other way with the exact
            # half-angle only at the border itself: there the value is unknown (NaN)
            border = np.abs(np.tan(geometry["phi_rad"]) * W0 - L_mm) <= 1e-12 * L_mm
            sse[border] = np.nan
        return sse

    return objective


def _fit_by_search(model, trials, objective, residual_at, L_lo, lower_bound=None):
    """One-parameter fit in L by the grid and zoom over ``[L_lo, L_SEARCH_SPAN max(x)]``.

    Shared by the fits that have no closed form (exact arc, shifted parabola, parabola
    with W0 free): the minimum, the fitted curve's residuals and the interval.
    ``residual_at(rows, L_mm)`` gives the residuals of trials ``rows`` at L (R,).
    """
    L_hi = L_SEARCH_SPAN * trials.x_max
    L_mm, found = _minimise_batch(objective, L_lo, L_hi, lower_bound=lower_bound)
    residual = np.full(trials.x.shape, np.nan)
    rows = np.flatnonzero(found)
    residual[rows] = residual_at(rows, L_mm[rows])
    low, high = _profile_batch(
        objective, L_mm, L_lo, L_hi, _row_sums(residual**2, trials.n), trials.n
    )
    errors = {
        int(i): f"no valid {model} curve: no admissible L between {L_lo[i]:g} and {L_hi[i]:g} mm"
        for i in np.flatnonzero(~found)
    }
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _ChunkFit(model, trials, params, residual, errors), L_mm


def _fit_curve_chunk(model, curve, objective, trials, depth_mm, L_lo, lower_bound=None, **how):
    def residual_at(rows, L_mm):
        # one problem per trial, as a call with that trial's points and a scalar L
        fitted = curve(
            trials.x[rows], depth_mm[rows, None], L_mm[:, None], independent_axes=1, **how
        )
        return trials.y[rows] - fitted

    return _fit_by_search(model, trials, objective, residual_at, L_lo, lower_bound)[0]


def _shifted_lower_bound(trials, depth_mm):
    """A lower bound of the shifted parabola's SSE, from the paper's parabola read at x.

    The shifted curve is ``W(X)`` at ``x = X + U(X)`` with ``X <= x``, so at each
    point it differs from ``W(x)`` by at most ``max |W'| |U(X)|``, where
    ``|W'| <= 4 W0 / L`` on the membrane and ``|U(X)| = (6 W0^2 / L) g(X / L)``,
    ``g(s) = s (1 - s)^2 <= min(s, 4/27)``.  The gaps' root sum of squares is then
    at most ``D = min(sqrt(n) 32 W0^3 / (9 L^2), 24 W0^3 sqrt(sum x^2) / L^3)``, and
    by the triangle inequality ``SSE_shifted >= (sqrt(SSE_parabola) - D)^2``.  The
    parabola's SSE is the quartic in ``1 / L`` of the waterbed fit, less a bound on
    its rounding error; each value costs a few operations, not one per point.
    """
    x, n = trials.x, trials.n
    quartic, a, b, c = _waterbed_quartic(trials, depth_mm)
    # sums of the terms' sizes: the rounding of the coefficients and of Horner's rule
    # together stay below (n + 10) eps times the polynomial of these
    sizes = np.column_stack(
        [
            _row_sums(c * c, n),
            2.0 * _row_sums(np.abs(b * c), n),
            _row_sums(b * b + 2.0 * np.abs(a * c), n),
            2.0 * _row_sums(np.abs(a * b), n),
            _row_sums(a * a, n),
        ]
    )
    rounding = 4.0 * (n + 10) * np.finfo(float).eps
    W0_cubed = np.abs(depth_mm) ** 3
    root_sum_x2 = np.sqrt(_row_sums(x**2, n))

    def lower_bound(L_mm, rows):
        u = 1.0 / L_mm
        parabola = _polyval(quartic[rows], u) - rounding[rows, None] * _polyval(sizes[rows], u)
        gap = np.minimum(
            np.sqrt(n[rows, None]) * 32.0 * W0_cubed[rows, None] / (9.0 * L_mm**2),
            24.0 * W0_cubed[rows, None] * root_sum_x2[rows, None] / L_mm**3,
        )
        return np.maximum(np.sqrt(np.maximum(parabola, 0.0)) - gap * (1.0 + 1e-9), 0.0) ** 2

    return lower_bound


def _fit_arc_chunk(trials, depth_mm):
    objective = _arc_objective(trials, depth_mm)
    return _fit_curve_chunk(
        "arc", arc_deflection_mm, objective, trials, depth_mm, trials.x_max, as_scalars=True
    )


def _fit_shifted_chunk(trials, depth_mm):
    fold_mm = np.abs(depth_mm) / MAX_ONE_TO_ONE_RATIO * (1.0 + 1e-9)
    L_lo = np.maximum(trials.x_max, fold_mm)
    objective = _curve_objective(shifted_deflection_mm, trials, depth_mm)
    return _fit_curve_chunk(
        "shifted",
        shifted_deflection_mm,
        objective,
        trials,
        depth_mm,
        L_lo,
        _shifted_lower_bound(trials, depth_mm),
    )


def _fit_free_depth_chunk(trials, depth_mm=None):
    def shape_and_depth(L_mm, rows):
        # for a given L the best W0 of W0 g(x) is linear least squares
        s = trials.x[rows, None, :] / L_mm[:, :, None]
        g = 3.0 * s**2 - 4.0 * s + 1.0
        n = trials.n[rows]
        return g, _row_sums(trials.y[rows, None, :] * g, n) / _row_sums(g * g, n)

    def objective(L_mm, rows, mode="call"):
        def evaluate(part):
            r = rows[part]
            g, W0 = shape_and_depth(L_mm[part], r)
            return _row_sums((trials.y[r, None, :] - W0[:, :, None] * g) ** 2, trials.n[r])

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    W0_mm = np.full(trials.n.size, np.nan)

    def residual_at(rows, L_mm):
        W0_mm[rows] = shape_and_depth(L_mm[:, None], rows)[1][:, 0]
        return trials.y[rows] - waterbed_deflection_mm(
            trials.x[rows], W0_mm[rows, None], L_mm[:, None]
        )

    fit, _ = _fit_by_search("waterbed_free_depth", trials, objective, residual_at, trials.x_max)
    fit.params["W0_mm"] = W0_mm
    return fit


def _fit_boussinesq_chunk(trials, depth_mm=None):
    x, y, n = trials.x, trials.y, trials.n
    log_x = np.log(x)
    # w = A ln x0 - A ln x is a straight line in ln x: centred linear least squares
    mean_log_x = _row_sums(log_x, n) / n
    mean_y = _row_sums(y, n) / n
    centred = log_x - mean_log_x[:, None]
    spread = _row_sums(centred**2, n)
    single = spread == 0.0  # one distinct distance: the minimum-norm solution, as lstsq
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = _row_sums(centred * (y - mean_y[:, None]), n) / spread
    A_mm = np.where(single, -mean_log_x * mean_y / (1.0 + mean_log_x**2), -slope)
    intercept = np.where(single, mean_y / (1.0 + mean_log_x**2), mean_y + A_mm * mean_log_x)
    rising = A_mm > 0
    x0_mm = np.full(n.size, np.nan)
    x0_mm[rising] = np.exp(intercept[rising] / A_mm[rising])
    residual = y - (intercept[:, None] + (-log_x) * A_mm[:, None])
    residual[rising] = y[rising] - boussinesq_deflection_mm(
        x[rising], A_mm[rising, None], x0_mm[rising, None]
    )
    return _ChunkFit("boussinesq", trials, {"A_mm": A_mm, "x0_mm": x0_mm}, residual)


_CHUNK_FITS = {
    "waterbed": _fit_waterbed_chunk,
    "shifted": _fit_shifted_chunk,
    "arc": _fit_arc_chunk,
    "waterbed_free_depth": _fit_free_depth_chunk,
    "boussinesq": _fit_boussinesq_chunk,
}


# --------------------------------------------------------------------------- many trials


class BatchFits:
    """One model fitted to many trials: parameters and measures as arrays, by trial.

    Attributes
    ----------
    model : str
        The model's name (a key of :data:`MODELS`).
    params : dict of str to numpy.ndarray
        Each parameter of the model (``FitResult.params`` names), NaN where the
        trial has no fit.
    measures : dict of str to numpy.ndarray
        ``sse_mm2``, ``rmse_mm``, ``max_abs_residual_mm`` and ``aicc``, NaN where
        the trial has no fit.
    n_points : numpy.ndarray of int
        Points of each trial.
    fitted : numpy.ndarray of bool
        Whether the trial has a fit (enough points, an admissible L).
    errors : dict of int to str
        Why a trial has no fit, by trial index.
    """

    def __init__(self, model, n_points):
        count = n_points.size
        self.model = model
        self.params = {name: np.full(count, np.nan) for name in MODELS[model][0]}
        self.measures = {name: np.full(count, np.nan) for name in _MEASURES}
        self.n_points = n_points
        self.fitted = np.zeros(count, dtype=bool)
        self.errors = {}
        self._chunks = []
        self._where = np.full((count, 2), -1)

    def _add(self, trial_index, chunk):
        ok = np.ones(trial_index.size, dtype=bool)
        for row, message in chunk.errors.items():
            ok[row] = False
            self.errors[int(trial_index[row])] = message
        fitted = trial_index[ok]
        for name, values in chunk.params.items():
            self.params[name][fitted] = values[ok]
        for name, values in chunk.measures.items():
            self.measures[name][fitted] = values[ok]
        self.fitted[fitted] = True
        self._where[trial_index, 0] = len(self._chunks)
        self._where[trial_index, 1] = np.arange(trial_index.size)
        self._chunks.append(chunk)

    def __len__(self):
        return self.fitted.size

    def result(self, i):
        """The fit of trial ``i`` as a :class:`FitResult`.

        Raises
        ------
        ValueError
            If the trial has no fit (too few points, no admissible L).
        """
        if not self.fitted[i]:
            raise ValueError(self.errors[i])
        chunk, row = self._where[i]
        chunk = self._chunks[chunk]
        n = int(self.n_points[i])
        return FitResult(
            model=self.model,
            params={name: _python_float(values[i]) for name, values in self.params.items()},
            n_points=n,
            n_params=MODELS[self.model][1],
            residual_mm=chunk.residual_mm[row, :n].copy(),
            **{name: _python_float(values[i]) for name, values in self.measures.items()},
        )


def _as_trials(distance_mm, deflection_mm):
    """Concatenated points of many trials, and each trial's count."""
    distance_mm = [np.asarray(x, dtype=float) for x in distance_mm]
    deflection_mm = [np.asarray(y, dtype=float) for y in deflection_mm]
    if len(distance_mm) != len(deflection_mm):
        raise ValueError("distance_mm and deflection_mm must hold the same number of trials")
    for i, (x, y) in enumerate(zip(distance_mm, deflection_mm, strict=True)):
        if x.shape != y.shape or x.ndim != 1:
            raise ValueError(
                f"trial {i}: distance_mm and deflection_mm must be 1-D arrays of equal length"
            )
    counts = np.array([x.size for x in distance_mm], dtype=np.intp)
    if not counts.size:
        return np.zeros(0), np.zeros(0), counts
    return np.concatenate(distance_mm), np.concatenate(deflection_mm), counts


def _fit_flat(x_mm, y_mm, counts, depth_mm, models):
    """Fit ``models`` to trials given as concatenated points and counts."""
    offsets = np.cumsum(counts) - counts
    fits = {model: BatchFits(model, counts) for model in models}
    for model in models:
        minimum = MODELS[model][2]
        for i in np.flatnonzero(counts < minimum):
            fits[model].errors[int(i)] = (
                f"at least {minimum} points are needed, got {int(counts[i])}"
            )
    order = np.argsort(counts, kind="stable")
    order = order[counts[order] >= 1]
    for start in range(0, order.size, CHUNK_TRIALS):
        chunk = order[start : start + CHUNK_TRIALS]
        trials = _Trials.from_flat(x_mm, y_mm, counts[chunk], offsets[chunk])
        for model in models:
            enough = counts[chunk] >= MODELS[model][2]
            if not enough.any():
                continue
            part = trials if enough.all() else trials.take(np.flatnonzero(enough))
            fits[model]._add(chunk[enough], _CHUNK_FITS[model](part, depth_mm[chunk[enough]]))
    return fits


def fit_batch(distance_mm, deflection_mm, depth_mm=None, models=tuple(MODELS)):
    """Fit models to many trials at once, each on all of its points.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        One 1-D array per trial (mm); distances > 0, all finite.  Trials may
        differ in length.
    depth_mm : float or array_like, optional
        Indentation depth of each trial (mm), W0 of the fixed-depth waterbed
        fits; needed for those.
    models : iterable of str, optional
        Keys of :data:`MODELS`.

    Returns
    -------
    dict of str to BatchFits
        By model.  A trial with fewer points than a model needs, or without an
        admissible L, has no fit (``BatchFits.result`` raises the ValueError the
        single-trial function raises).

    Raises
    ------
    ValueError
        For a trial whose arrays differ in shape, a distance <= 0 or a value
        that is not finite.
    """
    models = tuple(models)
    x_mm, y_mm, counts = _as_trials(distance_mm, deflection_mm)
    if not (np.all(np.isfinite(x_mm)) and np.all(np.isfinite(y_mm))):
        raise ValueError("distances and deflections must be finite")
    if np.any(x_mm <= 0):
        raise ValueError("distances must be > 0 (the load point itself is not fitted)")
    if depth_mm is None:
        if set(models) & {"waterbed", "shifted", "arc"}:
            raise ValueError("the fixed-depth fits need depth_mm")
        depth_mm = np.nan
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), counts.shape)
    return _fit_flat(x_mm, y_mm, counts, depth_mm, models)


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


def _fit_one(model, distance_mm, deflection_mm, depth_mm=np.nan):
    x, y = _as_points(distance_mm, deflection_mm, minimum=MODELS[model][2])
    fits = _fit_flat(x, y, np.array([x.size]), np.array([float(depth_mm)]), (model,))
    return fits[model].result(0)


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
    return _fit_one("waterbed", distance_mm, deflection_mm, depth_mm)


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
    return _fit_one("arc", distance_mm, deflection_mm, depth_mm)


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
    return _fit_one("shifted", distance_mm, deflection_mm, depth_mm)


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
    return _fit_one("waterbed_free_depth", distance_mm, deflection_mm)


def fit_boussinesq(distance_mm, deflection_mm):
    """Fit the modified Boussinesq profile ``A ln(x0 / x)``: linear least squares.

    The model is a straight line in ``ln x``: ``w = A ln x0 - A ln x``, so the
    fit is an exact linear regression (centred, in closed form).  ``x0`` is
    reported as NaN when the slope has the wrong sign (``A <= 0``), where the
    form has no zero crossing.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two distinct.

    Returns
    -------
    FitResult
        ``params = {"A_mm": A, "x0_mm": x0}``.
    """
    return _fit_one("boussinesq", distance_mm, deflection_mm)


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


def window_points(distance_mm, deflection_mm, window_mm):
    """The points of many trials inside a fit window, concatenated.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        One 1-D array per trial (mm).
    window_mm : float or array_like
        Outer edge of the fitted region (mm), one for all trials or one each.

    Returns
    -------
    tuple
        ``(x_mm, y_mm, counts)``: the points with ``0 < distance <= window`` and a
        finite deflection, trial after trial, and how many each trial has.
    """
    x_mm, y_mm, counts = _as_trials(distance_mm, deflection_mm)
    window_mm = np.broadcast_to(np.asarray(window_mm, dtype=float), counts.shape)
    keep = in_fit_window(x_mm, np.repeat(window_mm, counts)) & np.isfinite(y_mm)
    trial = np.repeat(np.arange(counts.size), counts)
    return x_mm[keep], y_mm[keep], np.bincount(trial[keep], minlength=counts.size)


def fit_windowed(distance_mm, deflection_mm, depth_mm, window_mm, models=tuple(MODELS)):
    """Fit models to many trials at once, each on its points inside a fit window.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm), W0 of the fixed-depth waterbed fits.
    window_mm : float or array_like
        Points with ``0 < distance <= window_mm`` and a finite deflection are fitted.
    models : iterable of str, optional
        Keys of :data:`MODELS`.

    Returns
    -------
    dict
        ``n_points`` and ``max_distance_mm`` (arrays by trial, NaN for a trial
        without points) and each model's :class:`BatchFits` by its name.
    """
    x_mm, y_mm, counts = window_points(distance_mm, deflection_mm, window_mm)
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), counts.shape)
    fits = _fit_flat(x_mm, y_mm, counts, depth_mm, tuple(models))
    max_distance_mm = np.full(counts.size, np.nan)
    some = counts > 0
    if some.any():
        max_distance_mm[some] = np.maximum.reduceat(x_mm, (np.cumsum(counts) - counts)[some])
    return {"n_points": counts, "max_distance_mm": max_distance_mm, **fits}


def fit_trials(distance_mm, deflection_mm, depth_mm, window_mm):
    """Fit every model of the fit table to many trials, each on its windowed points.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm), W0 of the waterbed fits.
    window_mm : float or array_like
        Points with ``0 < distance <= window_mm`` are fitted.

    Returns
    -------
    list of dict
        One row per trial, as :func:`fit_trial` gives it.
    """
    fits = fit_windowed(distance_mm, deflection_mm, depth_mm, window_mm, TABLE_MODELS)
    count = fits["n_points"].size
    columns = {
        "depth_mm": np.broadcast_to(np.asarray(depth_mm, dtype=float), count).tolist(),
        "fit_window_mm": np.broadcast_to(np.asarray(window_mm, dtype=float), count).tolist(),
        "n_points": fits["n_points"].tolist(),
        "max_distance_mm": fits["max_distance_mm"].tolist(),
    }
    for model in TABLE_MODELS:
        fit = fits[model]
        for name, values in (*fit.params.items(), *list(fit.measures.items())[1:]):
            columns[f"{model}_{name}"] = values.tolist()
    for name, values in columns.items():
        if name != "n_points":
            columns[name] = [np.nan if v != v else v for v in values]
    names = list(columns)
    return [dict(zip(names, row, strict=True)) for row in zip(*columns.values(), strict=True)]


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
    return fit_trials([distance_mm], [deflection_mm], [depth_mm], window_mm)[0]
