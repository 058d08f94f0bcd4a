"""How much the fitted L and the model comparison depend on open choices.

The paper fixes W0 to the depth, fits the small-slope parabola, and judges the
fit within about 3 mm of the load.  Here each trial is refitted with other
windows (2 mm, 3 mm, the whole profile), with W0 free, in measured coordinates
(the shifted parabola) and with the exact arc in place of the parabola, and the
two approximations the paper calls harmless (the horizontal shift U, and
agreement only near the load) get numbers.
"""

from __future__ import annotations

import numpy as np

from lineload import models
from lineload.fitting.batch import TABLE_MODELS, fit_windowed
from lineload.fitting.families import FAMILIES
from lineload.models import waterbed_deflection_mm

__all__ = [
    "CHECK_COLUMNS",
    "SENSITIVITY_COLUMNS",
    "agreement_reach_mm",
    "curve_gap_mm",
    "sensitivity_rows",
    "sensitivity_rows_batch",
    "trial_checks",
    "trial_checks_batch",
]

SENSITIVITY_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "window",
    "fit_window_mm",
    "model",
    "n_points",
    "L_mm",
    "L_ci_low_mm",
    "L_ci_high_mm",
    "W0_mm",
    "A_mm",
    "x0_mm",
    "rmse_mm",
    "max_abs_residual_mm",
    "aicc",
    "delta_aicc",
]

CHECK_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "waterbed_L_mm",
    "shifted_L_mm",
    "arc_L_mm",
    "gap_shifted_mm",
    "gap_arc_mm",
    "shift_at_third_mm",
    "shift_fraction_at_third",
    "reach_tolerance_mm",
    "reach_mm",
    "rmse_within_window_mm",
    "rmse_beyond_window_mm",
    "n_beyond_window",
]

#: The models refitted in every window, in table order (every model of lineload.models).
MODELS = models.MODELS

#: Name of each refitted model in the sensitivity tables and figure.
MODEL_NAMES = {model: names.refit for model, names in models.MODEL_NAMES.items()}

#: The models whose W0 is held at the depth (the registry's families of the fit table
#: whose curve takes it).
FIXED_DEPTH = tuple(m for m in TABLE_MODELS if FAMILIES[m].needs_depth)

#: The waterbed curves in measured coordinates, by model name (the registry's curves).
CONSISTENT_CURVES = {model: FAMILIES[model].curve for model in ("shifted", "arc")}


def _nan_is_nan(value):
    """A float for the tables; NaN is always the ``numpy.nan`` object."""
    value = float(value)
    return np.nan if value != value else value


def _curve_gaps_mm(depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm, model, n_points=601):
    """:func:`curve_gap_mm` for many trials at once (arrays by trial)."""
    values = (depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm)
    values = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values))
    depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm = (v.reshape(-1) for v in values)
    gaps = np.full(depth_mm.size, np.nan)
    rows = np.flatnonzero(np.all([np.isfinite(v) for v in values], axis=0).reshape(-1))
    if rows.size:
        x = np.linspace(0.0, max_distance_mm[rows], n_points, axis=-1)
        paper = waterbed_deflection_mm(x, depth_mm[rows, None], waterbed_L_mm[rows, None])
        other = CONSISTENT_CURVES[model](x, depth_mm[rows, None], other_L_mm[rows, None])
        gaps[rows] = np.max(np.abs(paper - other), axis=1)
    return gaps.reshape(values[0].shape)


def curve_gap_mm(depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm, model, n_points=601):
    """Largest vertical gap between the paper's fitted curve and a coordinate-consistent one.

    Both curves are evaluated on ``n_points`` even steps over ``[0, max_distance_mm]``
    (the fitted range): the paper's eq. 19 with its own fitted L, read at x as if
    it were X, and the ``model`` curve (``"shifted"`` or ``"arc"``) with its
    fitted L.  The gap says how far apart the two procedures put the fitted
    profile where there are data; compare it with the digitising noise.

    Parameters
    ----------
    depth_mm : float
        W0 of both curves (mm).
    waterbed_L_mm, other_L_mm : float
        Fitted L of the paper's curve and of the other curve (mm).
    max_distance_mm : float
        Largest fitted distance (mm).
    model : {"shifted", "arc"}
        The coordinate-consistent curve.
    n_points : int, optional
        Number of evaluation points.

    Returns
    -------
    float
        The gap (mm); NaN if either L or the range is not finite.
    """
    gap = _curve_gaps_mm(
        depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm, model, n_points=n_points
    )
    return _nan_is_nan(gap)


def window_label(window_mm):
    """``"2 mm"``-style label, or ``"whole"`` for an unbounded window."""
    return "whole" if not np.isfinite(window_mm) else f"{window_mm:g} mm"


def sensitivity_rows(distance_mm, deflection_mm, depth_mm, windows_mm):
    """Refit one trial with every model in every window.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        The averaged profile of one trial (mm).
    depth_mm : float
        Indentation depth (mm): W0 of the fixed-depth waterbed fits.
    windows_mm : sequence of float
        Outer edges of the fitted region (mm); ``inf`` is the whole profile.

    Returns
    -------
    list of dict
        One row per window and model with the columns of
        :data:`SENSITIVITY_COLUMNS` except ``subject`` and ``species``;
        parameters a model does not have are NaN.  ``delta_aicc`` is the AICc
        minus the lowest AICc of the models in that window.
    """
    return sensitivity_rows_batch([distance_mm], [deflection_mm], [depth_mm], windows_mm)[0]


def sensitivity_rows_batch(distance_mm, deflection_mm, depth_mm, windows_mm):
    """:func:`sensitivity_rows` for many trials at once (each model fitted to all together).

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm).
    windows_mm : sequence of float
        Outer edges of the fitted region (mm); ``inf`` is the whole profile.

    Returns
    -------
    list of list of dict
        For each trial, its rows as :func:`sensitivity_rows` gives them.
    """
    count = len(distance_mm)
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), (count,))
    rows = [[] for _ in range(count)]
    for window_mm in windows_mm:
        fits = fit_windowed(distance_mm, deflection_mm, depth_mm, window_mm, MODELS)
        aicc = np.array([fits[model].measures["aicc"] for model in MODELS])
        best = np.fmin.reduce(aicc, axis=0)  # NaN only where every model has none
        for model in MODELS:
            fit = fits[model]
            columns = {
                name: fit.params.get(name, np.full(count, np.nan))
                for name in ("L_mm", "L_ci_low_mm", "L_ci_high_mm", "A_mm", "x0_mm")
            }
            columns["W0_mm"] = fit.params.get(
                "W0_mm", depth_mm if FAMILIES[model].needs_depth else np.full(count, np.nan)
            )
            columns.update(
                {name: fit.measures[name] for name in ("rmse_mm", "max_abs_residual_mm", "aicc")}
            )
            columns["delta_aicc"] = fit.measures["aicc"] - best
            values = {name: column.tolist() for name, column in columns.items()}
            n_points = fits["n_points"].tolist()
            for i in range(count):
                row = {
                    "depth_mm": float(depth_mm[i]),
                    "window": window_label(window_mm),
                    "fit_window_mm": float(window_mm),
                    "model": model,
                    "n_points": int(n_points[i]),
                }
                for name in SENSITIVITY_COLUMNS[7:]:
                    row[name] = _nan_is_nan(values[name][i])
                rows[i].append(row)
    return rows


def agreement_reach_mm(distance_mm, residual_mm, tolerance_mm):
    """Largest distance up to which every residual stays within the tolerance.

    Parameters
    ----------
    distance_mm, residual_mm : array_like
        Points of a trial and data-minus-model there (mm).
    tolerance_mm : float
        Largest acceptable absolute residual (mm).

    Returns
    -------
    float
        The distance of the last point before the first one outside the
        tolerance (in order of distance); 0 if the nearest point is already
        outside, the largest distance if none is.
    """
    order = np.argsort(distance_mm, kind="stable")
    distance_mm = np.asarray(distance_mm, dtype=float)[order]
    outside = np.abs(np.asarray(residual_mm, dtype=float)[order]) > tolerance_mm
    if not outside.any():
        return float(distance_mm[-1]) if distance_mm.size else np.nan
    first = int(np.argmax(outside))
    return float(distance_mm[first - 1]) if first > 0 else 0.0


def trial_checks(distance_mm, deflection_mm, depth_mm, window_mm, reach_fraction):
    """Per-trial numbers behind two of the paper's remarks on the waterbed.

    The horizontal shift U is largest at ``X = L/3``, where it is
    ``8 W0**2 / (9 L)``; the paper calls it negligible when small next to
    that X.  What neglecting it costs is measured directly: the shifted
    parabola and the exact arc are fitted in the same window, and the largest
    vertical gap between each and the paper's curve over the fitted range is
    given (:func:`curve_gap_mm`).  The fit is said to hold to about 3 mm; here that is measured as
    the distance up to which the waterbed (fitted in the window) stays within
    ``reach_fraction * depth`` of every averaged point.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        The averaged profile of one trial (mm), all distances.
    depth_mm : float
        Indentation depth (mm).
    window_mm : float
        Fit window (mm) of the waterbed fit.
    reach_fraction : float
        Tolerance of the reach, as a fraction of the depth.

    Returns
    -------
    dict
        The columns of :data:`CHECK_COLUMNS` except ``subject`` and ``species``.

    Raises
    ------
    ValueError
        If a waterbed curve cannot be fitted in the window (no point in it).
    """
    return trial_checks_batch(
        [distance_mm], [deflection_mm], [depth_mm], window_mm, reach_fraction
    )[0]


def trial_checks_batch(distance_mm, deflection_mm, depth_mm, window_mm, reach_fraction):
    """:func:`trial_checks` for many trials at once (the fits of all of them together).

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm).
    window_mm : float
        Fit window (mm) of the waterbed fits.
    reach_fraction : float
        Tolerance of the reach, as a fraction of the depth.

    Returns
    -------
    list of dict
        For each trial, what :func:`trial_checks` gives.

    Raises
    ------
    ValueError
        For the first trial whose waterbed curves cannot be fitted in the window.
    """
    count = len(distance_mm)
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), (count,))
    fits = fit_windowed(distance_mm, deflection_mm, depth_mm, window_mm, FIXED_DEPTH)
    for i in range(count):
        for model in FIXED_DEPTH:
            if not fits[model].fitted[i]:
                raise ValueError(fits[model].errors[i])
    L_mm = fits["waterbed"].params["L_mm"]
    consistent_L_mm = {model: fits[model].params["L_mm"] for model in CONSISTENT_CURVES}
    max_distance_mm = fits["max_distance_mm"]
    gaps = {
        model: _curve_gaps_mm(depth_mm, L_mm, consistent_L_mm[model], max_distance_mm, model)
        for model in CONSISTENT_CURVES
    }
    checks = []
    for i in range(count):
        distance = np.asarray(distance_mm[i], dtype=float)
        deflection = np.asarray(deflection_mm[i], dtype=float)
        usable = (distance > 0) & np.isfinite(deflection)
        x, y = distance[usable], deflection[usable]
        inside = x <= window_mm
        depth, L = float(depth_mm[i]), float(L_mm[i])
        shift_mm = 8.0 * depth**2 / (9.0 * L)
        residual = y - waterbed_deflection_mm(x, depth, L)
        tolerance_mm = reach_fraction * depth
        beyond = ~inside
        checks.append(
            {
                "depth_mm": depth,
                "waterbed_L_mm": L,
                "shifted_L_mm": _nan_is_nan(consistent_L_mm["shifted"][i]),
                "arc_L_mm": _nan_is_nan(consistent_L_mm["arc"][i]),
                **{f"gap_{model}_mm": _nan_is_nan(gaps[model][i]) for model in CONSISTENT_CURVES},
                "shift_at_third_mm": shift_mm,
                "shift_fraction_at_third": shift_mm / (L / 3.0),
                "reach_tolerance_mm": tolerance_mm,
                "reach_mm": agreement_reach_mm(x, residual, tolerance_mm),
                "rmse_within_window_mm": float(np.sqrt(np.mean(residual[inside] ** 2))),
                "rmse_beyond_window_mm": (
                    float(np.sqrt(np.mean(residual[beyond] ** 2))) if beyond.any() else np.nan
                ),
                "n_beyond_window": int(beyond.sum()),
            }
        )
    return checks
