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

Batches
-------
Every algorithm here runs on many trials at once (:func:`fit_trials`,
:func:`fit_windowed`, :func:`fit_batch`); the single-trial functions
(:func:`fit_waterbed`, :func:`fit_trial`, ...) are the same code with a batch
of one.  The trials' points are padded to a common length and each step is done
for all trials together by :mod:`lineload.fitting.optimize`.  A trial's numbers do not
depend on its batch beyond rounding: two batchings agree to the tolerance of
:func:`lineload.fitting.optimize.solution_tolerance`, not to the last bit.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from lineload.fitting.optimize import CHI2_1DOF_95, likelihood_interval, minimize_bounded
from lineload.models import (
    MAX_ONE_TO_ONE_RATIO,
    TABLE_MODELS,
    arc_deflection_mm,
    arc_geometry,
    boussinesq_deflection_mm,
    shifted_deflection_mm,
    waterbed_deflection_mm,
)

__all__ = [
    "AT_BOUND_RTOL",
    "CHI2_1DOF_95",
    "FIT_COLUMNS",
    "MODELS",
    "BatchFits",
    "FitResult",
    "at_search_bound",
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
    "window_points",
]

#: Largest membrane half-width searched by the iterative fits (exact arc, and the
#: parabola with W0 free), as a multiple of the smallest admissible one. The
#: fixed-W0 parabola needs no such bound: its minimum is found exactly.
L_SEARCH_SPAN = 1000.0

#: Trials fitted together (after sorting by number of points, so that little is
#: padded).
CHUNK_TRIALS = 1024

#: Largest number of elements of one temporary array while an objective is evaluated
#: for many trials and many L at once (2**14 doubles: 128 KiB, within a core's
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
    "boussinesq": (
        ("A_mm", "x0_mm", "A_ci_low_mm", "A_ci_high_mm", "x0_ci_low_mm", "x0_ci_high_mm"),
        2,
        2,
    ),
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
    chi2 : float
        With a covariance ``C`` only: ``r' C^-1 r`` of the residuals at the
        minimum (how far the misfit is beyond the noise); NaN without one.
    at_bound : bool
        Whether the fitted L ends on a bound of its search (:func:`at_search_bound`):
        its interval is then one-sided and the value itself is not a measurement.
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
    chi2: float = np.nan
    at_bound: bool = False


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


def _padded_covariances(covariance_mm2, counts, width):
    """Each trial's covariance, padded with zeros to ``width``.

    Raises
    ------
    ValueError
        If a covariance is not a finite ``(n, n)`` symmetric positive-definite matrix.
    """
    padded = np.zeros((counts.size, width, width))
    for i, (matrix, n) in enumerate(zip(covariance_mm2, counts, strict=True)):
        matrix = np.asarray(matrix, dtype=float)
        if matrix.shape != (n, n) or not np.all(np.isfinite(matrix)):
            raise ValueError(f"trial {i}: the covariance must be a finite {n} x {n} matrix")
        padded[i, :n, :n] = matrix
    eye = np.eye(width) * (np.arange(width)[None, :] >= counts[:, None])[:, None, :]
    try:
        np.linalg.cholesky(padded + eye)
    except np.linalg.LinAlgError:
        raise ValueError("every covariance must be symmetric positive definite") from None
    return padded


class _Trials:
    """Points of many trials padded to a common width (a multiple of 8) with NaN.

    Padded entries cost nothing in the iterative solves (a NaN distance is not
    iterated on) and are left out of every sum and maximum (through ``mask``).
    ``covariance`` holds each trial's covariance (zero-padded) when the intervals
    are to honour it, or is None (independent errors of unknown variance).
    ``wedge_sd_mm`` is the standard deviation of the wedge's misplacement along
    the outline, which the log-singular Boussinesq form feels to second order.
    """

    def __init__(
        self, x, y, mask, n, x_max, covariance=None, wedge_sd_mm=0.0, prior_covariance=None
    ):
        self.x, self.y, self.mask, self.n, self.x_max = x, y, mask, n, x_max
        self.covariance = covariance
        self.wedge_sd_mm = wedge_sd_mm
        self.prior_covariance = prior_covariance

    @classmethod
    def from_flat(
        cls,
        x_mm,
        y_mm,
        counts,
        offsets,
        covariance_mm2=None,
        wedge_sd_mm=0.0,
        prior_covariance_mm2=None,
    ):
        """Trials ``i`` = ``x_mm[offsets[i]:offsets[i] + counts[i]]`` (each with a point).

        ``prior_covariance_mm2``, if given, is the part of each covariance that the
        stated priors make (shared offset, tilt, depth): what :func:`_prior_share` reads.
        """
        width = _padded_width(counts.max())
        column = np.arange(width)
        mask = column < counts[:, None]
        index = offsets[:, None] + np.minimum(column, counts[:, None] - 1)
        x = np.where(mask, x_mm[index], np.nan)
        y = np.where(mask, y_mm[index], np.nan)
        covariance = (
            None if covariance_mm2 is None else _padded_covariances(covariance_mm2, counts, width)
        )
        prior = None
        if covariance is not None and prior_covariance_mm2 is not None:
            prior = np.zeros_like(covariance)
            for i, (matrix, n) in enumerate(zip(prior_covariance_mm2, counts, strict=True)):
                prior[i, :n, :n] = matrix
        x_max = np.fmax.reduce(x, axis=1)
        return cls(x, y, mask, counts, x_max, covariance, wedge_sd_mm, prior)

    def take(self, rows):
        covariance = None if self.covariance is None else self.covariance[rows]
        prior = None if self.prior_covariance is None else self.prior_covariance[rows]
        return _Trials(
            self.x[rows],
            self.y[rows],
            self.mask[rows],
            self.n[rows],
            self.x_max[rows],
            covariance,
            self.wedge_sd_mm,
            prior,
        )

    @property
    def width(self):
        return self.x.shape[1]

    def sum(self, values, rows=slice(None)):
        """Sum over each trial's points of ``values`` (rows ``rows``, points last)."""
        mask = self.mask[rows]
        mask = mask.reshape(mask.shape[:1] + (1,) * (values.ndim - 2) + mask.shape[1:])
        return np.sum(np.where(mask, values, 0.0), axis=-1)

    def masked(self, values, rows=slice(None)):
        """``values`` at each trial's points, zero in the padding."""
        mask = self.mask[rows]
        mask = mask.reshape(mask.shape[:1] + (1,) * (values.ndim - 2) + mask.shape[1:])
        return np.where(mask, values, 0.0)

    def chi2(self, residual, rows=slice(None)):
        """Sum of squares over each trial's points; NaN -> inf."""
        total = np.sum(self.masked(residual, rows) ** 2, axis=-1)
        return np.where(np.isfinite(total), total, np.inf)

    def quadratic(self, left, right=None):
        """``left' C right`` of each trial (C its covariance), for columns ``(T, n)``
        or ``(T, n, k)`` (then ``(T, k, k)``)."""
        right = left if right is None else right
        if left.ndim == 2:
            left, right = self.masked(left), self.masked(right)
            return np.einsum("ti,tij,tj->t", left, self.covariance, right)
        mask = self.mask[:, :, None]
        left, right = np.where(mask, left, 0.0), np.where(mask, right, 0.0)
        return np.einsum("tik,tij,tjl->tkl", left, self.covariance, right)

    def generalised_chi2(self, residual):
        """``r' C^-1 r`` of each trial's residuals: how far the misfit is beyond the noise."""
        eye = np.eye(self.width) * (~self.mask)[:, None, :]
        # NaN for a trial whose own points have no residual (no fit); the padding is not its
        r = np.where(self.mask & ~np.isfinite(residual), np.nan, self.masked(residual))
        with np.errstate(invalid="ignore"):
            solved = np.linalg.solve(self.covariance + eye, r[..., None])[..., 0]
        return np.sum(r * solved, axis=-1)

    def threshold(self, chi2_min, rows=slice(None), delta=None, chi2=CHI2_1DOF_95):
        """The objective's value at the ends of the 95 % interval.

        With a covariance: ``SSE_min + delta``, ``delta`` from
        :func:`_sandwich_delta`.  Without: ``SSE_min exp(chi2 / n)``, the profile
        likelihood with the variance unknown.
        """
        if self.covariance is not None:
            return chi2_min + delta
        return np.maximum(chi2_min, _TINY) * np.exp(chi2 / self.n[rows])


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
    sse = np.sum(np.where(mask, residual_mm, 0.0) ** 2, axis=-1)
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
    residual_mm = np.asarray(residual_mm, dtype=float).reshape(1, -1)
    mask = np.ones(residual_mm.shape, dtype=bool)
    measures = _measures(residual_mm, mask, n_params)
    return {name: _python_float(values[0]) for name, values in measures.items()}


# --------------------------------------------------------------------------- the fits of a chunk


class _ChunkFit:
    """One model fitted to the trials of a :class:`_Trials` chunk."""

    def __init__(
        self, model, trials, params, residual_mm, errors=None, at_bound=None, prior_share=None
    ):
        self.model = model
        self.trials = trials
        self.params = params
        count = trials.n.size
        self.at_bound = np.zeros(count, dtype=bool) if at_bound is None else at_bound
        self.prior_share = np.full(count, np.nan) if prior_share is None else prior_share
        self.residual_mm = residual_mm
        self.errors = errors or {}
        self.measures = _measures(residual_mm, trials.mask, MODELS[model][1])
        self.chi2 = (
            np.full(trials.n.size, np.nan)
            if trials.covariance is None
            else trials.generalised_chi2(residual_mm)
        )


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


def _fit_waterbed_chunk(trials, depth_mm):
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


def _curve_objective(curve, trials, depth_mm):
    """Chi-square of ``curve(x, W0, L)`` for trials ``rows`` at L (R, K)."""

    def objective(L_mm, rows):
        def evaluate(part):
            r = rows[part]
            model = curve(trials.x[r, None, :], depth_mm[r, None, None], L_mm[part, :, None])
            return trials.chi2(trials.y[r, None, :] - model, r)

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    return objective


def _arc_objective(trials, depth_mm):
    """:func:`_curve_objective` of the arc, its circle solved once per (W0, L)."""

    def objective(L_mm, rows):
        geometry = arc_geometry(depth_mm[rows, None], L_mm)

        def evaluate(part):
            r = rows[part]
            model = arc_deflection_mm(
                trials.x[r, None, :],
                depth_mm[r, None, None],
                L_mm[part, :, None],
                geometry={name: values[part, :, None] for name, values in geometry.items()},
            )
            return trials.chi2(trials.y[r, None, :] - model, r)

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    return objective


def _fit_by_search(model, trials, objective, residual_at, L_lo, lower_bound=None, delta_at=None):
    """One-parameter fit in L by the grid and zoom over ``[L_lo, L_SEARCH_SPAN max(x)]``.

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


def _fit_arc_chunk(trials, depth_mm):
    objective = _arc_objective(trials, depth_mm)
    return _fit_curve_chunk("arc", arc_deflection_mm, objective, trials, depth_mm, trials.x_max)


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
    """95 % intervals on A and x0 given the points' covariance ``C`` (the sandwich), and
    the share of A's variance that the stated priors make (NaN without their split).

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
    a little, and it rests on the prior (its share of A's variance is reported
    with the others', :func:`_prior_share`).
    """
    X = np.stack([np.ones(trials.x.shape), -np.log(trials.x)], axis=-1)
    X = np.where(trials.mask[:, :, None], X, 0.0)
    z = np.sqrt(CHI2_1DOF_95)
    count = A_mm.size
    ends = {name: np.full(count, np.nan) for name in ("A_low", "A_high", "x0_low", "x0_high")}
    share = np.full(count, np.nan)
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
    return intervals, share


def _fit_boussinesq_chunk(trials, depth_mm=None):
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
    share = None
    if trials.covariance is None:
        params.update(_boussinesq_intervals(trials, intercept, A_mm))
    else:
        intervals, share = _boussinesq_sandwich_intervals(trials, intercept, A_mm)
        params.update(intervals)
    return _ChunkFit("boussinesq", trials, params, residual, prior_share=share)


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
    chi2 : numpy.ndarray
        ``r' C^-1 r`` of the residuals at the minimum, given a covariance ``C``;
        NaN without one.
    n_points : numpy.ndarray of int
        Points of each trial.
    fitted : numpy.ndarray of bool
        Whether the trial has a fit (enough points, an admissible L).
    at_bound : numpy.ndarray of bool
        Whether the fitted L ends on a bound of its search (False for a model
        without L, and for a trial without a fit).
    prior_share : numpy.ndarray
        Share of the variance of the model's first parameter (L, or A) that the
        stated priors make (shared offset, tilt and depth error; for A also the
        wedge's position); NaN without a noise model.
    errors : dict of int to str
        Why a trial has no fit, by trial index.
    """

    def __init__(self, model, n_points):
        count = n_points.size
        self.model = model
        self.params = {name: np.full(count, np.nan) for name in MODELS[model][0]}
        self.measures = {name: np.full(count, np.nan) for name in _MEASURES}
        self.chi2 = np.full(count, np.nan)
        self.n_points = n_points
        self.fitted = np.zeros(count, dtype=bool)
        self.at_bound = np.zeros(count, dtype=bool)
        self.prior_share = np.full(count, np.nan)
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
        self.chi2[fitted] = chunk.chi2[ok]
        self.at_bound[fitted] = chunk.at_bound[ok]
        self.prior_share[fitted] = chunk.prior_share[ok]
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
            chi2=_python_float(self.chi2[i]),
            at_bound=bool(self.at_bound[i]),
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


def _fit_flat(
    x_mm,
    y_mm,
    counts,
    depth_mm,
    models,
    covariance_mm2=None,
    wedge_sd_mm=0.0,
    prior_covariance_mm2=None,
):
    """Fit ``models`` to trials given as concatenated points and counts (``prior_covariance_mm2``:
    the priors' part of each covariance, for the fits' ``prior_share``)."""
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
        covariance = None if covariance_mm2 is None else [covariance_mm2[i] for i in chunk]
        prior = None
        if prior_covariance_mm2 is not None:
            prior = [prior_covariance_mm2[i] for i in chunk]
        trials = _Trials.from_flat(
            x_mm, y_mm, counts[chunk], offsets[chunk], covariance, wedge_sd_mm, prior
        )
        for model in models:
            enough = counts[chunk] >= MODELS[model][2]
            if not enough.any():
                continue
            part = trials if enough.all() else trials.take(np.flatnonzero(enough))
            fits[model]._add(chunk[enough], _CHUNK_FITS[model](part, depth_mm[chunk[enough]]))
    return fits


def fit_batch(distance_mm, deflection_mm, depth_mm=None, models=tuple(MODELS), covariance_mm2=None):
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
    covariance_mm2 : sequence of array_like, optional
        The covariance of each trial's deflections (mm^2), an ``(n, n)`` matrix
        for a trial of ``n`` points: the intervals honour it (the fits stay
        least squares), taking it as known.

    Returns
    -------
    dict of str to BatchFits
        By model.  A trial with fewer points than a model needs, or without an
        admissible L, has no fit (``BatchFits.result`` raises the ValueError the
        single-trial function raises).

    Raises
    ------
    ValueError
        For a trial whose arrays differ in shape, a distance <= 0, a value that
        is not finite, or a covariance of the wrong shape or not positive
        definite.
    """
    models = tuple(models)
    x_mm, y_mm, counts = _as_trials(distance_mm, deflection_mm)
    if not (np.all(np.isfinite(x_mm)) and np.all(np.isfinite(y_mm))):
        raise ValueError("distances and deflections must be finite")
    if np.any(x_mm <= 0):
        raise ValueError("distances must be > 0 (the load point itself is not fitted)")
    if covariance_mm2 is not None and len(covariance_mm2) != counts.size:
        raise ValueError("covariance_mm2 must hold one matrix per trial")
    if depth_mm is None:
        if set(models) & {"waterbed", "shifted", "arc"}:
            raise ValueError("the fixed-depth fits need depth_mm")
        depth_mm = np.nan
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), counts.shape)
    return _fit_flat(x_mm, y_mm, counts, depth_mm, models, covariance_mm2)


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


def _fit_one(model, distance_mm, deflection_mm, depth_mm=np.nan, covariance_mm2=None):
    x, y = _as_points(distance_mm, deflection_mm, minimum=MODELS[model][2])
    covariance = None if covariance_mm2 is None else [covariance_mm2]
    fits = _fit_flat(x, y, np.array([x.size]), np.array([float(depth_mm)]), (model,), covariance)
    return fits[model].result(0)


def fit_waterbed(distance_mm, deflection_mm, depth_mm, covariance_mm2=None):
    """Fit the small-slope waterbed (eq. 19) with W0 fixed: exact global least squares.

    With ``u = 1 / L`` the model ``W0 (3 u**2 x**2 - 4 u x + 1)`` is quadratic
    in ``u``, so the sum of squared residuals is a quartic in ``u``.
    Its global minimum over ``0 <= u <= 1 / max(x)`` is at a real root of the
    cubic derivative or at an end of that interval; all candidates are compared
    exactly, so no start value or iterative optimiser is involved.  ``u = 0``
    means a flat membrane (``L`` infinite).

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}``, the
        last two the 95 % likelihood interval (see the module's notes).
    """
    return _fit_one("waterbed", distance_mm, deflection_mm, depth_mm, covariance_mm2)


def fit_arc(distance_mm, deflection_mm, depth_mm, covariance_mm2=None):
    """Fit the exact circular-arc waterbed with W0 fixed and L free.

    The one-dimensional least-squares problem in ``L`` over
    ``[max(x), 1000 max(x)]`` is solved by :func:`lineload.fitting.optimize.minimize_bounded`.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}`` with
        the 95 % likelihood interval.
    """
    return _fit_one("arc", distance_mm, deflection_mm, depth_mm, covariance_mm2)


def fit_shifted(distance_mm, deflection_mm, depth_mm, covariance_mm2=None):
    """Fit the small-slope waterbed in measured coordinates, W0 fixed and L free.

    The model is eq. 19's ``W(X)`` at ``x = X + U(X)`` (eq. 20), i.e.
    :func:`lineload.models.shifted_deflection_mm`.  It is defined for
    ``L > sqrt(6) W0`` only (where ``x(X)`` is one-to-one), so the search runs
    over ``[max(max(x), sqrt(6) W0 (1 + 1e-9)), 1000 max(x)]``.  A fit that ends
    on the lower bound means the data want a membrane too narrow for the
    small-slope solution.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}`` with
        the 95 % likelihood interval.
    """
    return _fit_one("shifted", distance_mm, deflection_mm, depth_mm, covariance_mm2)


def fit_waterbed_free_depth(distance_mm, deflection_mm, covariance_mm2=None):
    """Fit the small-slope waterbed with both W0 and L free.

    For a given L the model ``W0 g(x)``, ``g = 3 s**2 - 4 s + 1``, is linear in
    W0, whose best value is ``sum(y g) / sum(g**2)``; what remains is a one-dimensional problem in L
    (``L >= max(x)``).  The interval on L profiles W0 out.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two.
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm", "L_ci_low_mm", "L_ci_high_mm", "W0_mm"}``.
    """
    return _fit_one("waterbed_free_depth", distance_mm, deflection_mm, np.nan, covariance_mm2)


def fit_boussinesq(distance_mm, deflection_mm, covariance_mm2=None):
    """Fit the modified Boussinesq profile ``A ln(x0 / x)``: linear least squares.

    The model is a straight line in ``ln x``: ``w = A ln x0 - A ln x``, so the
    fit is an exact linear regression (centred, in closed form).  ``x0`` is
    reported as NaN when the slope has the wrong sign (``A <= 0``), where the
    form has no zero crossing.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two distinct.
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"A_mm": A, "x0_mm": x0}``.
    """
    return _fit_one("boussinesq", distance_mm, deflection_mm, np.nan, covariance_mm2)


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
    "waterbed_L_at_bound",
    "waterbed_L_prior_share",
    "waterbed_L_window_min_mm",
    "waterbed_L_window_max_mm",
    "waterbed_rmse_mm",
    "waterbed_max_abs_residual_mm",
    "waterbed_aicc",
    "shifted_L_mm",
    "shifted_L_ci_low_mm",
    "shifted_L_ci_high_mm",
    "shifted_L_at_bound",
    "shifted_L_prior_share",
    "shifted_L_window_min_mm",
    "shifted_L_window_max_mm",
    "shifted_rmse_mm",
    "shifted_max_abs_residual_mm",
    "shifted_aicc",
    "arc_L_mm",
    "arc_L_ci_low_mm",
    "arc_L_ci_high_mm",
    "arc_L_at_bound",
    "arc_L_prior_share",
    "arc_L_window_min_mm",
    "arc_L_window_max_mm",
    "arc_rmse_mm",
    "arc_max_abs_residual_mm",
    "arc_aicc",
    "boussinesq_A_mm",
    "boussinesq_x0_mm",
    "boussinesq_A_ci_low_mm",
    "boussinesq_A_ci_high_mm",
    "boussinesq_A_prior_share",
    "boussinesq_x0_ci_low_mm",
    "boussinesq_x0_ci_high_mm",
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


def _window_covariances(distance_mm, deflection_mm, depth_mm, window_mm, noise, n_sides):
    """Each trial's covariance (:meth:`NoiseModel.average_covariance_mm2`) on its window,
    under its own noise model (``noise``: one per trial)."""
    covariances = []
    for x, y, depth, window, sides, model in zip(
        distance_mm, deflection_mm, depth_mm, window_mm, n_sides, noise, strict=True
    ):
        x, y, sides = (np.asarray(v, dtype=float) for v in (x, y, sides))
        keep = in_fit_window(x, window) & np.isfinite(y)
        covariances.append(model.average_covariance_mm2(x[keep], sides[keep], y[keep], depth))
    return covariances


def fit_windowed(
    distance_mm,
    deflection_mm,
    depth_mm,
    window_mm,
    models=tuple(MODELS),
    noise=None,
    n_sides=None,
):
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
    noise : lineload.noise.NoiseModel or sequence of NoiseModel, optional
        The digitising noise, one model for every trial or one per trial: the
        intervals honour each trial's covariance (the fits themselves stay least
        squares; see the module's notes).  Without it, least squares with
        intervals from the residuals (independent errors).
    n_sides : sequence of array_like, optional
        With ``noise``: how many sides were read at each point of each trial
        (2 everywhere if not given).

    Returns
    -------
    dict
        ``n_points`` and ``max_distance_mm`` (arrays by trial, NaN for a trial
        without points) and each model's :class:`BatchFits` by its name.
    """
    x_mm, y_mm, counts = window_points(distance_mm, deflection_mm, window_mm)
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), counts.shape)
    covariance_mm2, wedge_sd_mm, prior_covariance_mm2 = None, 0.0, None
    if noise is not None:
        if not isinstance(noise, (list, tuple)):
            noise = [noise] * counts.size
        if len(noise) != counts.size:
            raise ValueError("noise must be one model or one per trial")
        # a dataset's prior: the same in every trial's model
        wedge_sd_mm = max((n.wedge_position_sd_mm for n in noise), default=0.0)
        if n_sides is None:
            n_sides = [np.full(np.shape(x), 2.0) for x in distance_mm]
        window = np.broadcast_to(np.asarray(window_mm, dtype=float), counts.shape)
        covariance_mm2 = _window_covariances(
            distance_mm, deflection_mm, depth_mm, window, noise, n_sides
        )
        priors_only = [n.priors_only() for n in noise]
        prior_covariance_mm2 = _window_covariances(
            distance_mm, deflection_mm, depth_mm, window, priors_only, n_sides
        )
    fits = _fit_flat(
        x_mm,
        y_mm,
        counts,
        depth_mm,
        tuple(models),
        covariance_mm2,
        wedge_sd_mm,
        prior_covariance_mm2,
    )
    max_distance_mm = np.full(counts.size, np.nan)
    some = counts > 0
    if some.any():
        max_distance_mm[some] = np.maximum.reduceat(x_mm, (np.cumsum(counts) - counts)[some])
    return {"n_points": counts, "max_distance_mm": max_distance_mm, **fits}


#: The fits whose L the fit table follows across other windows (:func:`fit_trials`).
WINDOW_MODELS = ("waterbed", "shifted", "arc")


def fit_trials(
    distance_mm,
    deflection_mm,
    depth_mm,
    window_mm,
    noise=None,
    n_sides=None,
    other_windows_mm=(),
):
    """Fit every model of the fit table to many trials, each on its windowed points.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm), W0 of the waterbed fits.
    window_mm : float or array_like
        Points with ``0 < distance <= window_mm`` are fitted.
    noise : lineload.noise.NoiseModel or sequence of NoiseModel, optional
        The digitising noise, for all trials or per trial (the intervals honour it;
        see :func:`fit_windowed`).
    n_sides : sequence of array_like, optional
        Sides read at each point of each trial (with ``noise``).
    other_windows_mm : sequence of float or None, optional
        Further windows (None or infinity: the whole profile) in which the waterbed
        fits' L is found again: ``{model}_L_window_min_mm`` and ``_max_mm`` give
        the smallest and largest L over these and ``window_mm`` (L is the
        half-width *for a window*; the spread is a sensitivity, not part of the
        95 % interval).  Without any, those columns equal L.

    Returns
    -------
    list of dict
        One row per trial, as :func:`fit_trial` gives it.
    """
    fits = fit_windowed(
        distance_mm, deflection_mm, depth_mm, window_mm, TABLE_MODELS, noise, n_sides
    )
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
        first = next(iter(fit.params))
        columns[f"{model}_{first.removesuffix('_mm')}_prior_share"] = fit.prior_share.tolist()
        if "L_mm" in fit.params:
            columns[f"{model}_L_at_bound"] = fit.at_bound.tolist()
    spread = {model: [fits[model].params["L_mm"]] for model in WINDOW_MODELS}
    for other in other_windows_mm:
        other = np.inf if other is None else float(other)
        refit = fit_windowed(distance_mm, deflection_mm, depth_mm, other, WINDOW_MODELS)
        for model in WINDOW_MODELS:
            spread[model].append(refit[model].params["L_mm"])
    for model, values in spread.items():
        values = np.array(values)
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a trial without any fit
            columns[f"{model}_L_window_min_mm"] = np.nanmin(values, axis=0).tolist()
            columns[f"{model}_L_window_max_mm"] = np.nanmax(values, axis=0).tolist()
    for name, values in columns.items():
        if name != "n_points" and not name.endswith("_at_bound"):
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
