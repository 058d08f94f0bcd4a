"""A pair of photographs (at rest and loaded) read into a trial's readings.

The loaded outline is registered on the resting one far from the wedge, the columns
spoilt near the tip are left unread with their reason, and each side's deflection is
read at the given distances with its own uncertainty; :func:`quality_record` says how
well, and :func:`trial_problem` when a pair cannot be used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lineload.rawdata.photographs.apex import (
    APEX_SEARCH_MM,
    _notch_mm,
    _wedge_apex_mm,
    _wedge_tip_mm,
)
from lineload.rawdata.photographs.edges import (
    EDGE_BAND_PX,
    _edges,
    _outline_mm,
    _smoothed,
    excluded_mask,
)
from lineload.rawdata.photographs.files import ImageError, Scene
from lineload.rawdata.photographs.glare import (
    GLARE_REACH_MM,
    GLARE_SHARE,
    _saturated_near,
    _slope,
    _traced,
)
from lineload.rawdata.photographs.uncertainty import _reading_sds_mm, _registration_sd_mm

__all__ = [
    "REGISTRATION_ROUGHNESS_MAX",
    "TIP_PIXELS_MAX",
    "DigitisedTrial",
    "digitise_pair",
    "digitise_photographs",
    "own_reading_sd_mm",
    "profile_rows",
    "quality_record",
    "trial_problem",
    "truth_error_um",
]


@dataclass
class DigitisedTrial:
    """The readings of one trial and how well they were made.

    Attributes
    ----------
    readings : dict
        Side (``left``, ``right``) -> ``(distance_mm, deflection_mm)`` arrays.
    tip_x_mm : float
        Where the wedge's tip was placed (x, mm, in the loaded image).
    shift_mm : tuple of float
        ``(dx, dz)``: the loaded image's shift against the resting one.
    registration_rms_mm : float
        RMS of the far-field difference left after registration.
    edge_noise_mm : float
        The outline's own roughness (one column's edge, SD).
    reading_sd_mm : float
        The digitising uncertainty of one reading, the median over the trial's
        readings: its own (``reading_sds_mm``) and the registration's together.
    registration_sd_mm : float
        The registration's own error, an offset shared by every reading of the
        trial, both sides alike (the part of ``reading_sd_mm`` that left-right
        differences cannot see; the fits take it in place of the config's prior
        ``noise: shared_offset_sd_mm``).
    outlines : dict, optional
        ``x_mm`` of each column, the loaded outline (``loaded_mm``, NaN where unread)
        and the resting one moved onto it (``rest_mm``): what the quality figure draws.
    apex_x_mm : float, optional
        The wedge's apex as seen in the loaded image (None where no wedge is seen
        against the background): ``tip_x_mm`` itself unless the sheet gave the tip.
    pixel_mm : float, optional
        The size of a pixel (tissue mm).
    reading_sds_mm : dict, optional
        Side -> each reading's own SD (mm), the registration's shared error apart: the
        edge errors of both outlines averaged over its columns, at its place.
    tip_sd_mm : float, optional
        The apex's standard error (mm), from the scatter of each face's points about
        its line (None where no wedge is seen against the background).
    unread : dict, optional
        Side -> list of ``(distance_mm, reason)``: each distance of the grid left
        unread on that side, and why.
    seen : dict, optional
        What the digitiser saw, for a diagnostic image (:func:`digitise_pair`).
    """

    readings: dict
    tip_x_mm: float
    shift_mm: tuple
    registration_rms_mm: float
    edge_noise_mm: float
    reading_sd_mm: float
    registration_sd_mm: float = 0.0
    outlines: dict = None
    apex_x_mm: float | None = None
    pixel_mm: float | None = None
    reading_sds_mm: dict = None
    tip_sd_mm: float | None = None
    unread: dict = None
    seen: dict = None


def _roughness_mm(z_mm, window_px=25):
    """The outline's own roughness: SD of one column's edge about the outline's local
    trend (a moving quadratic), and the correlation of neighbouring columns' errors.

    Returns
    -------
    tuple of float
        ``(sd_mm, rho)``; NaN where the outline is too short.
    """
    from scipy.signal import savgol_filter

    ok = np.isfinite(z_mm)
    if ok.sum() < 3 * window_px:
        return float("nan"), float("nan")
    # columns without an edge filled in from their neighbours for the trend only
    index = np.arange(z_mm.size)
    filled = np.interp(index, index[ok], z_mm[ok])
    residual = (filled - savgol_filter(filled, window_px | 1, 2))[ok]
    # a quadratic over the window takes a share 3/window of the variance away
    sd = float(np.std(residual) / np.sqrt(1.0 - 3.0 / window_px))
    rho = float(np.corrcoef(residual[:-1], residual[1:])[0, 1])
    return sd, min(max(rho, 0.0), 0.99)


def _sample(x_mm, z_mm, at_mm, half_window_mm):
    """The outline at each point from the columns within ``half_window_mm`` of it: their
    straight line (least squares) at the point, their mean where they are too few or all
    at one place (NaN where a window holds no column with an edge: that reading is
    unreadable).

    The columns' mean alone would be the outline at their mean position, up to half a
    pixel from the point: on a slope of 0.2 at 10 um a pixel, a 1 um error that no
    smoothing removes.  The line through them takes the slope out.
    """
    ok = np.isfinite(z_mm)
    x, z = x_mm[ok], z_mm[ok]
    lo = np.searchsorted(x, at_mm - half_window_mm, side="left")
    hi = np.searchsorted(x, at_mm + half_window_mm, side="right")
    counts = hi - lo
    n = np.maximum(counts, 1)
    # sums over each window, about the point itself (well conditioned)
    windows = [slice(a, b) for a, b in zip(lo, hi, strict=True)]
    offsets = [x[w] - at for w, at in zip(windows, at_mm, strict=True)]
    sum_d = np.array([o.sum() for o in offsets])
    sum_dd = np.array([(o * o).sum() for o in offsets])
    sum_z = np.array([z[w].sum() for w in windows])
    sum_dz = np.array([(o * z[w]).sum() for o, w in zip(offsets, windows, strict=True)])
    spread = sum_dd - sum_d**2 / n
    slope = np.where(
        spread > 0, (sum_dz - sum_d * sum_z / n) / np.where(spread > 0, spread, 1.0), 0.0
    )
    value = sum_z / n - slope * sum_d / n
    return np.where(counts > 0, value, np.nan), counts


def digitise_pair(
    rest_image,
    loaded_image,
    scene,
    distances_mm,
    reach_mm,
    tip_x_mm=None,
    smoothing_px=1.5,
    window_mm=0.02,
    names=("rest", "loaded"),
    exclude_px=(),
):
    """Readings of both sides of the wedge from a resting and a loaded photograph.

    Parameters
    ----------
    rest_image, loaded_image : numpy.ndarray
        The two photographs, of the same size and scale.
    scene : Scene
        Their scale and field of view.
    distances_mm : array_like
        Distances from the wedge at which to read each side (mm, > 0).
    reach_mm : float
        Distance from the wedge beyond which the load does not reach: the outlines are
        registered there.
    tip_x_mm : float, optional
        x of the wedge's tip in the loaded image (from the sheet); found otherwise.
    smoothing_px : float, optional
        Smoothing before the edge is sought (:func:`skin_outline_mm`).
    window_mm : float, optional
        Half-width of the columns averaged into one reading.
    names : tuple of str, optional
        How messages name the two images (their files).
    exclude_px : sequence of sequence of int, optional
        Regions no edge or wedge is sought in, ``[left, top, right, bottom]`` pixels
        (:func:`excluded_mask`); a column whose edge would lie there is left unread.

    Returns
    -------
    DigitisedTrial

    Raises
    ------
    ImageError
        If an image has no edge, the wedge's tip cannot be found, or too little skin
        beyond ``reach_mm`` is in view to register the outlines.  Its ``seen`` holds what
        the digitiser saw up to then (as the trial's ``seen`` does): ``scene``,
        ``exclude_px``, ``reach_mm``, ``failed`` (0 or 1: which image), and as far as it
        got ``rest_mm`` and ``loaded_mm`` (each column's edge, NaN where none),
        ``notch_x_mm``, ``apex_region_mm`` (``x_lo, x_hi``: where the apex was sought),
        ``apex_x_mm``, ``tip_x_mm``, ``why`` (each column's reason for being left out,
        "" where kept): what :mod:`lineload.figures.diagnostic` draws.
    """
    seen = {"scene": scene, "exclude_px": list(exclude_px), "reach_mm": reach_mm, "failed": 0}
    try:
        return _digitise_pair(
            seen,
            rest_image,
            loaded_image,
            scene,
            distances_mm,
            reach_mm,
            tip_x_mm,
            smoothing_px,
            window_mm,
            names,
            exclude_px,
        )
    except ImageError as error:
        error.seen = seen
        raise


def _digitise_pair(
    seen,
    rest_image,
    loaded_image,
    scene,
    distances_mm,
    reach_mm,
    tip_x_mm,
    smoothing_px,
    window_mm,
    names,
    exclude_px,
):
    """:func:`digitise_pair`'s work; ``seen`` is filled in as it goes."""
    x = scene.column_x_mm
    excluded = excluded_mask(exclude_px, (scene.height_px, scene.width_px), smoothing_px)
    smooth_rest = _smoothed(rest_image, scene, smoothing_px, names[0])
    z_rest, _ = _outline_mm(smooth_rest, scene, names[0], excluded)
    seen.update(rest_mm=z_rest, failed=1)
    smooth_load = _smoothed(loaded_image, scene, smoothing_px, names[1])
    z_load, contrast_load, _ = _edges(smooth_load, scene, names[1], excluded)
    seen["loaded_mm"] = z_load
    why = np.where(np.isfinite(z_load), "", "no edge in the column")
    if excluded is not None:
        why = np.where(np.isfinite(z_load) | ~excluded.any(axis=0), why, "an excluded region")
    # the wedge is sought only where the load pressed the skin in: around the notch,
    # where the loaded outline lies furthest below the resting one (a scale bar, a ruler
    # or a label elsewhere is never taken for it)
    notch_x_mm = _notch_mm(x, z_rest, z_load)
    apex = _wedge_apex_mm(smooth_load, scene, z_load, smoothing_px, notch_x_mm, excluded)
    apex_x_mm, apex_sd_mm = apex if apex is not None else (None, None)
    seen.update(
        notch_x_mm=notch_x_mm,
        apex_region_mm=(notch_x_mm - APEX_SEARCH_MM, notch_x_mm + APEX_SEARCH_MM),
    )
    seen["apex_x_mm"] = apex_x_mm
    if tip_x_mm is None:
        tip_x_mm = apex_x_mm
        if tip_x_mm is None:  # no wedge seen against the background: the notch's tip
            tip_x_mm = _wedge_tip_mm(x, z_load, names[1], around_mm=notch_x_mm)
    # glare at the wedge brightens the skin: its edge's step shrinks and its place is
    # biased.  A steep edge's fall per pixel shrinks too (by about 1 / sqrt(1 + slope^2),
    # the blur spread along the column), so the fall is compared slope-corrected: within
    # GLARE_REACH_MM of the tip, a column whose corrected fall is below GLARE_SHARE of
    # the one 1-3 mm out, or whose skin just below the edge is saturated, is left unread
    # (as a hand reader starts past a glaring stretch)
    away = np.abs(x - tip_x_mm)
    corrected = contrast_load * np.sqrt(1.0 + _slope(x, z_load) ** 2)
    reference_columns = (away > 1.0) & (away < 3.0) & np.isfinite(corrected)
    reference = (
        float(np.median(corrected[reference_columns])) if reference_columns.any() else np.nan
    )
    weak = (away < GLARE_REACH_MM) & (corrected < GLARE_SHARE * reference)
    saturated = (away < GLARE_REACH_MM) & _saturated_near(
        loaded_image, z_load, scene, int(np.ceil(3 * smoothing_px)) + EDGE_BAND_PX
    )
    jumped = ~_traced(
        x, np.where(saturated | weak, np.nan, z_load), tip_x_mm, 1.0 / scene.pixels_per_mm
    )
    why = np.where(
        np.isfinite(z_load) & jumped,
        "glare or an overlay: the edge leaves the outline traced in towards the tip",
        why,
    )
    why = np.where(
        np.isfinite(z_load) & saturated,
        "glare: saturated pixels at the edge",
        np.where(
            np.isfinite(z_load) & weak,
            f"glare or the wedge above the edge: its slope-corrected contrast is below "
            f"{GLARE_SHARE:g} of the contrast 1-3 mm out",
            why,
        ),
    )
    why = np.where(
        (why == "no edge in the column") & (away < GLARE_REACH_MM),
        "no edge in the column, near the tip (glare as bright as the background?)",
        why,
    )
    seen.update(tip_x_mm=float(tip_x_mm), why=why)
    z_load = np.where(why == "", z_load, np.nan)
    far = np.isfinite(z_load) & (away > reach_mm)
    if far.sum() < 20 or not ((x[far] < tip_x_mm).any() and (x[far] > tip_x_mm).any()):
        ppmm = scene.pixels_per_mm
        sides = {
            side: int(np.sum(far & (sign * (x - tip_x_mm) > 0)))
            for side, sign in (("left", -1.0), ("right", 1.0))
        }
        raise ImageError(
            f"{names[1]}: too little skin in view beyond {reach_mm:g} mm of the wedge on "
            f"both sides to register the two photographs: the wedge's tip was placed at "
            f"pixel column {(tip_x_mm - scene.x0_mm) * ppmm - 0.5:.1f} "
            f"({'seen at its apex' if apex_x_mm is not None else 'from the notch'}, "
            f"the notch at column {(notch_x_mm - scene.x0_mm) * ppmm - 0.5:.0f}), leaving "
            f"{sides['left']} columns with an edge on the left and {sides['right']} on the "
            f"right beyond reach_mm (the image is {scene.width_px} columns, "
            f"{scene.width_px / ppmm:.2f} mm, wide); expected at least 20 in all, on both "
            "sides: widen the view, lower reach_mm, or check the tip (a tip_x_px from "
            "another photograph?)"
        )
    # the loaded outline against the resting one shifted by (dx, dz), least squares
    ok_rest = np.isfinite(z_rest)
    slope = np.gradient(z_rest[ok_rest], x[ok_rest])
    dx = dz = 0.0
    for _ in range(4):
        shifted = np.interp(x[far] - dx, x[ok_rest], z_rest[ok_rest])
        slope_at = np.interp(x[far] - dx, x[ok_rest], slope)
        design = np.column_stack([np.ones(far.sum()), -slope_at])
        residual = z_load[far] - shifted - dz
        step, *_ = np.linalg.lstsq(design, residual, rcond=None)
        dz += step[0]
        dx += step[1]
    final = z_load[far] - np.interp(x[far] - dx, x[ok_rest], z_rest[ok_rest]) - dz
    registration_rms = float(np.sqrt(np.mean(final**2)))
    rest_on_loaded = np.interp(x - dx, x[ok_rest], z_rest[ok_rest]) + dz
    deflection = np.where(np.isfinite(z_load), rest_on_loaded - z_load, np.nan)
    distances_mm = np.asarray(distances_mm, dtype=float)
    readings, unread = {}, {}
    columns = []
    for side, sign in (("left", -1.0), ("right", 1.0)):
        distance = sign * (x - tip_x_mm)
        keep = distance > 0
        d, w = distance[keep], deflection[keep]
        order = np.argsort(d)
        values, counts = _sample(d[order], w[order], distances_mm, window_mm)
        inside = np.isfinite(values)
        readings[side] = (distances_mm[inside], values[inside])
        columns.extend(counts[inside])
        unread[side] = [
            (round(float(at), 6), _unread_reason(d[order], why[keep][order], at, window_mm))
            for at in distances_mm[~inside]
        ]
    # each reading's own error: the mean over its columns of two outlines' edge errors,
    # and the registration's error, shared by every reading (_reading_sds_mm)
    rough = [_roughness_mm(z_rest), _roughness_mm(z_load)]
    edge = float(np.sqrt(np.nanmean([sd**2 for sd, _ in rough])))
    design = np.column_stack([np.ones(far.sum()), -np.interp(x[far] - dx, x[ok_rest], slope)])
    registration_sd = _registration_sd_mm(design, final, np.flatnonzero(far))
    own = _reading_sds_mm(x, z_rest, z_load, dx, tip_x_mm, readings, window_mm)
    totals = np.concatenate([np.hypot(own[side], registration_sd) for side in own])
    return DigitisedTrial(
        readings=readings,
        tip_x_mm=float(tip_x_mm),
        shift_mm=(float(dx), float(dz)),
        registration_rms_mm=registration_rms,
        edge_noise_mm=float(edge),
        reading_sd_mm=float(np.median(totals)) if totals.size else float(registration_sd),
        registration_sd_mm=float(registration_sd),
        outlines={"x_mm": x, "loaded_mm": z_load, "rest_mm": rest_on_loaded},
        apex_x_mm=None if apex_x_mm is None else float(apex_x_mm),
        pixel_mm=1.0 / scene.pixels_per_mm,
        reading_sds_mm=own,
        tip_sd_mm=None if apex_sd_mm is None else float(apex_sd_mm),
        unread=unread,
        seen=seen,
    )


def digitise_photographs(
    rest_image, loaded_image, pixels_per_mm, distances_mm, settings, tip_x_px=None, names=()
):
    """A pair read as the workflow reads it, from the sheet's values and the config's.

    Coordinates are the images' own (x from their left edge, z down from their top, in
    tissue mm at the sheet's scale); the tip, when the sheet gives its pixel column,
    is at that column's centre.

    Parameters
    ----------
    rest_image, loaded_image : numpy.ndarray
        The two photographs.
    pixels_per_mm : float
        Their scale (images.csv).
    distances_mm : array_like
        Where to read each side.
    settings : dict
        The config's ``digitise`` settings (``reach_mm``, ``smoothing_px``,
        ``window_mm``, ``exclude_px``).
    tip_x_px : float, optional
        The sheet's ``tip_x_px``; found in the image when None.
    names : tuple of str, optional
        How messages name the two images.

    Returns
    -------
    DigitisedTrial
    """
    height, width = np.shape(loaded_image)[:2]
    scene = Scene(pixels_per_mm, 0.0, 0.0, width, height)
    return digitise_pair(
        rest_image,
        loaded_image,
        scene,
        distances_mm,
        reach_mm=settings["reach_mm"],
        tip_x_mm=None if tip_x_px is None else (float(tip_x_px) + 0.5) / pixels_per_mm,
        smoothing_px=settings["smoothing_px"],
        window_mm=settings["window_mm"],
        exclude_px=settings.get("exclude_px", ()),
        names=tuple(names) or ("rest", "loaded"),
    )


#: How far (pixels) a tip given in the sheet may lie from the apex seen in the image:
#: the apex is found to within 0.35 pixel on 20 pairs with harder camera settings.
TIP_PIXELS_MAX = 3.0


#: How many times the outlines' own roughness the registration may leave beyond
#: reach_mm.  On the photograph example the residual is 1.9-2.4 times it; a pair whose
#: skin beyond reach_mm moved (reach 2 mm: 156-276 times), whose resting view is 3 %
#: zoomed (44-61 times) or whose scale is a quarter of the truth (195-212 times) is
#: far beyond.
REGISTRATION_ROUGHNESS_MAX = 10.0


def trial_problem(trial, depth_mm, deflection_factor, names=("rest", "loaded")):
    """Why a digitised trial is not a plausible indentation, or None.

    The checks a profile file gets (its readings within ``deflection_factor`` of the
    depth), and those only a pair of photographs can fail: no deflection at all (one
    photograph copied over the other), skin raised at the wedge (the two swapped), a
    registration that leaves many times the outlines' roughness (the skin beyond
    ``reach_mm`` moved, or the two photographs differ in scale).

    Parameters
    ----------
    trial : DigitisedTrial
    depth_mm : float
        The pair's depth (images.csv, tissue mm).
    deflection_factor : float
        The config's ``input_checks: deflection_factor``.
    names : tuple of str, optional
        How messages name the two photographs.

    Returns
    -------
    str or None
        One sentence naming the loaded photograph, what was found and the likely cause.
    """
    name = names[1]
    values = [trial.readings[side][1] for side in ("left", "right")]
    readings = np.concatenate(values)
    if readings.size == 0:
        return None  # nothing read: the digitiser said so already
    edge_mm = max(trial.edge_noise_mm, 1e-9)
    near_mm = float(np.mean([v[0] for v in values if v.size]))
    largest = float(np.max(np.abs(readings)))
    if largest < 5.0 * edge_mm or largest < depth_mm / 100.0:
        return (
            f"{name}: no deflection (at most {1000 * largest:.1f} um anywhere, at a depth of "
            f"{depth_mm:g} mm); expected the loaded outline pressed in: is one photograph "
            "copied over the other?"
        )
    if near_mm < 0 and -near_mm > depth_mm / deflection_factor:
        return (
            f"{name}: the skin at the wedge is raised by {-near_mm:.3f} mm against the "
            f"resting photograph, at a depth of {depth_mm:g} mm; expected it pressed down: "
            "are rest and loaded swapped?"
        )
    if trial.apex_x_mm is not None and trial.pixel_mm:
        off_px = (trial.tip_x_mm - trial.apex_x_mm) / trial.pixel_mm
        if abs(off_px) > TIP_PIXELS_MAX:
            return (
                f"{name}: the sheet's tip_x_px puts the wedge's tip {abs(off_px):.1f} pixels "
                f"{'right' if off_px > 0 else 'left'} of its apex as seen in the photograph "
                f"(pixel column {trial.apex_x_mm / trial.pixel_mm - 0.5:.1f}); expected them "
                f"within {TIP_PIXELS_MAX:g} pixels: a tip read from another photograph, or "
                "a typing error?"
            )
    ratio = trial.registration_rms_mm / edge_mm
    if ratio > REGISTRATION_ROUGHNESS_MAX:
        return (
            f"{name}: the two outlines beyond reach_mm differ by "
            f"{1000 * trial.registration_rms_mm:.1f} um after registration, {ratio:.0f} times "
            f"the outlines' own roughness ({1000 * edge_mm:.2f} um; expected at most "
            f"{REGISTRATION_ROUGHNESS_MAX:g} times): reach_mm too short (the load still "
            "moves the skin there), the two photographs at different scales (zoom, or a "
            "wrong pixels_per_mm), or not the same finger"
        )
    if near_mm > deflection_factor * depth_mm or largest > deflection_factor * depth_mm:
        return (
            f"{name}: deflected {max(near_mm, largest):.3f} mm at a depth of {depth_mm:g} mm, "
            f"more than {deflection_factor:g} times it; expected about the depth at the "
            "wedge: is the scale (pixels_per_mm) or the depth wrong?"
        )
    if near_mm < depth_mm / deflection_factor:
        return (
            f"{name}: deflected {near_mm:.3f} mm next to the wedge at a depth of "
            f"{depth_mm:g} mm, less than 1/{deflection_factor:g} of it; expected about the "
            "depth: is the scale (pixels_per_mm) or the depth wrong, or the loaded view "
            "not indented?"
        )
    return None


def _unread_reason(distance_mm, why, at_mm, half_window_mm):
    """Why the reading at ``at_mm`` has no column with an edge: the commonest reason of
    its columns, or that none of its columns is in view."""
    inside = np.abs(distance_mm - at_mm) <= half_window_mm
    if not inside.any():
        return "outside the view"
    reasons, counts = np.unique(why[inside], return_counts=True)
    return str(reasons[np.argmax(counts)])


def profile_rows(depth_mm, trial, magnification):
    """The readings of one digitised trial as rows of the profile contract.

    Parameters
    ----------
    depth_mm : float
        The trial's indentation depth.
    trial : DigitisedTrial
    magnification : float
        The subject's enlargement: readings are written in image units (tissue mm times
        it), as a hand reader's would be, so the workflow converts them alike.

    Returns
    -------
    list of tuple
        ``(depth_mm, side, distance_image_mm, deflection_image_mm)``, left side first,
        each side by distance.
    """
    rows = []
    for side in ("left", "right"):
        distance, deflection = trial.readings[side]
        for d, w in zip(distance, deflection, strict=True):
            rows.append((float(depth_mm), side, float(d) * magnification, float(w) * magnification))
    return rows


def truth_error_um(trial, truth, window_mm):
    """RMS difference (um) between the readings and the truth over the fit window, both
    sides together; None without a truth.

    Parameters
    ----------
    trial : DigitisedTrial
    truth : dict
        Side -> ``(distance_mm, deflection_mm)`` of the true profile (interpolated at
        the readings' distances).
    window_mm : float
        The fit window: readings at or within it count.
    """
    errors = []
    for side, (distance, deflection) in trial.readings.items():
        if side not in truth:
            continue
        inside = distance <= window_mm
        true = np.interp(distance[inside], *truth[side])
        errors.extend(deflection[inside] - true)
    if not errors:
        return None
    return float(1000 * np.sqrt(np.mean(np.square(errors))))


def own_reading_sd_mm(trial, window_mm):
    """The RMS of a trial's readings' own SDs within the fit window (both sides), or
    None where it states none: what the fits take as its ``reading_sd_mm``."""
    if not trial.reading_sds_mm:
        return None
    sds = np.concatenate(
        [
            trial.reading_sds_mm[side][trial.readings[side][0] <= window_mm]
            for side in ("left", "right")
        ]
    )
    return float(np.sqrt(np.mean(sds**2))) if sds.size else None


def quality_record(depth_mm, trial, truth=None, window_mm=3.0):
    """What a reviewer needs to judge one digitised trial, JSON-ready (mm and um); with
    a truth (side -> distances and deflections), the readings' RMS error against it over
    the fit window (``error_rms_um``, else None).  ``registration_sd_um`` and
    ``own_reading_sd_um`` (:func:`own_reading_sd_mm`) are what the fits take for the
    trial's shared offset and reading error (:func:`lineload.noise.registration_rows`)."""
    error = truth_error_um(trial, truth, window_mm) if truth else None
    own = own_reading_sd_mm(trial, window_mm)
    return {
        "error_rms_um": None if error is None else round(error, 3),
        "depth_mm": float(depth_mm),
        "tip_x_mm": round(trial.tip_x_mm, 6),
        "shift_x_mm": round(trial.shift_mm[0], 6),
        "shift_z_mm": round(trial.shift_mm[1], 6),
        "registration_rms_um": round(1000 * trial.registration_rms_mm, 3),
        "edge_noise_um": round(1000 * trial.edge_noise_mm, 3),
        "reading_sd_um": round(1000 * trial.reading_sd_mm, 3),
        "registration_sd_um": round(1000 * trial.registration_sd_mm, 3),
        # the readings' own SD over the fit window: the trial's reading_sd_mm in the fits
        "own_reading_sd_um": None if own is None else round(1000 * own, 3),
        "tip_sd_um": None if trial.tip_sd_mm is None else round(1000 * trial.tip_sd_mm, 3),
        "readings": {side: len(trial.readings[side][0]) for side in ("left", "right")},
        "unread": {
            side: [
                {"distance_mm": round(distance, 4), "reason": reason}
                for distance, reason in (trial.unread or {}).get(side, [])
            ]
            for side in ("left", "right")
        },
        "first_read_mm": {
            side: round(float(trial.readings[side][0][0]), 4)
            if len(trial.readings[side][0])
            else None
            for side in ("left", "right")
        },
    }
