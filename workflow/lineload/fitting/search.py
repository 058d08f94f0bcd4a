"""The fits without a closed form: a bounded search in L over many trials at once.

The exact arc, the shifted parabola and the parabola with W0 free each reduce to a
least-squares objective in L alone over ``[L_lo, L_SEARCH_SPAN max(x)]``, minimised by
:func:`lineload.fitting.optimize.minimize_bounded` for a whole chunk of trials.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.goodness import _ChunkFit
from lineload.fitting.intervals import _interval, _sandwich_delta, at_search_bound
from lineload.fitting.optimize import minimize_bounded

__all__ = ["BLOCK_ELEMENTS", "L_SEARCH_SPAN"]

#: Largest membrane half-width searched by the iterative fits (exact arc, and the
#: parabola with W0 free), as a multiple of the smallest admissible one. The
#: fixed-W0 parabola needs no such bound: its minimum is found exactly.
L_SEARCH_SPAN = 1000.0

#: Largest number of elements of one temporary array while an objective is evaluated
#: for many trials and many L at once (2**14 doubles: 128 KiB, within a core's
#: cache); larger evaluations go in blocks of trials.
BLOCK_ELEMENTS = 1 << 14


def _in_blocks(evaluate, n_rows, n_L, width):
    """``evaluate(part)`` for slices of rows small enough that a temporary of ``n_L``
    values of L at ``width`` points stays under BLOCK_ELEMENTS; results concatenated."""
    size = max(1, BLOCK_ELEMENTS // max(1, n_L * width))
    if n_rows <= size:
        return evaluate(slice(None))
    return np.concatenate([evaluate(slice(i, i + size)) for i in range(0, n_rows, size)])


def _curve_objective(curve, trials, depth_mm):
    """Chi-square of ``curve(x, W0, L)`` for trials ``rows`` at L (R, K)."""

    def objective(L_mm, rows):
        def evaluate(part):
            r = rows[part]
            model = curve(trials.x[r, None, :], depth_mm[r, None, None], L_mm[part, :, None])
            return trials.chi2(trials.y[r, None, :] - model, r)

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    return objective


def _fit_by_search(model, trials, objective, residual_at, L_lo, lower_bound=None, delta_at=None):
    """One-parameter fit in L by a grid and Brent's method over ``[L_lo, L_SEARCH_SPAN max(x)]``.

    Shared by the fits that have no closed form (exact arc, shifted parabola, parabola
    with W0 free): the minimum, the fitted curve's residuals and the interval.
    ``residual_at(rows, L_mm)`` gives the residuals of trials ``rows`` at L (R,);
    ``delta_at(L_mm, residual)``, if given, replaces :func:`_sandwich_delta`.
    """
    L_hi = L_SEARCH_SPAN * trials.x_max
    L_mm, found = minimize_bounded(objective, L_lo, L_hi, lower_bound=lower_bound)
    residual = np.full(trials.x.shape, np.nan)
    rows = np.flatnonzero(found)
    residual[rows] = residual_at(rows, L_mm[rows])
    if not trials.intervals:  # the fit alone (a refit that follows L across windows)
        low, high, share = np.full_like(L_mm, np.nan), np.full_like(L_mm, np.nan), None
        at_bound = at_search_bound(L_mm, L_lo, L_hi)
    else:
        if delta_at is None:
            delta, share = _sandwich_delta(trials, residual_at, L_mm, residual)
        else:
            delta, share = delta_at(L_mm, residual), None
        low, high, at_bound = _interval(
            objective, trials, L_mm, L_lo, L_hi, trials.chi2(residual), delta, residual_at, residual
        )
    if rows.size:
        residual_at(rows, L_mm[rows])  # restores what residual_at keeps of the best fit (W0)
    errors = {
        int(i): f"no valid {model} curve: no admissible L between {L_lo[i]:g} and {L_hi[i]:g} mm"
        for i in np.flatnonzero(~found)
    }
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _ChunkFit(model, trials, params, residual, errors, at_bound, share), L_mm


def _fit_curve_chunk(model, curve, objective, trials, depth_mm, L_lo, lower_bound=None):
    def residual_at(rows, L_mm):
        return trials.y[rows] - curve(trials.x[rows], depth_mm[rows, None], L_mm[:, None])

    return _fit_by_search(model, trials, objective, residual_at, L_lo, lower_bound)[0]
