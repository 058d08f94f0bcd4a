"""The wedge's tip in a loaded photograph: where its two faces meet against the
background, sought only around the notch (where the loaded outline lies furthest below
the resting one), with the standard error of the faces' crossing.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from lineload.rawdata.photographs.edges import _peak_offset
from lineload.rawdata.photographs.files import ImageError
from lineload.rawdata.photographs.uncertainty import _sandwich_covariance

__all__ = ["APEX_SEARCH_MM"]

#: How far from the notch (mm) the wedge's apex is sought (:func:`_wedge_apex_mm`).
APEX_SEARCH_MM = 1.0


def _notch_mm(x_mm, z_rest_mm, z_load_mm):
    """x where the loaded outline lies furthest below the resting one (over 0.1 mm of
    columns): the notch the wedge made, before any registration (a shift between the
    shots moves the skin by far less than the wedge does)."""
    gap = z_rest_mm - z_load_mm
    ok = np.isfinite(gap)
    if ok.sum() < 10:
        ok = np.isfinite(z_load_mm)
        if ok.sum() < 10:
            return float(np.mean(x_mm))
        gap = -z_load_mm
    spacing = float(np.median(np.diff(x_mm)))
    filled = np.interp(x_mm, x_mm[ok], gap[ok])
    size = max(3, round(0.1 / spacing) | 1)
    return float(x_mm[np.argmax(ndimage.uniform_filter1d(filled, size, mode="nearest"))])


def _robust_line(heights, columns, pixel_mm):
    """``x = a z + b`` through one face's points, points more than 3 robust SDs (at least
    a pixel) off dropped twice; its fit, the fit's covariance (the points' errors
    correlated down the face: :func:`_sandwich_covariance`), the kept points' count and
    their residual SD."""
    keep = np.ones(heights.size, dtype=bool)
    for _ in range(3):
        if keep.sum() < 10:
            return None
        a, b = np.polyfit(heights[keep], columns[keep], 1)
        residual = columns - (a * heights + b)
        spread = 1.4826 * np.median(np.abs(residual[keep]))
        keep = np.abs(residual) <= max(3.0 * spread, pixel_mm)
    if keep.sum() < 10:
        return None
    a, b = np.polyfit(heights[keep], columns[keep], 1)
    residual = columns[keep] - (a * heights[keep] + b)
    sd = float(np.std(residual, ddof=2))
    # rows' errors correlate through the smoothing and the blur: the fit's covariance is
    # the sandwich with the residual's own autocovariance down the face (an AR(1) chain
    # fitted to the lag-1 correlation alone overstated it: docs/calibration/digitiser.md)
    rows = np.rint((heights[0] - heights[keep]) / pixel_mm).astype(int)
    design = np.column_stack([heights[keep], np.ones(int(keep.sum()))])
    covariance, effective = _sandwich_covariance(design, residual, rows)
    # the residual's variance is that of the points about a line fitted to them, lower
    # than their errors' by the line's 2 parameters out of the effective count
    covariance = covariance * effective / max(effective - 2.0, 1.0)
    return a, b, covariance, int(keep.sum()), sd


def _wedge_apex_mm(
    smooth,
    scene,
    z_mm,
    smoothing_px,
    notch_x_mm,
    excluded=None,
    half_window_mm=1.5,
    search_mm=APEX_SEARCH_MM,
    centre_mm=0.3,
):
    """x of the wedge's apex, where its two faces meet, and its standard error; None if no
    wedge is seen.

    The wedge is sought only around the notch (``notch_x_mm``, :func:`_notch_mm`): above
    the skin within ``search_mm`` of the notch, its middle is the darkest column within
    ``centre_mm`` of it (where the wedge fills every row: a bar crossing its face
    further out may darken a column more), and an apex more than ``search_mm`` from the
    notch is no apex (None: the notch's own tip is taken instead; glare near the tip can
    put the notch 0.3 mm off).  In each
    row, its left face is the first strong fall in brightness met going left from that
    column (within ``half_window_mm``), its right face the first strong rise going right
    (each refined by a parabola); a straight line through each face's points (robustly:
    a scale bar's tick or a label in a row is dropped as an outlier), extended down to
    where they cross, gives the apex.  Its standard error comes from the scatter of the
    faces' points about their lines.  ``smooth`` is the loaded image as its outline was
    sought in (:func:`_smoothed`); ``excluded`` pixels (:func:`excluded_mask`) hold no
    face.
    """
    ppmm = scene.pixels_per_mm
    pixel_mm = 1.0 / ppmm
    x = scene.column_x_mm
    near = np.abs(x - notch_x_mm) <= search_mm + half_window_mm
    if not np.isfinite(z_mm[near]).any():
        return None
    skin_top = float(np.nanmax(z_mm[near]))
    last_row = int((scene.z0_mm - skin_top) * ppmm - 4 * smoothing_px)
    rows = np.arange(2, last_row)
    if rows.size < 10:
        return None
    lo_search = max(int((notch_x_mm - centre_mm - scene.x0_mm) * ppmm), 0)
    hi_search = min(int((notch_x_mm + centre_mm - scene.x0_mm) * ppmm) + 1, smooth.shape[1])
    if hi_search - lo_search < 3:
        return None
    centre = lo_search + int(np.argmin(smooth[rows, lo_search:hi_search].mean(axis=0)))
    rise = smooth[:, 1:] - smooth[:, :-1]  # between columns c and c + 1
    if excluded is not None:  # no face in a declared region
        rise = np.where(excluded[:, 1:] | excluded[:, :-1], 0.0, rise)
    reach = int(half_window_mm * ppmm)
    points = {-1.0: ([], []), 1.0: ([], [])}
    bounds, noise = {}, {}
    for sign in (-1.0, 1.0):
        lo, hi = (centre, centre + reach) if sign > 0 else (centre - reach, centre)
        bounds[sign] = lo, hi = max(lo, 1), min(hi, rise.shape[1] - 1)
        if hi - lo >= 4:  # the rise's noise over the rows and columns searched
            block = rise[rows, lo:hi]
            noise[sign] = 1.4826 * float(np.median(np.abs(block - np.median(block))))
    for row in rows:
        for sign in (-1.0, 1.0):
            lo, hi = bounds[sign]
            if hi - lo < 4:
                continue
            # the left face darkens going right, the right face brightens: both peak here
            segment = sign * rise[row, lo:hi]
            strong = max(5.0 * noise[sign], 0.3 * float(segment.max()), 1e-3)
            peaks = np.flatnonzero(
                (segment[1:-1] >= segment[:-2])
                & (segment[1:-1] > segment[2:])
                & (segment[1:-1] >= strong)
            )
            if peaks.size == 0:
                continue
            # the face is the first strong edge met going out from inside the wedge (a
            # scale bar's tick or a label further out may be stronger)
            c = int(peaks[0] if sign > 0 else peaks[-1]) + 1
            offset = float(_peak_offset(segment[c - 1], segment[c], segment[c + 1]))
            column = lo + c + 0.5 + offset  # between c and c + 1
            points[sign][0].append(scene.z0_mm - (row + 0.5) / ppmm)
            points[sign][1].append(scene.x0_mm + (column + 0.5) / ppmm)
    lines = []
    for sign in (-1.0, 1.0):
        heights, columns = (np.asarray(v) for v in points[sign])
        if heights.size < 10:
            return None
        fit = _robust_line(heights, columns, pixel_mm)
        if fit is None:
            return None
        a, b, covariance, kept, sd = fit
        if kept < 0.5 * heights.size or sd > pixel_mm or sign * a <= 0:
            return None  # not a straight face opening upward: no wedge seen
        lines.append((a, b, covariance))

    def apex(p):
        a1, b1, a2, b2 = p
        z = (b2 - b1) / (a1 - a2)
        return a1 * z + b1

    params = np.array([lines[0][0], lines[0][1], lines[1][0], lines[1][1]])
    covariance = np.zeros((4, 4))
    covariance[:2, :2], covariance[2:, 2:] = lines[0][2], lines[1][2]
    steps = 1e-6 * np.maximum(np.abs(params), 1.0)
    gradient = np.array(
        [
            (apex(params + np.eye(4)[k] * steps[k]) - apex(params - np.eye(4)[k] * steps[k]))
            / (2 * steps[k])
            for k in range(4)
        ]
    )
    apex_x_mm = float(apex(params))
    if not abs(apex_x_mm - notch_x_mm) <= search_mm:
        return None  # the faces met away from the notch: not the wedge's
    return apex_x_mm, float(np.sqrt(max(gradient @ covariance @ gradient, 0.0)))


def _wedge_tip_mm(x_mm, z_mm, name, near_mm=(0.1, 0.8), around_mm=None, search_mm=1.0):
    """x where the two sides of the loaded outline meet.

    The tip is first placed at the sharpest dip of the outline (where it lies furthest
    below the mean of the outline ``near_mm[1]`` either side: a finger's own curve dips
    far less than the wedge's notch), within ``search_mm`` of ``around_mm`` when given
    (:func:`_notch_mm`); lines fitted to each side of it, between ``near_mm`` of it, are
    then intersected.
    """
    ok = np.isfinite(z_mm)
    if ok.sum() < 10:
        raise ImageError(f"{name}: no skin outline to find the wedge in")
    xs, zs = x_mm[ok], z_mm[ok]
    span = near_mm[1]
    inner = (xs > xs[0] + span) & (xs < xs[-1] - span)
    if around_mm is not None and (inner & (np.abs(xs - around_mm) <= search_mm)).any():
        inner &= np.abs(xs - around_mm) <= search_mm
    if not inner.any():
        raise ImageError(f"{name}: the outline in view is too short to find the wedge in")
    dip = 0.5 * (np.interp(xs - span, xs, zs) + np.interp(xs + span, xs, zs)) - zs
    lowest = xs[inner][np.argmax(dip[inner])]
    # each side near the notch as a quadratic in x (the outline bends there), fitted
    # outside the first 0.1 mm, where the blur rounds the notch; where they cross is the tip
    fits = []
    for sign in (-1.0, 1.0):
        d = sign * (x_mm - lowest)
        pick = ok & (d > near_mm[0]) & (d < near_mm[1])
        if pick.sum() < 6:
            raise ImageError(
                f"{name}: the wedge was not found (no outline on both sides of the notch "
                f"at x = {lowest:.2f} mm; is the wedge pressed in, and in view?)"
            )
        fits.append(np.polyfit(x_mm[pick] - lowest, z_mm[pick], 2))
    left, right = fits
    slopes = (left[1], right[1])
    if not (left[1] < 0 < right[1]):
        raise ImageError(
            f"{name}: the wedge was not found (the outline does not fall to a notch: "
            f"slopes {left[1]:.3f} and {right[1]:.3f} either side of x = {lowest:.2f} mm)"
        )
    roots = np.roots(np.polysub(left, right))
    roots = roots[np.isreal(roots)].real
    roots = roots[np.abs(roots) < near_mm[0] + 0.05]
    if roots.size == 0:  # the two sides do not cross near the notch: their lines do
        return float(lowest + (right[2] - left[2]) / (slopes[0] - slopes[1]))
    return float(lowest + roots[np.argmin(np.abs(roots))])
