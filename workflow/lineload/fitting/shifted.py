"""The small-slope parabola in measured coordinates (W(X) at ``x = X + U(X)``), L searched.

It exists only while ``x(X)`` is one-to-one, ``L > sqrt(6) W0``: the search runs over
that range, and a cheap lower bound of its objective (from the paper's parabola)
lets the search skip most evaluations of the inverse map.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.search import _curve_objective, _fit_curve_chunk
from lineload.fitting.waterbed import _polyval, _waterbed_quartic
from lineload.models import MAX_ONE_TO_ONE_RATIO, shifted_deflection_mm

__all__ = ["fit_shifted_chunk"]


def _shifted_lower_bound(trials, depth_mm):
    """A lower bound of the shifted parabola's chi-square, from the paper's parabola read at x.

    The shifted curve is ``W(X)`` at ``x = X + U(X)`` with ``X <= x``, so at each
    point it differs from ``W(x)`` by at most ``max |W'| |U(X)|``, where
    ``|W'| <= 4 W0 / L`` on the membrane and ``|U(X)| = (6 W0^2 / L) g(X / L)``,
    ``g(s) = s (1 - s)^2 <= min(s, 4/27)``.  The gaps' root sum of squares is then
    at most ``D = min(sqrt(n) 32 W0^3 / (9 L^2), 24 W0^3 sqrt(sum x^2) / L^3)``, and
    by the triangle inequality ``SSE_shifted >= (sqrt(SSE_parabola) - D)^2``.  The
    parabola's value is the quartic in ``1 / L`` of the waterbed fit, less a bound
    on its rounding error; each value costs a few operations, not one per point.
    """
    x, n = trials.x, trials.n
    quartic, a, b, c = _waterbed_quartic(trials, depth_mm)
    # sums of the terms' sizes: the rounding of the coefficients and of Horner's rule
    # together stay below (n + 10) eps times the polynomial of these
    sizes = np.column_stack(
        [
            np.sum(c * c, axis=-1),
            2.0 * np.sum(np.abs(b * c), axis=-1),
            np.sum(b * b + 2.0 * np.abs(a * c), axis=-1),
            2.0 * np.sum(np.abs(a * b), axis=-1),
            np.sum(a * a, axis=-1),
        ]
    )
    rounding = 4.0 * (n + 10) * np.finfo(float).eps
    W0_cubed = np.abs(depth_mm) ** 3
    root_sum_x2 = np.sqrt(trials.sum(x**2))

    def lower_bound(L_mm, rows):
        u = 1.0 / L_mm
        parabola = _polyval(quartic[rows], u) - rounding[rows, None] * _polyval(sizes[rows], u)
        gap = np.minimum(
            np.sqrt(n[rows, None]) * 32.0 * W0_cubed[rows, None] / (9.0 * L_mm**2),
            24.0 * W0_cubed[rows, None] * root_sum_x2[rows, None] / L_mm**3,
        )
        return np.maximum(np.sqrt(np.maximum(parabola, 0.0)) - gap * (1.0 + 1e-9), 0.0) ** 2

    return lower_bound


def fit_shifted_chunk(trials, depth_mm):
    """The shifted parabola fitted to a chunk of trials, ``W0 = depth_mm``, ``L > sqrt(6) W0``."""
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
