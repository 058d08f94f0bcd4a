"""The paper's fit: the small-slope parabola (eq. 19) with W0 held at the depth, exactly.

With ``u = 1 / L`` the model ``W0 (3 u**2 x**2 - 4 u x + 1)`` is quadratic in ``u``,
so the sum of squares is a quartic in ``u``; its global minimum over
``0 <= u <= 1 / max(x)`` is at a real root of the cubic derivative or at an end,
and all candidates are compared exactly: no start value, no iteration.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.goodness import _ChunkFit
from lineload.fitting.intervals import _interval, _sandwich_delta
from lineload.models import waterbed_deflection_mm

__all__ = ["fit_waterbed_chunk"]


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
    """The paper's parabola's sum of squares as a quartic in ``u = 1 / L``.

    With ``W0`` the depth, each residual is ``a + b u + c u^2`` (``a = y - W0``,
    ``b = 4 W0 x``, ``c = -3 W0 x^2``), so ``SSE(u) = sum (a + b u + c u^2)^2``.

    Returns
    -------
    quartic : numpy.ndarray
        Shape ``(n_trials, 5)``: the coefficients, highest power first.
    a, b, c : numpy.ndarray
        The residual's terms, shaped like ``trials.x``, zero in padding.
    """
    x = trials.x
    W0 = depth_mm[:, None]
    a, b, c = (trials.masked(v) for v in (trials.y - W0, 4.0 * W0 * x, -3.0 * W0 * x**2))
    quartic = np.column_stack(
        [
            np.sum(c * c, axis=-1),
            2.0 * np.sum(b * c, axis=-1),
            np.sum(b * b + 2.0 * a * c, axis=-1),
            2.0 * np.sum(a * b, axis=-1),
            np.sum(a * a, axis=-1),
        ]
    )
    return quartic, a, b, c


def fit_waterbed_chunk(trials, depth_mm):
    """The parabola fitted to a chunk of trials, ``W0 = depth_mm``, L by the exact quartic."""
    x, y = trials.x, trials.y
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
    values = _polyval(quartic, candidates)
    values[:, 2:][~usable] = np.inf
    u_best = candidates[np.arange(x_max.size), np.argmin(values, axis=1)]
    with np.errstate(divide="ignore"):
        L_mm = np.where(u_best == 0.0, np.inf, 1.0 / u_best)
    residual = y - waterbed_deflection_mm(x, W0, L_mm[:, None])

    def residual_at(rows, L):
        return y[rows] - waterbed_deflection_mm(x[rows], W0[rows], L[:, None])

    delta, share = _sandwich_delta(trials, residual_at, L_mm, residual)
    low, high, at_bound = _interval(
        lambda L, rows: _polyval(quartic[rows], 1.0 / L),
        trials,
        L_mm,
        x_max,
        np.full(x_max.size, np.inf),
        trials.chi2(residual),
        delta,
        residual_at,
        residual,
    )
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _ChunkFit("waterbed", trials, params, residual, at_bound=at_bound, prior_share=share)
