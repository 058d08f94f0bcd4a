"""The points a fit sees: the fit window, the padded batch of trials, their covariances.

Every fit reads the same points of a trial: those with ``0 < distance <= window`` and
a finite deflection (:func:`in_fit_window`, :func:`window_points`).  The intervals
may honour the covariance of those points under a noise model
(:func:`window_covariance`); the fits themselves stay ordinary least squares.

Many trials are fitted at once: their points are padded with NaN to a common width
(a multiple of 8) in a :class:`_Trials`, whose sums and quadratic forms leave the
padding out.
"""

from __future__ import annotations

import numpy as np

from lineload.fitting.optimize import CHI2_1DOF_95
from lineload.noise import average_covariances_mm2

__all__ = ["in_fit_window", "window_covariance", "window_covariances", "window_points"]

_TINY = np.finfo(float).tiny


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


def window_covariance(distance_mm, deflection_mm, depth_mm, window_mm, noise, n_sides=None):
    """The covariance of one trial's points inside its fit window, under a noise model.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        The trial's averaged profile (mm).
    depth_mm : float
        Indentation depth (mm).
    window_mm : float
        Outer edge of the fitted region (mm).
    noise : lineload.noise.NoiseModel
        The trial's noise model.
    n_sides : array_like, optional
        Sides read at each point (2 everywhere if not given).

    Returns
    -------
    numpy.ndarray
        ``(n, n)`` (mm^2), ``n`` the points with ``0 < distance <= window`` and a
        finite deflection, in their order (:meth:`NoiseModel.average_covariance_mm2`).
    """
    return window_covariances(
        [distance_mm], [deflection_mm], [depth_mm], [window_mm], [noise], [n_sides]
    )[0]


def window_covariances(distance_mm, deflection_mm, depth_mm, window_mm, noise, n_sides):
    """:func:`window_covariance` of many trials, each under its own noise model.

    Parameters
    ----------
    distance_mm, deflection_mm, n_sides : sequence of array_like
        One array per trial (an ``n_sides`` of None: 2 everywhere).
    depth_mm, window_mm : sequence of float
        One value per trial.
    noise : sequence of lineload.noise.NoiseModel
        One per trial.

    Returns
    -------
    list of numpy.ndarray
    """
    kept = []
    for x, y, window, sides in zip(distance_mm, deflection_mm, window_mm, n_sides, strict=True):
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        keep = in_fit_window(x, window) & np.isfinite(y)
        sides = np.full(x.shape, 2.0) if sides is None else np.asarray(sides, dtype=float)
        kept.append((x[keep], y[keep], sides[keep]))
    counts = np.array([len(x) for x, _, _ in kept], dtype=int)
    covariances = [None] * counts.size
    # trials of similar length together: the padded matrices stay small
    order = np.argsort(counts, kind="stable")
    for start in range(0, counts.size, _COVARIANCE_BLOCK):
        block = order[start : start + _COVARIANCE_BLOCK]
        width = int(counts[block].max(initial=0))
        padded = np.full((3, block.size, width), np.nan)
        for row, i in enumerate(block):
            for column, values in enumerate(kept[i]):
                padded[column, row, : counts[i]] = values
        computed = average_covariances_mm2(
            [noise[i] for i in block], padded[0], padded[2], padded[1],
            np.asarray(depth_mm, dtype=float)[block],
        )  # fmt: skip
        for row, i in enumerate(block):
            covariances[i] = computed[row, : counts[i], : counts[i]]
    return covariances


#: Trials whose covariances are computed together (:func:`window_covariances`).
_COVARIANCE_BLOCK = 256


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
    ``intervals`` False asks the solvers for the fits alone (the refits that only
    follow a parameter across windows): the searched fits then skip their
    intervals, which are NaN.
    """

    def __init__(
        self,
        x,
        y,
        mask,
        n,
        x_max,
        covariance=None,
        wedge_sd_mm=0.0,
        prior_covariance=None,
        intervals=True,
    ):
        self.x, self.y, self.mask, self.n, self.x_max = x, y, mask, n, x_max
        self.covariance = covariance
        self.wedge_sd_mm = wedge_sd_mm
        self.prior_covariance = prior_covariance
        self.intervals = intervals

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
        intervals=True,
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
        return cls(x, y, mask, counts, x_max, covariance, wedge_sd_mm, prior, intervals)

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
            self.intervals,
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
