"""Supplementary figures: residuals, parabola against arc, sensitivity and coordinates.

Each function takes the workflow's tables (pandas DataFrames) and settings,
named as in :data:`lineload.figures.registry.ARGUMENTS`, and returns a
:class:`matplotlib.figure.Figure`.  The paper's own numbers drawn as reference
lines (its bound on the shift and the distance it says the fit holds to) come
from :mod:`lineload.paper`.

gids: ``residual:<model>:<subject>`` and ``fit-window`` (residuals);
``parabola``, ``shifted``, ``arc`` and ``difference:<kind>`` (parabola against
arc); ``L:<model>``, ``aicc:<model>``, ``shift`` and ``reach`` (sensitivity);
``L:<model>`` and ``gap:<model>`` (coordinates); ``footer`` for the data notice.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib import ticker
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from lineload import models, paper
from lineload.figures.data import fit_row, model_curve_mm, trial_points
from lineload.figures.style import (
    DATA_COLOUR,
    DOUBLE_COLUMN_MM,
    MODEL_COLOURS,
    MODEL_LINESTYLES,
    MODEL_NAMES,
    SINGLE_COLUMN_MM,
    SPECIES_MARKERS,
    SPECIES_PLURAL,
    WINDOW_STYLE,
    add_footer,
    grid_shape,
    grid_ylabel,
    label_outer_axes,
    log_distance_axis,
    message_figure,
    new_figure,
    noted_legend,
    padded_limits,
    panel_title,
    styled,
    subject_table,
)
from lineload.fitting.families import FAMILIES
from lineload.fitting.sensitivity import MODEL_NAMES as REFIT_NAMES
from lineload.fitting.sensitivity import MODELS as REFIT_MODELS
from lineload.noise import reading_noise_mm

__all__ = [
    "figure_arc_vs_parabola",
    "figure_coordinates",
    "figure_mechanics",
    "figure_residuals",
    "figure_sensitivity",
]

#: Colour of each model of the sensitivity refits (:data:`lineload.fitting.sensitivity.MODELS`,
#: drawn in that order and named as the sensitivity tables name them).
REFIT_COLOURS = {model: FAMILIES[model].colour for model in REFIT_MODELS}
#: Depths side by side in the residual and parabola-against-arc supplements; more wrap.
DEPTHS_PER_ROW = 4


def depths_per_row(n_depths):
    """Panels side by side for n depths: all of them up to DEPTHS_PER_ROW, else rows as
    even as they can be (5 -> 3 + 2, 6 -> 3 + 3, 8 -> 4 + 4)."""
    n_rows = math.ceil(n_depths / DEPTHS_PER_ROW)
    return math.ceil(n_depths / n_rows)


# ---------------------------------------------------------------- residuals


@styled
def figure_residuals(averaged, fits, subjects, fit_window_mm, notice=""):
    """Supplement: data minus model for the four fits, by species and depth.

    Rows are species and columns the depths in the data; in each panel, every
    subject contributes one thin line per model, coloured by model, over the
    fitted points (``0 < distance <= fit_window_mm``).  All panels share both
    axes, so the size of the misfit can be compared across depths.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles (``subject``, ``depth_mm``, ``distance_mm``, ``deflection_mm``).
    fits : pandas.DataFrame
        The fit table.
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    fit_window_mm : float
        Outer edge of the fitted region (mm).
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Lines carry the gid ``residual:<model>:<subject>``.
    """
    table = subject_table(subjects)
    species_rows = [s for s in paper.SPECIES if (table["species"] == s).any()]
    depths = sorted({float(d) for d in averaged["depth_mm"]}) if not averaged.empty else []
    if not species_rows or not depths:
        return message_figure("No profiles in this dataset: no residuals to show.", notice)
    # at most DEPTHS_PER_ROW panels side by side; more depths wrap onto further rows
    per_row = depths_per_row(len(depths))
    depth_rows = [depths[i : i + per_row] for i in range(0, len(depths), per_row)]
    n_rows, n_columns = len(species_rows) * len(depth_rows), per_row
    width_mm = DOUBLE_COLUMN_MM if n_columns > 1 else SINGLE_COLUMN_MM
    fig = new_figure(width_mm, 26.0 + 48.0 * n_rows)
    axes = fig.subplots(n_rows, n_columns, squeeze=False, sharex=True, sharey=True)
    present = np.zeros(axes.shape, dtype=bool)
    all_x, all_r = [fit_window_mm], [0.0]
    for i, species in enumerate(species_rows):
        members = [s for s in table["subject"] if table.loc[s, "species"] == species]
        for k, depth_mm in enumerate(depths):
            cell = (i * len(depth_rows) + k // per_row, k % per_row)
            ax = axes[cell]
            present[cell] = True
            ax.axhline(0.0, color="0.6", linewidth=0.6, zorder=0)
            ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
            drawn = False
            for subject in members:
                distance_mm, deflection_mm = trial_points(averaged, subject, depth_mm)
                keep = (distance_mm > 0) & (distance_mm <= fit_window_mm)
                distance_mm, deflection_mm = distance_mm[keep], deflection_mm[keep]
                if distance_mm.size == 0:
                    continue
                row = fit_row(fits, subject, depth_mm)
                for model in ("boussinesq", "waterbed", "shifted", "arc"):
                    values = model_curve_mm(model, distance_mm, depth_mm, row)
                    if values is None:
                        continue
                    residual_mm = deflection_mm - values
                    ax.plot(
                        distance_mm,
                        residual_mm,
                        color=MODEL_COLOURS[model],
                        linewidth=0.8,
                        alpha=0.8,
                        marker="o",
                        markersize=1.6,
                        linestyle=MODEL_LINESTYLES[model],
                        gid=f"residual:{model}:{subject}",
                    )
                    all_x.append(distance_mm.min())
                    all_r.extend(residual_mm[np.isfinite(residual_mm)])
                    drawn = True
            if not drawn:
                ax.text(
                    0.5,
                    0.5,
                    "no data",
                    transform=ax.transAxes,
                    ha="center",
                    va="center",
                    color="0.4",
                )
            ax.set_title(
                f"{SPECIES_PLURAL[species].capitalize()}, {depth_mm:g} mm depth", loc="left"
            )
            log_distance_axis(ax)
    for ax in axes[~present]:
        fig.delaxes(ax)
    axes[0, 0].set_xlim(min(all_x) / 1.25, fit_window_mm * 1.25)
    axes[0, 0].set_ylim(*padded_limits(all_r))
    label_outer_axes(axes, present, "distance x (mm, log scale)", "data − model (mm)")
    handles = [
        Line2D(
            [],
            [],
            color=MODEL_COLOURS[m],
            marker="o",
            markersize=2,
            linestyle=MODEL_LINESTYLES[m],
            label=MODEL_NAMES[m],
        )
        for m in models.TABLE_MODELS
    ]
    handles.append(Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE))
    noted_legend(
        fig, handles, 3, "one line per subject and model; positive: skin deeper than the model"
    )
    add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- parabola against arc


def _shifted_largest_text(shifted_diff, depth_mm):
    """'shifted 1.2%', the shifted parabola's largest gap to eq. 19 over W0; where the
    shifted curve does not exist (``L <= sqrt(6) W0``, no point of it finite) says so."""
    finite = np.abs(shifted_diff[np.isfinite(shifted_diff)])
    if not finite.size:
        return "shifted: none (L ≤ √6 W₀)"
    return f"shifted {100 * float(finite.max()) / depth_mm:.1f}%"


@styled
def figure_arc_vs_parabola(fits, notice=""):
    """Supplement: the small-slope parabola (eq. 19) against the exact arc, per depth.

    For each depth in the fit table, three shapes are drawn with W0 = depth and
    the median fitted waterbed half-width L of that depth (top row): eq. 19 read
    at x as if it were X (the paper's procedure), the same parabola placed at
    ``x = X + U(X)`` (measured coordinates) and the exact arc.  The bottom row
    shows each of the other two minus the paper's parabola at equal horizontal
    distance for the median L (thick) and arc minus parabola for each trial's
    own fitted L (thin).

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``depth_mm``, ``waterbed_L_mm``).
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Lines carry the gids ``parabola``, ``shifted``, ``arc``,
        ``difference:median``, ``difference:shifted`` and ``difference:trial``.
    """
    usable = fits[np.isfinite(fits["waterbed_L_mm"].astype(float))]
    depths = sorted({float(d) for d in usable["depth_mm"]})
    if not depths:
        return message_figure("No finite waterbed fits in this dataset.", notice)
    # a pair of rows (shapes, differences) per row of depths
    n_columns = depths_per_row(len(depths))
    n_pairs = math.ceil(len(depths) / n_columns)
    width_mm = DOUBLE_COLUMN_MM if n_columns > 1 else SINGLE_COLUMN_MM
    fig = new_figure(width_mm, 112.0 if n_pairs == 1 else 20.0 + 92.0 * n_pairs)
    grid = fig.subplots(
        2 * n_pairs,
        n_columns,
        squeeze=False,
        sharex=True,
        sharey="row",
        height_ratios=[1.3, 1.0] * n_pairs,
    )
    present = np.zeros(grid.shape, dtype=bool)
    profiles, differences = [0.0], [0.0]
    x_hi = 0.0
    for k, depth_mm in enumerate(depths):
        pair, j = divmod(k, n_columns)
        present[2 * pair : 2 * pair + 2, j] = True
        L_values = np.sort(
            usable.loc[np.isclose(usable["depth_mm"].astype(float), depth_mm), "waterbed_L_mm"]
            .astype(float)
            .to_numpy()
        )
        L_median = float(np.median(L_values))
        x_hi = max(x_hi, float(L_values.max()))
        distance_mm = np.linspace(0.0, L_median, 400)
        parabola = models.waterbed_deflection_mm(distance_mm, depth_mm, L_median)
        shifted = models.shifted_deflection_mm(distance_mm, depth_mm, L_median)
        arc = models.arc_deflection_mm(distance_mm, depth_mm, L_median)
        top, bottom = grid[2 * pair, j], grid[2 * pair + 1, j]
        top.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
        top.plot(
            distance_mm, parabola, color=MODEL_COLOURS["waterbed"], linestyle="--", gid="parabola"
        )
        top.plot(
            distance_mm,
            shifted,
            color=MODEL_COLOURS["shifted"],
            linestyle=MODEL_LINESTYLES["shifted"],
            gid="shifted",
        )
        top.plot(distance_mm, arc, color=MODEL_COLOURS["arc"], gid="arc")
        profiles.extend([*parabola, *arc[np.isfinite(arc)], *shifted[np.isfinite(shifted)]])
        for L_mm in L_values:
            d_mm = np.linspace(0.0, L_mm, 300)
            diff = models.arc_deflection_mm(d_mm, depth_mm, L_mm) - models.waterbed_deflection_mm(
                d_mm, depth_mm, L_mm
            )
            bottom.plot(d_mm, diff, color="0.6", linewidth=0.5, gid="difference:trial")
            differences.extend(diff[np.isfinite(diff)])
        shifted_diff = shifted - parabola
        bottom.plot(
            distance_mm,
            shifted_diff,
            color=MODEL_COLOURS["shifted"],
            linestyle=MODEL_LINESTYLES["shifted"],
            linewidth=1.3,
            gid="difference:shifted",
        )
        differences.extend(shifted_diff[np.isfinite(shifted_diff)])
        diff = arc - parabola
        bottom.plot(distance_mm, diff, color=DATA_COLOUR, linewidth=1.3, gid="difference:median")
        bottom.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
        largest = float(np.nanmax(np.abs(diff))) / depth_mm
        top.set_title(f"{depth_mm:g} mm depth", loc="left")
        top.text(
            0.96,
            0.04,
            f"L = {L_median:.1f} mm ({L_values.size} fit{'s' if L_values.size > 1 else ''})\n"
            f"W₀/L = {depth_mm / L_median:.3f}",
            transform=top.transAxes,
            ha="right",
            va="bottom",
            in_layout=False,
        )
        bottom.text(
            0.04,
            0.96,
            f"largest / W₀:\narc {100 * largest:.1f}%\n"
            + _shifted_largest_text(shifted_diff, depth_mm),
            transform=bottom.transAxes,
            ha="left",
            va="top",
            in_layout=False,
        )
    for ax in grid[~present]:
        fig.delaxes(ax)
    grid[0, 0].set_xlim(0.0, x_hi * 1.02)
    profile_lo, profile_hi = padded_limits(profiles, 0.04)
    lo, hi = padded_limits(differences, 0.1)
    for pair in range(n_pairs):
        grid[2 * pair, 0].set_ylim(profile_hi, profile_lo)
        grid[2 * pair + 1, 0].set_ylim(lo, hi + 1.2 * (hi - lo))
        grid[2 * pair, 0].set_ylabel("deflection w (mm)")
        grid[2 * pair + 1, 0].set_ylabel("minus eq. 19 (mm)")
    for j in range(n_columns):
        lowest = grid[np.flatnonzero(present[:, j])[-1], j]
        lowest.set_xlabel("distance x (mm)")
        lowest.tick_params(labelbottom=True)
    handles = [
        Line2D(
            [],
            [],
            color=MODEL_COLOURS["waterbed"],
            linestyle="--",
            label="parabola, eq. 19 (small slope)",
        ),
        Line2D(
            [],
            [],
            color=MODEL_COLOURS["shifted"],
            linestyle=MODEL_LINESTYLES["shifted"],
            label="same parabola at x = X + U (eqs 19-20)",
        ),
        Line2D([], [], color=MODEL_COLOURS["arc"], label="exact arc (same W₀, L)"),
        Line2D(
            [],
            [],
            color=DATA_COLOUR,
            linewidth=1.3,
            label="arc − parabola at the median L",
        ),
        Line2D(
            [],
            [],
            color=MODEL_COLOURS["shifted"],
            linestyle=MODEL_LINESTYLES["shifted"],
            linewidth=1.3,
            label="shifted − parabola at the median L",
        ),
        Line2D([], [], color="0.6", linewidth=0.5, label="arc − parabola at each trial's L"),
    ]
    noted_legend(fig, handles, 2, "shapes drawn with W₀ = depth and the median fitted waterbed L")
    add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- sensitivity


@styled
def figure_sensitivity(sensitivity, checks, notice=""):
    """Supplement: how the fits depend on the analysis choices, trial by trial.

    Four panels: (a) the fitted L of each waterbed variant in each fit window;
    (b) each model's AICc minus the best in that window; (c) the largest
    horizontal shift of the small-slope solution relative to X at L/3, with the
    paper's bound (:data:`lineload.paper.MAX_SHIFT_FRACTION`); (d) the distance
    up to which the waterbed stays within tolerance of the data, with the
    distance the paper says the fit holds to (:data:`lineload.paper.REACH_MM`).

    Parameters
    ----------
    sensitivity : pandas.DataFrame
        Rows of ``lineload.fitting.sensitivity.SENSITIVITY_COLUMNS``.
    checks : pandas.DataFrame
        Rows of ``lineload.fitting.sensitivity.CHECK_COLUMNS``.
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Point collections carry gids ``L:<model>``, ``aicc:<model>``, ``shift``
        and ``reach``.
    """
    if sensitivity is None or len(sensitivity) == 0:
        return message_figure("No sensitivity refits in this dataset.", notice)
    windows = list(dict.fromkeys(sensitivity["window"]))
    fig = new_figure(DOUBLE_COLUMN_MM, 120.0)
    (ax_L, ax_aicc), (ax_shift, ax_reach) = fig.subplots(2, 2)
    shift_limit, reach_claim_mm = paper.MAX_SHIFT_FRACTION, paper.REACH_MM
    width = 0.8 / len(REFIT_MODELS)
    for k, model in enumerate(REFIT_MODELS):
        colour, name = REFIT_COLOURS[model], REFIT_NAMES[model]
        rows = sensitivity[sensitivity["model"] == model]
        for axis, column, kind in ((ax_L, "L_mm", "L"), (ax_aicc, "delta_aicc", "aicc")):
            if kind == "L" and "L_mm" not in FAMILIES[model].results:
                continue
            x, y = [], []
            for i, window in enumerate(windows):
                values = rows.loc[rows["window"] == window, column].astype(float).to_numpy()
                values = values[np.isfinite(values)]
                # spread a window's trials evenly across the model's slot (no randomness)
                spread = np.linspace(-0.35, 0.35, values.size) * width if values.size > 1 else [0]
                x.extend(i - 0.4 + (k + 0.5) * width + np.asarray(spread))
                y.extend(values)
            axis.scatter(x, y, s=6, color=colour, label=name, gid=f"{kind}:{model}", linewidths=0)
    for axis in (ax_L, ax_aicc):
        axis.set_xticks(range(len(windows)), [f"window {w}" for w in windows])
        axis.set_xlim(-0.5, len(windows) - 0.5)
    ax_L.set_ylabel("fitted L (mm)")
    ax_L.set_title("(a) membrane half-width by fit window", loc="left")
    ax_aicc.set_yscale("symlog", linthresh=2.0)
    # plain numbers (0, 1, 10, 100): matplotlib's 10^k puts the exponent in small type
    ax_aicc.yaxis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    largest = float(np.nanmax(sensitivity["delta_aicc"].astype(float)))
    # differences are >= 0 by construction; a little room below keeps the zeros visible
    ax_aicc.set_ylim(-0.3, max(10.0, 2.0 * largest))
    ax_aicc.set_ylabel("AICc minus best in window")
    ax_aicc.set_title("(b) model comparison by fit window", loc="left")
    depths = sorted({float(d) for d in checks["depth_mm"]})
    for species, marker in SPECIES_MARKERS.items():
        rows = checks[checks["species"] == species]
        if rows.empty:
            continue
        offset = -0.04 if species == "monkey" else 0.04
        ax_shift.scatter(
            rows["depth_mm"] + offset,
            100 * rows["shift_fraction_at_third"],
            marker=marker,
            s=10,
            facecolors="none",
            edgecolors=DATA_COLOUR,
            linewidths=0.7,
            label=SPECIES_PLURAL[species],
            gid="shift",
        )
        ax_reach.scatter(
            rows["depth_mm"] + offset,
            rows["reach_mm"],
            marker=marker,
            s=10,
            facecolors="none",
            edgecolors=DATA_COLOUR,
            linewidths=0.7,
            label=SPECIES_PLURAL[species],
            gid="reach",
        )
    ax_shift.axhline(100 * shift_limit, color="0.5", linestyle=":", linewidth=0.8)
    # below its line: above it, the label would run into the panel title when the
    # bound is near the top of the axis
    ax_shift.annotate(
        f"paper's bound {100 * shift_limit:g} %",
        xy=(depths[0] - 0.2, 100 * shift_limit),
        xytext=(0, -2),
        textcoords="offset points",
        va="top",
        fontsize=7,
        color="0.4",
    )
    ax_shift.set_ylabel("largest |U| / X at L/3 (%)")
    ax_shift.set_title("(c) horizontal shift of the membrane", loc="left")
    ax_reach.axhline(reach_claim_mm, color="0.5", linestyle=":", linewidth=0.8)
    ax_reach.text(
        depths[0] - 0.2,
        reach_claim_mm,
        f"paper: about {reach_claim_mm:g} mm",
        va="bottom",
        fontsize=7,
        color="0.4",
    )
    tolerance = checks["reach_tolerance_mm"] / checks["depth_mm"]
    ax_reach.set_ylabel(f"fit holds to (mm; within {tolerance.iloc[0]:.0%} of depth)")
    ax_reach.set_title("(d) how far the waterbed follows the data", loc="left")
    for axis in (ax_shift, ax_reach):
        axis.set_xticks(depths, [f"{d:g}" for d in depths])
        axis.set_xlim(depths[0] - 0.3, depths[-1] + 0.3)
        axis.set_xlabel("indentation depth (mm)")
        axis.set_ylim(bottom=0)
    handles, labels = ax_aicc.get_legend_handles_labels()
    species_handles, species_labels = ax_shift.get_legend_handles_labels()
    fig.legend(
        handles + species_handles,
        labels + species_labels,
        loc="outside upper center",
        ncol=3,
        frameon=False,
        markerscale=2.0,
    )
    add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- coordinates


@styled
def figure_coordinates(fits, checks, noise=None, noise_mm=None, notice=""):
    """Supplement: what the paper's coordinate approximation costs, trial by trial.

    (a) L fitted in measured coordinates (the shifted parabola and the exact
    arc) against L fitted the paper's way, each with its 95 % interval, and the
    line of equality; (b) the largest vertical gap, over the fitted range,
    between each of those fitted curves and the paper's, by depth, with the
    digitising noise of one reading.

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``species``, ``depth_mm`` and the ``waterbed_``, ``shifted_``
        and ``arc_`` L columns with their intervals).
    checks : pandas.DataFrame
        Per-trial checks with ``gap_shifted_mm`` and ``gap_arc_mm``.
    noise : pandas.DataFrame, optional
        The noise table (``parameter``, ``value``): one reading's noise, drawn as
        a line in (b), is its reading and tracing errors together.
    noise_mm : float, optional
        One reading's noise as configured, instead of the table's (one of the
        two is needed).
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Point collections carry gids ``L:<model>`` and ``gap:<model>``.
    """
    noise_mm = reading_noise_mm(noise, noise_mm)
    usable = fits[np.isfinite(fits["waterbed_L_mm"].astype(float))]
    if usable.empty:
        return message_figure("No finite waterbed fits in this dataset.", notice)
    fig = new_figure(DOUBLE_COLUMN_MM, 82.0)
    ax_L, ax_gap = fig.subplots(1, 2)
    consistent = ("shifted", "arc")
    L_paper = usable["waterbed_L_mm"].astype(float).to_numpy()
    limits = [L_paper.min(), L_paper.max()]
    for model in consistent:
        for species, marker in SPECIES_MARKERS.items():
            rows = usable[usable["species"] == species]
            if rows.empty:
                continue
            x = rows["waterbed_L_mm"].astype(float).to_numpy()
            y = rows[f"{model}_L_mm"].astype(float).to_numpy()
            y_err = np.abs(
                np.vstack(
                    [
                        y - rows[f"{model}_L_ci_low_mm"].astype(float).to_numpy(),
                        rows[f"{model}_L_ci_high_mm"].astype(float).to_numpy() - y,
                    ]
                )
            )
            x_err = np.abs(
                np.vstack(
                    [
                        x - rows["waterbed_L_ci_low_mm"].astype(float).to_numpy(),
                        rows["waterbed_L_ci_high_mm"].astype(float).to_numpy() - x,
                    ]
                )
            )
            ax_L.errorbar(
                x,
                y,
                xerr=np.where(np.isfinite(x_err), x_err, 0.0),
                yerr=np.where(np.isfinite(y_err), y_err, 0.0),
                fmt="none",
                ecolor=MODEL_COLOURS[model],
                elinewidth=0.4,
                alpha=0.5,
            )
            ax_L.scatter(
                x,
                y,
                marker=marker,
                s=12,
                facecolors="none",
                edgecolors=MODEL_COLOURS[model],
                linewidths=0.8,
                gid=f"L:{model}",
            )
            limits.extend(y[np.isfinite(y)])
    lo, hi = padded_limits(limits, 0.05)
    ax_L.plot([lo, hi], [lo, hi], color="0.5", linewidth=0.7, linestyle=":", zorder=0)
    ax_L.set_xlim(lo, hi)
    ax_L.set_ylim(lo, hi)
    ax_L.set_aspect("equal", adjustable="box")
    ax_L.set_xlabel("L, paper's procedure (mm)")
    ax_L.set_ylabel("L in measured coordinates (mm)")
    ax_L.set_title("(a) fitted half-width", loc="left")
    depths = sorted({float(d) for d in checks["depth_mm"]}) if len(checks) else []
    gaps = [noise_mm]
    for k, model in enumerate(consistent):
        for species, marker in SPECIES_MARKERS.items():
            rows = checks[checks["species"] == species]
            if rows.empty:
                continue
            offset = (-0.06 if species == "monkey" else 0.06) + (k - 0.5) * 0.05
            values = rows[f"gap_{model}_mm"].astype(float).to_numpy()
            ax_gap.scatter(
                rows["depth_mm"].astype(float).to_numpy() + offset,
                values,
                marker=marker,
                s=12,
                facecolors="none",
                edgecolors=MODEL_COLOURS[model],
                linewidths=0.8,
                gid=f"gap:{model}",
            )
            gaps.extend(values[np.isfinite(values)])
    # the noise line is named in the legend: a label on the line would sit on the points
    ax_gap.axhline(noise_mm, color="0.5", linestyle=":", linewidth=0.8)
    if depths:
        ax_gap.set_xticks(depths, [f"{d:g}" for d in depths])
        ax_gap.set_xlim(depths[0] - 0.3, depths[-1] + 0.3)
    ax_gap.set_ylim(0.0, 1.15 * max(gaps))
    ax_gap.set_xlabel("indentation depth (mm)")
    ax_gap.set_ylabel("largest gap to the paper's curve (mm)")
    ax_gap.set_title("(b) how far the fitted curve moves", loc="left")
    handles = [
        Line2D(
            [],
            [],
            linestyle="none",
            marker="o",
            markerfacecolor="none",
            markeredgecolor=MODEL_COLOURS[m],
            label=MODEL_NAMES[m],
        )
        for m in consistent
    ] + [
        Line2D(
            [],
            [],
            linestyle="none",
            marker=marker,
            markerfacecolor="none",
            markeredgecolor=DATA_COLOUR,
            label=SPECIES_PLURAL[species],
        )
        for species, marker in SPECIES_MARKERS.items()
        if len(checks) and (checks["species"] == species).any()  # only those drawn
    ]
    handles.append(
        Line2D(
            [],
            [],
            color="0.5",
            linestyle=":",
            linewidth=0.8,
            # two significant figures: the measured noise is known to a few per cent
            label=f"(b) digitising noise of one reading ({1000 * noise_mm:.2g} µm)",
        )
    )
    fig.legend(handles=handles, loc="outside upper center", ncols=3)
    add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- forces on the wedge

#: Colours and line styles of the force curves (Okabe-Ito).
FORCE_STYLES = {
    "stress_free": {
        "color": "#D55E00",
        "linestyle": "--",
        "label": "stress-free membrane, N = Eε (eq. 7)",
    },
    "tension_only": {
        "color": "0.45",
        "linestyle": ":",
        "label": "tension at rest alone, N = N₀",
    },
    "fitted": {
        "color": "#0072B2",
        "linestyle": "-",
        "label": "fit with tension at rest, N = N₀ + Eε",
    },
}
#: Fill of the paper's force range (absolute mode) or its largest ratio (relative mode).
PAPER_BAND = {"color": "#F0E442", "alpha": 0.25, "linewidth": 0}


@styled
def figure_mechanics(mechanics_trials, mechanics, subjects, notice=""):
    """Supplement: force on the wedge against depth, one panel per subject, log-log.

    With force readings (any finite ``force_N``), each panel shows the readings,
    the stress-free membrane of the paper's eq. 7 with each trial's fitted
    exact-arc shape (force proportional to ``eps sin(theta0)``) and a membrane
    held by its tension alone (proportional to ``sin(theta0)``), both scaled to
    the reading at the subject's smallest depth, the pre-tensioned fit
    (``fitted_force_N``), and the paper's 0.3-1 N as a band.  Without any
    readings, the same two model curves are drawn relative to the smallest
    depth, against the largest ratio the paper's range allows.  Model values
    exist only at the measured depths (each has its own fitted L); lines join them.

    Parameters
    ----------
    mechanics_trials : pandas.DataFrame
        Rows of :data:`lineload.mechanics.TRIAL_COLUMNS`.
    mechanics : pandas.DataFrame
        Rows of :data:`lineload.mechanics.SUBJECT_COLUMNS` (may be empty).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``, in sheet order.
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Lines carry gids ``force:<subject>`` (readings), ``stress_free:<subject>``,
        ``tension_only:<subject>`` and ``fitted:<subject>``; bands ``paper-range``.
    """
    table = subject_table(subjects)
    trials = mechanics_trials.copy() if mechanics_trials is not None else None
    if trials is None or trials.empty:
        return message_figure("No fitted trials in this dataset: no forces to show.", notice)
    trials["subject"] = trials["subject"].astype(str)
    angle = trials["load_angle_rad"].astype(float).to_numpy()
    trials["u"] = np.sin(angle)
    trials["v"] = trials["strain"].astype(float).to_numpy() * trials["u"]
    usable = np.isfinite(trials["v"].to_numpy(float))
    members = [
        s
        for s in table["subject"]
        if trials.loc[(trials["subject"] == s) & usable, "depth_mm"].nunique() >= 2
    ]
    if not members:
        return message_figure(
            "No subject has fitted shapes at two or more depths: no force ratio to show.",
            notice,
        )
    forces = trials["force_N"].astype(float).to_numpy()
    absolute = bool(np.isfinite(forces).any())
    fits = {} if mechanics is None else {str(r.subject): r for r in mechanics.itertuples()}
    low_N, high_N = paper.FORCE_RANGE_N
    # four panels a row; beyond five rows the rows shrink to keep the figure on a page
    n_rows, n_columns = grid_shape(len(members), max_columns=4)
    width_mm = DOUBLE_COLUMN_MM if n_columns > 1 else SINGLE_COLUMN_MM
    fig = new_figure(width_mm, 24.0 + min(44.0, 212.0 / n_rows) * n_rows)
    axes = fig.subplots(n_rows, n_columns, squeeze=False, sharex=True, sharey=True)
    present = np.zeros(axes.shape, dtype=bool)
    depths_all, values_all = (
        [],
        [low_N, high_N] if absolute else [1.0, paper.FORCE_RANGE_N[1] / low_N],
    )
    for k, subject in enumerate(members):
        i, j = divmod(k, n_columns)
        ax, present[i, j] = axes[i, j], True
        rows = trials[(trials["subject"] == subject) & usable].sort_values("depth_mm")
        depth = rows["depth_mm"].to_numpy(float)
        u, v = rows["u"].to_numpy(float), rows["v"].to_numpy(float)
        force = rows["force_N"].to_numpy(float)
        depths_all.extend(depth)
        if absolute:
            ax.axhspan(low_N, high_N, gid="paper-range", **PAPER_BAND)
            measured = np.isfinite(force)
            if measured.any():
                first = int(np.argmax(measured))
                scale_v, scale_u = force[first] / v[first], force[first] / u[first]
                curves = {"stress_free": scale_v * v, "tension_only": scale_u * u}
                fitted = rows["fitted_force_N"].to_numpy(float)
                if np.isfinite(fitted).any():
                    curves["fitted"] = fitted
                for name, values in curves.items():
                    style = {k: val for k, val in FORCE_STYLES[name].items() if k != "label"}
                    ok = np.isfinite(values)
                    ax.plot(depth[ok], values[ok], gid=f"{name}:{subject}", **style)
                    values_all.extend(values[ok])
                ax.plot(
                    depth[measured],
                    force[measured],
                    linestyle="none",
                    marker="o",
                    markersize=3.5,
                    color=DATA_COLOUR,
                    gid=f"force:{subject}",
                )
                values_all.extend(force[measured])
                fit = fits.get(subject)
                if fit is not None and np.isfinite(fit.prestrain):
                    ax.text(
                        0.04,
                        0.96,
                        f"pre-strain {fit.prestrain:.2f} ± {fit.prestrain_se:.2f}",
                        transform=ax.transAxes,
                        ha="left",
                        va="top",
                        fontsize=7,
                    )
            else:
                ax.text(
                    0.5,
                    0.5,
                    "no force readings",
                    transform=ax.transAxes,
                    ha="center",
                    va="center",
                    color="0.4",
                )
        else:
            ax.axhspan(1.0, high_N / low_N, gid="paper-range", **PAPER_BAND)
            curves = {"stress_free": v / v[0], "tension_only": u / u[0]}
            for name, values in curves.items():
                style = {k: val for k, val in FORCE_STYLES[name].items() if k != "label"}
                ax.plot(depth, values, marker=".", gid=f"{name}:{subject}", **style)
                values_all.extend(values)
            ax.text(
                0.04,
                0.96,
                f"stress-free ×{v[-1] / v[0]:.0f}",
                transform=ax.transAxes,
                ha="left",
                va="top",
                fontsize=7,
            )
        ax.set_title(
            panel_title(table.loc[subject, "label"], table.loc[subject, "species"]), loc="left"
        )
    for i in range(n_rows):
        for j in range(n_columns):
            if not present[i, j]:
                fig.delaxes(axes[i, j])
    ax0 = axes[0, 0]
    ax0.set_xscale("log")
    ax0.set_yscale("log")
    depth_ticks = sorted(set(depths_all))
    if len(depth_ticks) > 4:  # a narrow log axis holds about four labels
        depth_ticks = [depth_ticks[round(i)] for i in np.linspace(0, len(depth_ticks) - 1, 4)]
    ax0.set_xticks(depth_ticks, [f"{d:g}" for d in depth_ticks])
    ax0.xaxis.set_minor_formatter(ticker.NullFormatter())
    ax0.set_xlim(min(depths_all) / 1.15, max(depths_all) * 1.15)
    values_all = np.asarray(values_all, dtype=float)
    values_all = values_all[np.isfinite(values_all) & (values_all > 0)]
    ax0.set_ylim(values_all.min() / 1.3, values_all.max() * 1.3)
    ax0.yaxis.set_major_locator(ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax0.yaxis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    ax0.yaxis.set_minor_formatter(ticker.NullFormatter())
    # labels on the outer panels (short: neighbouring panels' labels would collide);
    # one y label for the whole grid
    label_outer_axes(axes, present, "depth (mm, log scale)", "")
    ylabel = (
        "force on the wedge (N, log scale)"
        if absolute
        # relative to what, the legend's title says
        else "relative force (log scale)"
    )
    handles = []
    if absolute:
        handles.append(
            Line2D([], [], linestyle="none", marker="o", color=DATA_COLOUR, label="force readings")
        )
    names = (
        ("stress_free", "tension_only", "fitted") if absolute else ("stress_free", "tension_only")
    )
    for name in names:
        style = FORCE_STYLES[name]
        handles.append(
            Line2D([], [], color=style["color"], linestyle=style["linestyle"], label=style["label"])
        )
    band_label = (
        f"paper's {low_N:g}-{high_N:g} N"
        if absolute
        else f"ratios inside the paper's {low_N:g}-{high_N:g} N (up to {high_N / low_N:.2f})"
    )
    handles.append(Patch(label=band_label, **PAPER_BAND))
    title = (
        "model curves scaled to the reading at each subject's smallest depth; "
        "each depth uses its own fitted exact-arc L"
        if absolute
        else "no forces.csv: each model relative to its force at the subject's smallest depth"
    )
    fig.legend(handles=handles, loc="outside upper center", ncols=3, title=title, title_fontsize=7)
    add_footer(fig, notice)
    # placed last: the legend and the footer take their room first
    grid_ylabel(fig, axes[present], ylabel, fontsize=8)
    return fig
