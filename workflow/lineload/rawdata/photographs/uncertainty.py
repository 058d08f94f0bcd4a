"""The digitiser's stated uncertainties: the registration's and each reading's standard
deviation, from least-squares residuals with their own autocovariance along the
outline (a sandwich estimate), and the scatter of the outline about a smooth trend.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__ = ["LOCAL_SCATTER_MM", "TREND_MM", "TREND_ORDER"]

#: How the digitiser states its uncertainties (docs/calibration/digitiser.md measures
#: them against rendered pairs): an outline's edge errors are its residual about a moving
#: quadratic over :data:`TREND_MM` of outline (long against the errors' own correlation,
#: which blur, smoothing and the skin's grain make a few pixels long: a shorter trend
#: follows them and hides their slow part; short against the profile's own bends), and
#: their local size is taken over :data:`LOCAL_SCATTER_MM` either side of a reading.
TREND_MM = 1.0


TREND_ORDER = 4


LOCAL_SCATTER_MM = 0.5


def _autocovariance(residual, blocks, max_lag):
    """Autocovariance of ``residual`` at lags 0..``max_lag``, pooled over the contiguous
    runs of column indices ``blocks`` (a gap between runs is not a lag)."""
    runs = np.split(residual, np.flatnonzero(np.diff(blocks) != 1) + 1)
    gamma = np.zeros(max_lag + 1)
    pairs = np.zeros(max_lag + 1)
    for run in runs:
        for lag in range(min(max_lag, run.size - 1) + 1):
            gamma[lag] += np.sum(run[: run.size - lag] * run[lag:])
            pairs[lag] += run.size - lag
    return gamma / np.maximum(pairs, 1.0)


def _correlation_lags(gamma):
    """The lags up to the first at which the autocovariance is no longer positive: the
    window of the integrated autocorrelation (beyond it the estimate is noise)."""
    stop = np.flatnonzero(gamma <= 0.0)
    return int(stop[0]) if stop.size else gamma.size


def _sandwich_covariance(design, residual, index, max_lag=200):
    """Covariance of a least-squares fit whose errors are correlated along the outline or
    the face: the sandwich ``(X'X)^-1 X' S X (X'X)^-1``, whose ``S`` holds the residual's
    own autocovariance up to its first non-positive lag (zero beyond).

    Parameters
    ----------
    design : numpy.ndarray
        ``(n, k)``: the fit's columns at each point.
    residual : numpy.ndarray
        What the fit left there.
    index : numpy.ndarray
        The points' integer places along the outline (columns) or the face (rows): gaps
        split the lags.
    """
    gamma = _autocovariance(residual, index, min(max_lag, residual.size // 4))
    lags = _correlation_lags(gamma)
    runs = np.split(np.arange(residual.size), np.flatnonzero(np.diff(index) != 1) + 1)
    middle = gamma[0] * design.T @ design
    for lag in range(1, lags):
        for run in runs:
            if run.size > lag:
                a, b = design[run[:-lag]], design[run[lag:]]
                middle += gamma[lag] * (a.T @ b + b.T @ a)
    bread = np.linalg.inv(design.T @ design)
    # the points' count over the correlation's integrated length: what is independent in
    # them, for a degrees-of-freedom correction of the residual's variance
    effective = residual.size * gamma[0] / max(gamma[0] + 2.0 * gamma[1:lags].sum(), 1e-300)
    return bread @ middle @ bread, float(effective)


def _registration_sd_mm(design, residual, columns, max_lag=200):
    """SD of the registration's vertical offset: least squares with errors correlated
    along the outline (:func:`_sandwich_covariance`).

    Parameters
    ----------
    design : numpy.ndarray
        ``(n, 2)``: the offset's and the shift's columns of the far columns.
    residual : numpy.ndarray
        What the registration left there (mm).
    columns : numpy.ndarray
        Their column indices (gaps split the lags).
    """
    variance = _sandwich_covariance(design, residual, columns, max_lag)[0][0, 0]
    return float(np.sqrt(max(variance, 0.0)))


def _trend_residual(z_mm, trend_px, split):
    """The outline's residual about a moving quadratic of ``trend_px`` columns, each
    side of column ``split`` on its own (a trend across the wedge's notch would take its
    bend for scatter); NaN where no edge was found."""
    from scipy.signal import savgol_filter

    residual = np.full(z_mm.shape, np.nan)
    for part in (slice(0, split), slice(split, z_mm.size)):
        z = z_mm[part]
        ok = np.isfinite(z)
        if ok.sum() < max(trend_px, 7):
            continue
        index = np.arange(z.size)
        filled = np.interp(index, index[ok], z[ok])
        window = min(trend_px, z.size) - (1 - min(trend_px, z.size) % 2)  # odd
        residual[part] = np.where(ok, filled - savgol_filter(filled, window, TREND_ORDER), np.nan)
    return residual


def _mean_variance_factor(residual, n_columns, trend_px):
    """How much larger the variance of a mean of ``n_columns`` edge errors is than the
    mean square of the same mean of their residual about the moving quadratic.

    The quadratic takes part of the errors with it, the more the longer they are
    correlated.  With the errors' correlation taken from the residual's own
    autocorrelation up to its first non-positive lag (zero beyond) and the moving
    quadratic's weights ``h`` (Savitzky-Golay), the mean's weights are ``b`` (``1/n``
    over ``n`` columns) on the errors and ``a = b - b * h`` on the residual: the factor
    is ``b' R b / a' R a``.
    """
    from scipy.linalg import toeplitz
    from scipy.signal import savgol_coeffs

    runs = np.isfinite(residual)
    if runs.sum() < 3 * trend_px:
        return float("nan")
    columns = np.flatnonzero(runs)
    gamma = _autocovariance(residual[runs], columns, min(trend_px, 200))
    lags = _correlation_lags(gamma)
    window = trend_px | 1
    h = savgol_coeffs(window, TREND_ORDER)
    b = np.zeros(window + n_columns - 1)
    b[window // 2 : window // 2 + n_columns] = 1.0 / n_columns
    a = b - np.convolve(np.ones(n_columns) / n_columns, h)  # the mean of the residual
    rho = np.zeros(b.size)
    rho[:lags] = gamma[:lags] / gamma[0]
    correlation = toeplitz(rho)
    return float((b @ correlation @ b) / (a @ correlation @ a))


def _local_variance(z_mm, n_columns, pixel_mm, split):
    """Each column's local variance (mm^2) of the mean of ``n_columns`` neighbouring
    columns' edge errors: the outline's residual about its moving quadratic
    (:func:`_trend_residual`), averaged over ``n_columns``, squared, averaged over
    ``LOCAL_SCATTER_MM`` either side and scaled for what the quadratic took
    (:func:`_mean_variance_factor`); NaN where too few columns."""
    trend_px = max(7, round(TREND_MM / pixel_mm))
    half_px = max(3, round(LOCAL_SCATTER_MM / pixel_mm))
    residual = _trend_residual(z_mm, trend_px, split)
    factor = _mean_variance_factor(residual, n_columns, trend_px)
    ok = np.isfinite(residual)
    means = ndimage.uniform_filter1d(np.where(ok, residual, 0.0), n_columns, mode="nearest")
    full = ndimage.uniform_filter1d(ok.astype(float), n_columns, mode="nearest") > 1 - 1e-9
    size = 2 * half_px + 1
    sums = ndimage.uniform_filter1d(np.where(full, means**2, 0.0), size, mode="nearest")
    counts = ndimage.uniform_filter1d(full.astype(float), size, mode="nearest")
    return np.where(counts * size >= 10, factor * sums / np.maximum(counts, 1e-12), np.nan)


def _reading_sds_mm(x, z_rest, z_load, dx, tip_x_mm, readings, window_mm):
    """Each reading's own SD (mm; the registration's shared error apart).

    A reading is the line through its columns of the resting outline's edge minus the
    loaded one's, taken at its distance (:func:`_sample`); the two photographs' errors
    are independent, so its variance is the sum of each outline's local variance of a
    mean over as many columns (:func:`_local_variance`), at the reading's columns (the
    resting outline's moved onto the loaded one's): a steep or glaring stretch, rougher
    than the rest, counts as rough as it is.  A line taken off its columns' centre
    varies more than their mean: by ``1 + n (x0 - mean)^2 / sum (x - mean)^2`` for
    independent errors (least squares), a bound for errors correlated along the outline.
    """
    pixel_mm = float(np.median(np.diff(x)))
    n = max(1, int(np.sum(np.abs(x - x[x.size // 2]) <= window_mm)))
    split = int(np.searchsorted(x, tip_x_mm))
    local = _local_variance(z_load, n, pixel_mm, split) + np.interp(
        x - dx, x, _local_variance(z_rest, n, pixel_mm, z_rest.size)
    )
    fallback = float(np.nanmax(local)) if np.isfinite(local).any() else float("nan")
    read = np.isfinite(z_load)
    sds = {}
    for side, sign in (("left", -1.0), ("right", 1.0)):
        variances = []
        for c in tip_x_mm + sign * readings[side][0]:
            at = float(np.nanmean(local[np.abs(x - c) <= max(window_mm, pixel_mm)]))
            columns = x[read & (np.abs(x - c) <= window_mm)]
            spread = float(np.sum((columns - columns.mean()) ** 2)) if columns.size else 0.0
            off = 1.0 + (columns.size * (c - columns.mean()) ** 2 / spread if spread > 0 else 0.0)
            variances.append((at if np.isfinite(at) else fallback) * off)
        sds[side] = np.sqrt(np.array(variances, dtype=float))
    return sds
