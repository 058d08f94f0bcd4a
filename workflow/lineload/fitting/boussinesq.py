"""The modified Boussinesq half-space ``A ln(x0 / x)``: a straight line in ``ln x``.

The fit is linear least squares in closed form; the intervals are profile-likelihood
intervals without a covariance, and the sandwich (with the wedge's misplacement
taken into account) with one.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.goodness import _ChunkFit
from lineload.fitting.optimize import CHI2_1DOF_95
from lineload.models import boussinesq_deflection_mm

__all__ = ["fit_boussinesq_chunk"]


def _boussinesq_intervals(trials, intercept, A_mm):
    """95 % profile-likelihood intervals on A and x0 of the straight line in ``ln x``
    (independent errors of unknown variance).

    On columns ``u = 1``, ``v = -ln x`` and values ``y = w`` the model is
    ``a u + A v`` (``a = A ln x0``).  Profiling ``a`` out, the objective is
    quadratic in A: ``A +- sqrt(delta / (s22 - s12**2 / s11))``.  For x0, the
    model is ``A (ln x0 u + v)``; profiling A out, the interval's ends solve a
    quadratic in ``ln x0`` (a ratio of quadratics set to the threshold), bounded
    when its leading coefficient is negative, else unbounded (NaN ends).
    ``delta`` is the profile likelihood's ``SSE_min (exp(3.84 / n) - 1)``.
    """
    x, y = trials.x, trials.y
    ones = trials.masked(np.ones(x.shape))
    logs = trials.masked(-np.log(x))
    values = trials.masked(y)
    s11, s12, s22 = (np.sum(p * q, axis=-1) for p, q in ((ones, ones), (ones, logs), (logs, logs)))
    t1, t2 = np.sum(ones * values, axis=-1), np.sum(logs * values, axis=-1)
    total = np.sum(values**2, axis=-1)
    chi2_min = np.sum((values - intercept[:, None] * ones - A_mm[:, None] * logs) ** 2, axis=-1)
    delta = trials.threshold(chi2_min) - chi2_min
    with np.errstate(divide="ignore", invalid="ignore"):
        half = np.sqrt(delta / (s22 - s12**2 / s11))
        c = total - chi2_min - delta
        a2 = t1**2 - c * s11
        a1 = t1 * t2 - c * s12
        a0 = t2**2 - c * s22
        root = np.sqrt(a1**2 - a2 * a0)
        ends = np.sort(np.stack([(-a1 - root) / a2, (-a1 + root) / a2]), axis=0)
    bounded = (a2 < 0) & np.isfinite(ends).all(axis=0) & (A_mm > 0)
    x0_low = np.where(bounded, np.exp(ends[0]), np.nan)
    x0_high = np.where(bounded, np.exp(ends[1]), np.nan)
    return {
        "A_ci_low_mm": A_mm - half,
        "A_ci_high_mm": A_mm + half,
        "x0_ci_low_mm": x0_low,
        "x0_ci_high_mm": x0_high,
    }


#: Gauss-Hermite nodes of the wedge's misplacement (probabilists'), exact for
#: polynomials in d of degree up to 79: far beyond the series of ln(1 - d^2/x^2)
#: that matters at d/x < 1/2.
_WEDGE_NODES, _WEDGE_WEIGHTS = np.polynomial.hermite_e.hermegauss(40)
_WEDGE_WEIGHTS = _WEDGE_WEIGHTS / _WEDGE_WEIGHTS.sum()
#: Where the misplacement comes within 5 % of a reading's distance (``|1 - d^2/x^2|``
#: below ``1 - 0.95^2``), the log's argument is held there: the reading would sit on
#: the wedge itself.  (Beyond it, ``d > x``, the reading lies on the other side, at
#: ``d - x``; the profile is symmetric, so the same ``|.|`` holds.)
_WEDGE_MAX_RATIO = 0.95


def _wedge_moments(x_mm, mask, wedge_sd_mm):
    """Mean and centred quadrature terms of ``g = -ln|1 - d^2 / x^2| / 2`` over ``d``.

    Returns
    -------
    tuple of numpy.ndarray
        ``mean`` ``(T, n)`` and ``spread`` ``(T, n, nodes)``, the nodes' centred
        values times the square roots of their weights, so that the covariance of
        ``g`` is ``spread @ spread.T``; zero in the padding, and all zero when
        ``wedge_sd_mm`` is 0.
    """
    shape = x_mm.shape
    if not wedge_sd_mm > 0:
        return np.zeros(shape), np.zeros((*shape, 1))
    ratio = np.where(mask, wedge_sd_mm / np.where(mask, x_mm, 1.0), 0.0)
    scaled = np.abs(1.0 - (ratio[..., None] * _WEDGE_NODES) ** 2)
    g = -0.5 * np.log(np.maximum(scaled, 1.0 - _WEDGE_MAX_RATIO**2))
    mean = g @ _WEDGE_WEIGHTS
    spread = (g - mean[..., None]) * np.sqrt(_WEDGE_WEIGHTS)
    return mean, spread


def _boussinesq_sandwich_intervals(trials, intercept, A_mm):
    """95 % intervals on A and x0 given the points' covariance ``C`` (the sandwich), the
    share of A's variance that the stated priors make (NaN without their split), and the
    share the wedge's position alone makes (0 when its prior is 0).

    The least-squares line ``a - A ln x`` has covariance ``V = (X'X)^-1 X'CX
    (X'X)^-1`` (``X = [1, -ln x]``); A's interval is ``A +- 1.96 sqrt(V_AA)``,
    exact for a linear fit, and x0's is ``exp(ln x0 +- 1.96 sd)`` with
    ``ln x0 = a / A`` and its standard deviation to first order.

    A wedge misplaced by ``d`` along the outline reads each side at ``x +- d``;
    the left-right mean cancels the first-order error, but the form is
    log-singular at the wedge and the mean keeps ``A g(x, d)``, ``g = -ln|1 -
    d**2 / x**2| / 2`` (about ``d**2 / (2 x**2)``), positive while ``d < x``.  Near the
    wedge, where the points steer the slope in ``ln x``, that biases the
    least-squares A up by about a third of its standard deviation (coverage 0.92
    instead of 0.95 in simulation).  With ``d`` normal of standard deviation
    ``s`` (the noise model's wedge position), the mean ``m`` and covariance
    ``S`` of ``g`` over the readings are found by Gauss-Hermite quadrature; the
    intervals are centred on the line with ``A m`` removed (``E[A_ls] = A (1 +
    k_A)``, ``E[a_ls] = a + A k_a``, ``k = (X'X)^-1 X' m``) and widened by
    ``A**2 S``; the fitted A and x0 stay the least-squares values.  The
    correction assumes the logarithm holds down to the first reading, as the
    model says; for a profile that is smoother there it widens the intervals
    a little, and it rests on the prior: its share of A's variance is in the
    priors' share with the others' (:func:`lineload.fitting.intervals._prior_share`)
    and reported alone too (``A_wedge_share``, ``A**2 (h h')_AA / V_AA``).

    The shift is a prior, not estimated from each trial. The wedge's shift ``d`` reaches
    the readings only through the left-right difference, where it adds ``2 d w'(x)`` to
    the finger's own difference of its two sides, ``a(x) = w_l(x) - w_r(x)``. ``d``
    could be told from ``a`` only if ``a`` were known to lie in a family that ``w'`` is
    not in; nothing in the readings says which family. For every ``d'``, the finger
    ``a'(x) = a(x) + 2 (d - d') w'(x)`` read with the wedge at ``d'`` gives the same
    readings, and ``a'`` is a finger as plausible as ``a``: one side stiffer than the
    other, a bone off the axis, or a pad a little thicker on one side each make a smooth
    difference with a component along ``w'``. For the membrane, ``w'`` is a line, which
    the offset and rotation of the sides already hold; for this form it is ``-A/x``, and
    a finger one of whose sides has a larger ``A`` makes a multiple of ``ln x``, which
    the noise fit's fixed effects (offset, slope, quadratic and the wedge's ``-A/x``)
    fit to within the reading noise with a shift of the prior's size:
    ``tests/test_wedge_share.py`` recovers a known shift from a symmetric finger and
    fits a finger whose sides' ``A`` differ by 10 %, read without any shift, with a
    shift of more than half the default prior (``docs/calibration/wedge.md``, made by
    ``docs/calibration/scripts/wedge_study.py``, gives the sizes). So the shift is not
    identifiable apart from the finger's own asymmetry; it stays a prior (config
    ``noise.wedge_position_sd_mm``, an assumed default), and the fit table shows its
    weight.
    """
    X = np.stack([np.ones(trials.x.shape), -np.log(trials.x)], axis=-1)
    X = np.where(trials.mask[:, :, None], X, 0.0)
    z = np.sqrt(CHI2_1DOF_95)
    count = A_mm.size
    ends = {name: np.full(count, np.nan) for name in ("A_low", "A_high", "x0_low", "x0_high")}
    share, wedge_share = np.full(count, np.nan), np.full(count, np.nan)
    information = np.einsum("tik,til->tkl", X, X)
    ok = np.isfinite(A_mm) & (np.abs(np.linalg.det(information)) > 0)
    if ok.any():
        rows = np.flatnonzero(ok)
        inverse = np.linalg.inv(information[rows])
        Xr = X[rows]
        V = inverse @ trials.take(rows).quadratic(Xr) @ inverse
        A, a = A_mm[rows], intercept[rows]
        mean, spread = _wedge_moments(trials.x[rows], trials.mask[rows], trials.wedge_sd_mm)
        k = np.einsum("tkl,til,ti->tk", inverse, Xr, mean)
        # (X'X)^-1 X' of each quadrature node's centred term, then its weighted outer product
        h = np.einsum("tkl,til,tin->tkn", inverse, Xr, spread)
        stretch = 1.0 + k[:, 1]
        A = A / stretch
        a = a - A * k[:, 0]
        wedge = (A**2)[:, None, None] * np.einsum("tkn,tln->tkl", h, h)
        V = V + wedge
        sd_A = np.sqrt(np.maximum(V[:, 1, 1], 0.0)) / stretch
        with np.errstate(divide="ignore", invalid="ignore"):
            wedge_share[rows] = np.clip(wedge[:, 1, 1] / V[:, 1, 1], 0.0, 1.0)
        part = trials.take(rows)
        if part.prior_covariance is not None:
            # the priors' share of A's variance: shared offset, tilt, depth and the wedge
            prior = np.einsum("tik,tij,tjl->tkl", Xr, part.prior_covariance, Xr)
            prior = (inverse @ prior @ inverse)[:, 1, 1] + wedge[:, 1, 1]
            with np.errstate(divide="ignore", invalid="ignore"):
                share[rows] = np.clip(prior / V[:, 1, 1], 0.0, 1.0)
        ends["A_low"][rows], ends["A_high"][rows] = A - z * sd_A, A + z * sd_A
        with np.errstate(divide="ignore", invalid="ignore"):
            # ln x0 = a / A of the corrected line, as a function of the fitted (a, A)
            raw_A = A * stretch
            raw_a = a + A * k[:, 0]
            gradient = stretch[:, None] * np.stack([1.0 / raw_A, -raw_a / raw_A**2], axis=-1)
            sd_log = np.sqrt(np.maximum(np.einsum("tk,tkl,tl->t", gradient, V, gradient), 0.0))
            rising = A > 0
            ends["x0_low"][rows] = np.where(rising, np.exp(a / A - z * sd_log), np.nan)
            ends["x0_high"][rows] = np.where(rising, np.exp(a / A + z * sd_log), np.nan)
    intervals = {
        "A_ci_low_mm": ends["A_low"],
        "A_ci_high_mm": ends["A_high"],
        "x0_ci_low_mm": ends["x0_low"],
        "x0_ci_high_mm": ends["x0_high"],
    }
    return intervals, share, wedge_share


def fit_boussinesq_chunk(trials, depth_mm=None):
    """The Boussinesq line fitted to a chunk of trials (``depth_mm`` unused)."""
    x, y, n = trials.x, trials.y, trials.n
    log_x = np.log(x)
    # w = A ln x0 - A ln x is a straight line in ln x: linear least squares, centred
    mean_log_x = trials.sum(log_x) / n
    mean_y = trials.sum(y) / n
    centred = log_x - mean_log_x[:, None]
    spread = trials.sum(centred**2)
    single = spread == 0.0  # one distinct distance: the minimum-norm solution
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = trials.sum(centred * (y - mean_y[:, None])) / spread
    A_mm = np.where(single, -mean_log_x * mean_y / (1.0 + mean_log_x**2), -slope)
    intercept = np.where(single, mean_y / (1.0 + mean_log_x**2), mean_y + A_mm * mean_log_x)
    rising = A_mm > 0
    x0_mm = np.full(n.size, np.nan)
    x0_mm[rising] = np.exp(intercept[rising] / A_mm[rising])
    residual = y - (intercept[:, None] + (-log_x) * A_mm[:, None])
    residual[rising] = y[rising] - boussinesq_deflection_mm(
        x[rising], A_mm[rising, None], x0_mm[rising, None]
    )
    params = {"A_mm": A_mm, "x0_mm": x0_mm}
    share = wedge_share = None
    if trials.covariance is None:
        params.update(_boussinesq_intervals(trials, intercept, A_mm))
    else:
        intervals, share, wedge_share = _boussinesq_sandwich_intervals(trials, intercept, A_mm)
        params.update(intervals)
    return _ChunkFit(
        "boussinesq", trials, params, residual, prior_share=share, wedge_share=wedge_share
    )
