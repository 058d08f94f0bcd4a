"""The small-slope parabola with both W0 and L free (a sensitivity refit).

For a given L the model ``W0 g(x)`` is linear in W0, so W0 is profiled out in closed
form and L searched; the interval on L profiles W0 out.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.optimize import CHI2_1DOF_95
from lineload.fitting.search import _fit_by_search, _in_blocks
from lineload.models import waterbed_deflection_mm

__all__ = ["fit_free_depth_chunk"]


def fit_free_depth_chunk(trials, depth_mm=None):
    """The parabola with W0 free fitted to a chunk of trials (``depth_mm`` unused)."""

    def shape_and_depth(L_mm, rows):
        # for a given L the best W0 of W0 g(x) is linear least squares
        g = 3.0 * (trials.x[rows, None, :] / L_mm[:, :, None]) ** 2
        g = g - 4.0 * trials.x[rows, None, :] / L_mm[:, :, None] + 1.0
        g_in = trials.masked(g, rows)
        y_in = trials.masked(trials.y[rows], rows)[:, None, :]
        return g, np.sum(y_in * g_in, axis=-1) / np.sum(g_in * g_in, axis=-1)

    def objective(L_mm, rows):
        def evaluate(part):
            r = rows[part]
            g, W0 = shape_and_depth(L_mm[part], r)
            return trials.chi2(trials.y[r, None, :] - W0[:, :, None] * g, r)

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    W0_mm = np.full(trials.n.size, np.nan)

    def residual_at(rows, L_mm):
        W0_mm[rows] = shape_and_depth(L_mm[:, None], rows)[1][:, 0]
        return trials.y[rows] - waterbed_deflection_mm(
            trials.x[rows], W0_mm[rows, None], L_mm[:, None]
        )

    def delta_at(L_mm, residual):
        if trials.covariance is None:
            return None
        return _free_depth_delta(trials, L_mm, W0_mm, residual)

    fit, _ = _fit_by_search(
        "waterbed_free_depth", trials, objective, residual_at, trials.x_max, delta_at=delta_at
    )
    fit.params["W0_mm"] = W0_mm
    return fit


def _free_depth_delta(trials, L_mm, W0_mm, residual):
    """:func:`_sandwich_delta` of the parabola with W0 free: two parameters.

    With ``f = W0 g(x; L)``, ``g = 3 (x/L)^2 - 4 x/L + 1``, the Jacobian is
    ``[W0 g_L, g]`` and ``H = J'J - sum r f''`` (2 x 2); the sandwich
    ``V = H^-1 J'CJ H^-1`` gives L's variance, and the profile's curvature in L is
    ``1 / (H^-1)_LL``: the sum of squares rises by ``chi2 V_LL / (H^-1)_LL``.
    """
    x = trials.x
    L, W0 = L_mm[:, None], W0_mm[:, None]
    g = 3.0 * (x / L) ** 2 - 4.0 * x / L + 1.0
    g_L = -6.0 * x**2 / L**3 + 4.0 * x / L**2
    g_LL = 18.0 * x**2 / L**4 - 8.0 * x / L**3
    J = trials.masked(np.stack([W0 * g_L, g], axis=-1).transpose(0, 2, 1)).transpose(0, 2, 1)
    r = trials.masked(residual)
    H = np.einsum("tik,til->tkl", J, J)
    H[:, 0, 0] -= np.sum(r * trials.masked(W0 * g_LL), axis=-1)
    H[:, 0, 1] -= np.sum(r * trials.masked(g_L), axis=-1)
    H[:, 1, 0] = H[:, 0, 1]
    delta = np.full(L_mm.size, np.nan)
    ok = np.isfinite(L_mm) & np.isfinite(W0_mm) & np.all(np.isfinite(H), axis=(1, 2))
    if ok.any():
        inverse = np.linalg.pinv(H[ok])
        V = inverse @ trials.take(np.flatnonzero(ok)).quadratic(J[ok]) @ inverse
        with np.errstate(divide="ignore", invalid="ignore"):
            delta[ok] = CHI2_1DOF_95 * V[:, 0, 0] / inverse[:, 0, 0]
    return delta
