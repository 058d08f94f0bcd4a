"""The 95 % intervals on L of the one-parameter fits, and whether a fit ends on a bound.

Errors
------
Every fit is ordinary least squares: its parameters are the paper's (the best
unweighted approximation of the readings), whatever the noise.  The models are
approximations of the skin, so weighting the points would change what L means:
weighted by the digitising noise (generalised least squares), the noise-free
reconstruction's L moves by up to 1.1 mm (9 %), and with the noise measured
anew in each dataset it would move with the measurement.

Without a covariance, the interval on L is the profile-likelihood interval for
independent errors of unknown variance (``n ln(SSE(L) / SSE_min) <= chi2``).
Given the covariance of each trial's points (``covariance_mm2``, measured apart
from the fit), the interval honours it: the least-squares L moves with the
readings as ``dL = J' dy / H`` (``J`` the curve's derivative in L, ``H = J'J -
r' f''`` the objective's half-curvature, misfit ``r`` included), so its variance
is ``J' C J / H**2`` (the sandwich), and the interval holds the L whose sum of
squares exceeds the minimum by less than ``chi2 J' C J / H``: the profile's own
shape, scaled to that variance.  The two-parameter fits do the same with their
2 x 2 matrices.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.optimize import CHI2_1DOF_95, likelihood_interval

__all__ = ["AT_BOUND_RTOL", "at_search_bound"]


def _sandwich_delta(trials, residual_at, L_mm, residual):
    """How far the sum of squares rises at the ends of the 95 % interval on L, given
    the points' covariance: ``chi2 J' C J / H`` (see the module's notes), and the
    share of that variance the stated priors make (:func:`_prior_share`); None and
    NaN without a covariance.

    ``J`` and the curve's second derivative come from central differences of
    ``residual_at(rows, L)`` at ``L (1 +- 1e-4)``; where a side is not defined (a
    bound of the model) one-sided, with the misfit term left out of ``H``.
    """
    if trials.covariance is None:
        return None, np.full(L_mm.size, np.nan)
    delta, share = np.full(L_mm.size, np.nan), np.full(L_mm.size, np.nan)
    rows = np.flatnonzero(np.isfinite(L_mm))
    if not rows.size:
        return delta, share
    L = L_mm[rows]
    step = 1e-4 * L
    r0 = trials.masked(residual[rows], rows)
    with np.errstate(invalid="ignore"):
        above = trials.masked(residual_at(rows, L + step), rows)
        below = trials.masked(residual_at(rows, L - step), rows)
    central = np.all(np.isfinite(below), axis=-1)
    J = np.where(
        central[:, None], (below - above) / (2 * step[:, None]), (r0 - above) / step[:, None]
    )
    curvature = -(above - 2 * r0 + below) / step[:, None] ** 2  # the curve's d2f/dL2
    H = np.sum(J * J, axis=-1) - np.where(central, np.sum(r0 * curvature, axis=-1), 0.0)
    H = np.where(H > 0, H, np.sum(J * J, axis=-1))
    spread = np.einsum("ti,tij,tj->t", J, trials.covariance[rows], J)
    with np.errstate(divide="ignore", invalid="ignore"):
        delta[rows] = CHI2_1DOF_95 * spread / H
    share[rows] = _prior_share(trials.take(rows), J, spread)
    return delta, share


def _prior_share(trials, J, spread):
    """Share ``J' C_prior J / J' C J`` of a one-parameter fit's variance that the stated
    priors make (``C_prior`` the covariance of the shared offset, tilt and depth error
    alone, which enter ``C`` linearly in their variances); NaN without that split."""
    if trials.prior_covariance is None:
        return np.full(J.shape[0], np.nan)
    prior = np.einsum("ti,tij,tj->t", J, trials.prior_covariance, J)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.clip(prior / spread, 0.0, 1.0)


#: Relative distance from a bound of the search within which a fitted L is taken to
#: lie on it: far above the search's own tolerance (``rtol`` 1e-9 of
#: :func:`lineload.fitting.optimize.minimize_bounded`), far below any interval's width.
AT_BOUND_RTOL = 1e-6


def at_search_bound(L_mm, L_min, L_max):
    """Whether each fitted L lies on a bound of its admissible range.

    Parameters
    ----------
    L_mm, L_min, L_max : array_like
        Fitted L and the admissible range (mm); ``L_max`` may be infinite.

    Returns
    -------
    numpy.ndarray of bool
        True where ``L`` is within :data:`AT_BOUND_RTOL` of ``L_min`` or of ``L_max``
        (an infinite L, a flat membrane, is on the upper bound).
    """
    L_mm, L_min, L_max = (np.asarray(v, dtype=float) for v in (L_mm, L_min, L_max))
    with np.errstate(invalid="ignore"):
        low = np.isfinite(L_mm) & (L_mm <= L_min * (1.0 + AT_BOUND_RTOL))
        high = np.isinf(L_mm) | (np.isfinite(L_max) & (L_mm >= L_max * (1.0 - AT_BOUND_RTOL)))
    return low | high


def _bound_half_width(trials, residual_at, L_mm, residual, rows):
    """Half-width ``z_0.975 sqrt(J' C J) / J' J`` of a linearised 95 % interval on L,
    for fits that end on the lower bound of L.

    There the sum of squares does not have a minimum but a slope, so the likelihood
    interval (the L whose sum of squares rises by less than a threshold) shrinks with
    that slope to microns, however noisy the readings.  What the readings allow is
    how far L moves with them: ``J = df/dL`` from a one-sided difference into the
    admissible side, and ``C`` the points' covariance (without one, the residual
    variance times the identity, ``n - 1`` degrees of freedom).  A fit on its bound
    misfits the readings by construction; where the misfit exceeds the noise
    (``r' C^-1 r`` above ``n - 1``), the variance is scaled by their ratio, as
    for independent errors of unknown size, so that the readings' departure from
    the model widens the interval instead of being read as precision.
    """
    L = L_mm[rows]
    step = 1e-4 * L
    r0 = trials.masked(residual[rows], rows)
    with np.errstate(invalid="ignore"):
        above = trials.masked(residual_at(rows, L + step), rows)
    J = (r0 - above) / step[:, None]
    H = np.sum(J * J, axis=-1)
    if trials.covariance is not None:
        spread = np.einsum("ti,tij,tj->t", J, trials.covariance[rows], J)
        misfit = trials.take(rows).generalised_chi2(residual[rows])
        spread = spread * np.fmax(misfit / np.maximum(trials.n[rows] - 1, 1), 1.0)
    else:
        variance = np.sum(r0 * r0, axis=-1) / np.maximum(trials.n[rows] - 1, 1)
        spread = variance * H
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.sqrt(CHI2_1DOF_95 * spread) / H


def _interval(
    objective, trials, L_best, L_min, L_max, chi2_min, delta=None, residual_at=None, residual=None
):
    """The 95 % interval on L of each trial (NaN where it cannot be had), and which
    fits end on a bound of L.

    Without a covariance a fit needs two points for its variance; with one (and
    ``delta`` from :func:`_sandwich_delta`), one.  A fit on the lower bound gets a
    one-sided interval: from the bound up to the bound plus the linearised
    half-width (:func:`_bound_half_width`), or the likelihood interval's upper end
    if that is further; never the microns the sum of squares' slope there would give.
    """
    valid = np.isfinite(L_best) & (trials.n >= (1 if trials.covariance is not None else 2))
    if delta is not None:
        valid &= np.isfinite(delta) & (delta > 0)
    best = np.where(valid, L_best, np.nan)
    low, high = likelihood_interval(
        objective, best, L_min, L_max, trials.threshold(chi2_min, delta=delta)
    )
    at_bound = at_search_bound(L_best, L_min, L_max)
    on_lower = np.flatnonzero(at_bound & np.isfinite(L_best) & np.isfinite(high))
    if residual_at is not None and on_lower.size:
        half = _bound_half_width(trials, residual_at, L_best, residual, on_lower)
        low[on_lower] = L_min[on_lower]
        high[on_lower] = np.fmax(high[on_lower], L_min[on_lower] + half)
    return low, high, at_bound
