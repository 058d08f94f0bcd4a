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

from .fitting import fit_windowed
from .models import arc_deflection_mm, shifted_deflection_mm, waterbed_deflection_mm

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

#: The models refitted in every window, in table order.
MODELS = ("waterbed", "waterbed_free_depth", "shifted", "arc", "boussinesq")

#: The models whose W0 is held at the depth.
FIXED_DEPTH = ("waterbed", "shifted", "arc")

#: The waterbed curves in measured coordinates, by model name.
CONSISTENT_CURVES = {"shifted": shifted_deflection_mm, "arc": arc_deflection_mm}

#: How each curve is evaluated for many trials at once so that every row is what a
#: call with that trial's scalar W0 and L gives (see lineload.models).
_ONE_CALL_PER_ROW = {
    "shifted": {"independent_axes": 1},
    "arc": {"independent_axes": 1, "as_scalars": True},
}


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
        other = CONSISTENT_CURVES[model](
            x, depth_mm[rows, None], other_L_mm[rows, None], **_ONE_CALL_PER_ROW[model]
        )
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
                "W0_mm", depth_mm if model in FIXED_DEPTH else np.full(count, np.nan)
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
    fits = fit_windowed(
        distance_mm, deflection_mm, depth_mm, window_mm, ("waterbed", "shifted", "arc")
    )
    for i in range(count):
        for model in ("waterbed", "shifted", "arc"):
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


MODEL_NAMES = {
    "waterbed": "parabola, W0 = depth",
    "waterbed_free_depth": "parabola, W0 free",
    "shifted": "parabola in measured coordinates",
    "arc": "exact arc, W0 = depth",
    "boussinesq": "Boussinesq",
}


def summary_markdown(sensitivity, checks, notice=""):
    """Reviewer's summary of the sensitivity refits and the per-trial checks.

    Parameters
    ----------
    sensitivity : pandas.DataFrame
        Rows of :data:`SENSITIVITY_COLUMNS` for every trial.
    checks : pandas.DataFrame
        Rows of :data:`CHECK_COLUMNS` for every trial.
    notice : str, optional
        Footer line about the data (empty for none).

    Returns
    -------
    str
        Markdown: median L per species, depth, model and window; how often each
        model has the lowest AICc in each window; the per-trial U shift and reach.
    """
    from .tables import format_fixed, markdown_table

    windows = list(dict.fromkeys(sensitivity["window"]))
    species_order = {"monkey": 0, "human": 1}
    parts = [
        "# Sensitivity of the fits to the analysis choices\n",
        "Median fitted half-width L (mm) over the subjects of each species, by depth, "
        "model and fit window.\n",
    ]
    with_L = [m for m in MODELS if m != "boussinesq"]
    headers = ["species", "depth (mm)"] + [
        f"{MODEL_NAMES[m]}, {w}" for m in with_L for w in windows
    ]
    rows = []
    groups = sensitivity.groupby(["species", "depth_mm"], sort=False)
    keys = sorted(groups.groups, key=lambda k: (species_order.get(k[0], 2), k[0], k[1]))
    for species, depth_mm in keys:
        group = groups.get_group((species, depth_mm))
        cells = [species, f"{depth_mm:g}"]
        for model in with_L:
            for window in windows:
                values = group[(group["model"] == model) & (group["window"] == window)]["L_mm"]
                cells.append(format_fixed(values.median(), 2))
        rows.append(cells)
    parts.append(markdown_table(headers, rows, "lr" + "r" * (len(headers) - 2)))
    parts.append(
        "\nNumber of trials in which each model has the lowest AICc, by fit window "
        "(all trials of the dataset).\n"
    )
    rows = []
    best = sensitivity[sensitivity["delta_aicc"] == 0]
    for window in windows:
        counts = best[best["window"] == window]["model"].value_counts()
        rows.append([window] + [str(int(counts.get(m, 0))) for m in MODELS])
    parts.append(
        markdown_table(["window"] + [MODEL_NAMES[m] for m in MODELS], rows, "l" + "r" * len(MODELS))
    )
    parts.append(
        "\nPer trial: L under the paper's procedure and in measured coordinates (shifted "
        "parabola, exact arc), and the largest vertical gap between each of those fitted "
        "curves and the paper's over the fitted range; the largest horizontal shift of the "
        "small-slope solution, 8 W0^2 / (9 L) at X = L/3, as a fraction of that X; and the "
        "reach, the distance up to which the waterbed fitted in the main window stays within "
        "the tolerance of every averaged point.\n"
    )
    rows = [
        [
            row.subject,
            f"{row.depth_mm:g}",
            format_fixed(row.waterbed_L_mm, 2),
            format_fixed(row.shifted_L_mm, 2),
            format_fixed(row.arc_L_mm, 2),
            format_fixed(row.gap_shifted_mm, 4),
            format_fixed(row.gap_arc_mm, 4),
            format_fixed(100 * row.shift_fraction_at_third, 1),
            format_fixed(row.reach_tolerance_mm, 3),
            format_fixed(row.reach_mm, 2),
            format_fixed(row.rmse_within_window_mm, 4),
            format_fixed(row.rmse_beyond_window_mm, 4),
        ]
        for row in checks.itertuples()
    ]
    headers = [
        "subject",
        "depth (mm)",
        "L paper (mm)",
        "L shifted (mm)",
        "L arc (mm)",
        "gap shifted (mm)",
        "gap arc (mm)",
        "U/X at L/3 (%)",
        "tolerance (mm)",
        "reach (mm)",
        "RMSE in window (mm)",
        "RMSE beyond (mm)",
    ]
    parts.append(markdown_table(headers, rows, "l" + "r" * (len(headers) - 1)))
    if notice:
        parts.append(f"\n*Data: {notice}*\n")
    return "\n".join(parts)
