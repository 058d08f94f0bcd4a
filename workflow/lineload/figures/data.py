"""Figures drawn from the measurements: outlines (1), examples (2) and per-species fits (6, 7).

Every function takes data (pandas DataFrames, plain numbers) and returns a
:class:`matplotlib.figure.Figure`; parameter names are those of
:data:`lineload.figures.registry.ARGUMENTS`.  Lengths are tissue millimetres and
deflection is downward positive, drawn on a downward axis.

gids: ``outline:resting``, ``outline:deformed`` and ``wedge`` in Figure 1;
``data``, ``model:waterbed``, ``model:boussinesq`` and ``fit-window`` in
Figure 2; ``data:<depth>``, ``model:<depth>`` and ``fit-window`` in Figures 6
and 7; ``footer`` for the data notice.
"""

from __future__ import annotations

import matplotlib
import numpy as np
from matplotlib import patches
from matplotlib.lines import Line2D

from lineload.figures.style import (
    DATA_COLOUR,
    DEFLECTION_LABEL,
    DISTANCE_LABEL,
    DOUBLE_COLUMN_MM,
    LEGEND_ROW_MM,
    MM_PER_INCH,
    MODEL_COLOURS,
    NOTE_FONT_PT,
    REST_COLOUR,
    SINGLE_COLUMN_MM,
    WINDOW_STYLE,
    add_footer,
    depth_colours,
    grid_legend,
    grid_shape,
    label_outer_axes,
    legend_columns,
    log_distance_axis,
    message_figure,
    new_figure,
    padded_limits,
    panel_title,
    styled,
    subject_table,
    wrapped_note,
)
from lineload.fitting.families import FAMILIES, curve_mm

__all__ = [
    "EXAMPLE_FAMILIES",
    "data_handle",
    "deflection_limits",
    "draw_fitted_trial",
    "example_per_species",
    "figure_digitised",
    "figure_examples",
    "figure_outlines",
    "figure_species_fits",
    "fit_row",
    "model_curve_mm",
    "trial_points",
]


# ---------------------------------------------------------------- reading the tables


def trial_points(averaged, subject, depth_mm):
    """Finite averaged points of one subject at one depth, sorted by distance.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles (``subject``, ``depth_mm``, ``distance_mm``, ``deflection_mm``).
    subject : str
    depth_mm : float

    Returns
    -------
    distance_mm, deflection_mm : numpy.ndarray
        Empty when the subject has no profile at that depth.
    """
    rows = averaged[
        (averaged["subject"] == subject) & np.isclose(averaged["depth_mm"].astype(float), depth_mm)
    ]
    rows = rows[np.isfinite(rows["deflection_mm"].astype(float))]
    rows = rows.sort_values("distance_mm", kind="stable")
    return rows["distance_mm"].to_numpy(float), rows["deflection_mm"].to_numpy(float)


def fit_row(fits, subject, depth_mm):
    """The fit-table row of one subject and depth.

    Returns
    -------
    pandas.Series or None
        None when the table has no such row.
    """
    rows = fits[(fits["subject"] == subject) & np.isclose(fits["depth_mm"].astype(float), depth_mm)]
    return None if rows.empty else rows.iloc[0]


def example_per_species(fitted, subjects, prefer_depth_mm=None):
    """One fitted trial per species: the species' first subject (sheet order) with a row
    in ``fitted``, at ``prefer_depth_mm`` if fitted there, else at its deepest depth.

    Parameters
    ----------
    fitted : pandas.DataFrame
        The trials that have the fit to be drawn (``subject``, ``depth_mm``).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    prefer_depth_mm : float, optional
        The depth to show where the subject was fitted there.

    Returns
    -------
    tuple
        ``(chosen, table)``: ``(subject, species, depth_mm)`` for monkeys then humans
        (a species without a fitted trial left out), and the subject table.
    """
    table = subject_table(subjects)
    chosen = []
    for species in ("monkey", "human"):
        for subject in table.index[table["species"] == species]:
            depths = fitted.loc[fitted["subject"] == subject, "depth_mm"].astype(float)
            if len(depths):
                preferred = (
                    np.isclose(depths, prefer_depth_mm)
                    if prefer_depth_mm is not None
                    else np.zeros(len(depths), bool)
                )
                depth_mm = float(depths[preferred].iloc[0] if preferred.any() else depths.max())
                chosen.append((subject, species, depth_mm))
                break
    return chosen, table


#: Deflection of a fitted model at given distances, its parameters read from a fit-table
#: row (``model_curve_mm(model, distance_mm, depth_mm, row)``; None without a finite fit):
#: the registry's :func:`lineload.fitting.families.curve_mm`.
model_curve_mm = curve_mm


# ---------------------------------------------------------------- one trial against its fits

#: The families drawn in Figure 2, in drawing order.
EXAMPLE_FAMILIES = ("boussinesq", "waterbed")


def data_handle():
    """Legend entry of the averaged points (open circles)."""
    return Line2D(
        [],
        [],
        linestyle="none",
        marker="o",
        markerfacecolor="white",
        markeredgecolor=DATA_COLOUR,
        label="data (mean of left and right)",
    )


def draw_fitted_trial(
    ax,
    averaged,
    row,
    subject,
    depth_mm,
    families,
    fit_window_mm,
    reach_mm=0.0,
    n_curve=400,
    emphasis=None,
):
    """One trial's averaged points (x > 0) on a log distance axis, with its fitted families.

    Draws the fit window's edge, each family's curve where its fit is finite (its
    registry colour and line style, gid ``model:<family>``), the points (gid
    ``data``) and sets the distance limits: from the first point / 1.3 to the
    farthest of the last point and ``reach_mm``, times 1.3 (10 mm without points
    and reach).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    averaged : pandas.DataFrame
        Averaged profiles.
    row : pandas.Series or None
        The trial's row of a table with the families' columns (:func:`fit_row`).
    subject : str
    depth_mm : float
    families : sequence of str
        Keys of :data:`lineload.fitting.families.FAMILIES`, in drawing order.
    fit_window_mm : float
    reach_mm : float, optional
        Distance the axis reaches at least (before the margin).
    n_curve : int, optional
        Points of each curve.
    emphasis : dict of str to dict, optional
        Further line properties of some families' curves, by family.

    Returns
    -------
    list of numpy.ndarray
        What was drawn (curves, then the points), for :func:`deflection_limits`.
    """
    distance_mm, deflection_mm = trial_points(averaged, subject, depth_mm)
    keep = distance_mm > 0
    distance_mm, deflection_mm = distance_mm[keep], deflection_mm[keep]
    lo = distance_mm.min() / 1.3 if distance_mm.size else 0.05
    far_mm = max(distance_mm.max() if distance_mm.size else 0.0, reach_mm)
    hi = far_mm * 1.3 if far_mm > 0 else 10.0
    grid_mm = np.geomspace(lo, hi, n_curve)
    ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
    drawn = []
    for name in families:
        values = curve_mm(name, grid_mm, depth_mm, row)
        if values is not None:
            entry = FAMILIES[name]
            ax.plot(
                grid_mm,
                values,
                color=entry.colour,
                linestyle=entry.linestyle,
                gid=f"model:{name}",
                **(emphasis or {}).get(name, {}),
            )
            drawn.append(values)
    ax.plot(
        distance_mm,
        deflection_mm,
        linestyle="none",
        marker="o",
        markersize=3.2,
        markerfacecolor="white",
        markeredgecolor=DATA_COLOUR,
        markeredgewidth=0.8,
        color=DATA_COLOUR,
        gid="data",
        zorder=3,
    )
    drawn.append(deflection_mm)
    log_distance_axis(ax)
    ax.set_xlim(lo, hi)
    ax.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
    return drawn


def deflection_limits(drawn, depth_mm):
    """Deflection-axis limits holding what was drawn and zero, curves clipped to
    ``[-0.6, 1.3]`` times the depth (a far-off curve must not squash the data)."""
    values = np.concatenate([np.ravel(v) for v in drawn]) if drawn else np.array([])
    values = np.clip(values[np.isfinite(values)], -0.6 * depth_mm, 1.3 * depth_mm)
    return padded_limits(np.append(values, 0.0))


# ---------------------------------------------------------------- Figure 1


@styled
def figure_outlines(outlines, subjects, outline_subjects, outline_depth_mm, notice=""):
    """Figure 1: resting and deformed outlines of fingertips, drawn to scale.

    Parameters
    ----------
    outlines : pandas.DataFrame or None
        Outline points in tissue mm: ``subject``, ``depth_mm``, ``state``
        (``resting`` or ``deformed``), ``x_mm`` (wedge at 0) and ``z_mm``
        (upward positive).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    outline_subjects : list of str
        Subjects to draw, one panel each, top to bottom; empty gives a figure
        saying that the data hold no outlines.
    outline_depth_mm : float or None
        Indentation depth of the photographs to draw.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Panels share one millimetre scale on both axes (equal aspect, equal
        limits), so fingers can be compared by size.
    """
    if not outline_subjects or outline_depth_mm is None:
        return message_figure(
            "No outline files (outlines/<subject>.csv) in this dataset: there are no "
            "resting and deformed outlines to draw.",
            notice,
        )
    table = subject_table(subjects)
    selected = {}
    for subject in outline_subjects:
        rows = outlines[
            (outlines["subject"] == subject)
            & np.isclose(outlines["depth_mm"].astype(float), outline_depth_mm)
        ]
        selected[subject] = {
            state: rows[rows["state"] == state].sort_values("x_mm", kind="stable")
            for state in ("resting", "deformed")
        }
    all_x = np.concatenate([s[k]["x_mm"].to_numpy(float) for s in selected.values() for k in s])
    all_z = np.concatenate([s[k]["z_mm"].to_numpy(float) for s in selected.values() for k in s])
    half_span_mm = float(np.max(np.abs(all_x))) * 1.04 if all_x.size else 1.0
    wedge_top_mm = max(float(np.max(all_z)) if all_z.size else 0.0, 0.0) + 0.08 * half_span_mm
    wedge_half_angle = np.radians(12.0)
    z_lo = min(float(np.min(all_z)) if all_z.size else -outline_depth_mm, -outline_depth_mm)
    z_lo -= 0.03 * half_span_mm
    z_hi = wedge_top_mm + 0.02 * half_span_mm
    n = len(outline_subjects)
    width_mm = DOUBLE_COLUMN_MM
    axes_width_mm = width_mm - 14.0
    panel_height_mm = axes_width_mm * (z_hi - z_lo) / (2 * half_span_mm) + 9.0
    footer_mm = 5.0 if notice else 0.0
    fig = new_figure(width_mm, n * panel_height_mm + 12.0 + footer_mm, layout="compressed")
    axes = fig.subplots(n, 1, squeeze=False, sharex=True, sharey=True)[:, 0]
    for ax, subject in zip(axes, outline_subjects, strict=True):
        for state, style in (
            ("resting", {"color": REST_COLOUR, "linestyle": "--", "linewidth": 1.0}),
            ("deformed", {"color": DATA_COLOUR, "linestyle": "-", "linewidth": 1.2}),
        ):
            rows = selected[subject][state]
            for side in (rows[rows["x_mm"] <= 0], rows[rows["x_mm"] >= 0]):
                ax.plot(side["x_mm"], side["z_mm"], gid=f"outline:{state}", **style)
        apex_z = -outline_depth_mm
        half_top = (wedge_top_mm - apex_z) * np.tan(wedge_half_angle)
        ax.add_patch(
            patches.Polygon(
                [(0.0, apex_z), (-half_top, wedge_top_mm), (half_top, wedge_top_mm)],
                closed=True,
                facecolor="0.8",
                edgecolor="0.3",
                linewidth=0.6,
                gid="wedge",
                zorder=3,
            )
        )
        species = table.loc[subject, "species"] if subject in table.index else ""
        label = table.loc[subject, "label"] if subject in table.index else subject
        ax.set_title(
            f"{panel_title(label, species)}, wedge {outline_depth_mm:g} mm deep", loc="left"
        )
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlim(-half_span_mm, half_span_mm)
        ax.set_ylim(z_lo, z_hi)
        ax.set_ylabel("height z (mm)")
    axes[-1].set_xlabel("horizontal position x (mm; wedge at 0)")
    handles = [
        Line2D([], [], color=REST_COLOUR, linestyle="--", label="resting outline"),
        Line2D([], [], color=DATA_COLOUR, linestyle="-", label="deformed outline"),
        patches.Patch(facecolor="0.8", edgecolor="0.3", linewidth=0.6, label="wedge (schematic)"),
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=3)
    add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- Figure 2


@styled
def figure_examples(
    averaged,
    fits,
    subjects,
    example_subjects,
    example_depth_mm,
    fit_window_mm,
    example_note="",
    notice="",
):
    """Figure 2: one depth on a log distance axis, data against both fitted models.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles: ``subject``, ``depth_mm``, ``distance_mm``,
        ``deflection_mm`` (left/right mean).
    fits : pandas.DataFrame
        The fit table (``subject``, ``depth_mm``, ``waterbed_L_mm``,
        ``boussinesq_A_mm``, ``boussinesq_x0_mm``...).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    example_subjects : list of str
        One panel per subject, left to right.
    example_depth_mm : float or None
        The indentation depth shown (None: the dataset has no profiles).
    fit_window_mm : float
        Outer edge of the fitted region (mm), marked on every panel.
    example_note : str, optional
        How the depth was chosen, when it is not the paper's; printed as the
        title of the legend (gid ``note``).  Empty for none.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not example_subjects:
        where = "" if example_depth_mm is None else f" at {example_depth_mm:g} mm depth"
        return message_figure(f"No subject in this dataset has a profile{where}.", notice)
    table = subject_table(subjects)
    n = len(example_subjects)
    width_mm = SINGLE_COLUMN_MM if n == 1 else DOUBLE_COLUMN_MM
    # side by side up to two subjects (as in the paper), then rows of three
    n_rows, n_columns = (1, n) if n <= 2 else grid_shape(n, 3)
    fig = new_figure(width_mm, 72.0 + 56.0 * (n_rows - 1))
    grid = fig.subplots(n_rows, n_columns, squeeze=False, sharey=True)
    for ax in grid.flat[n:]:
        fig.delaxes(ax)
    axes = grid.flat[:n]
    y_values = []
    for ax, subject in zip(axes, example_subjects, strict=True):
        row = fit_row(fits, subject, example_depth_mm)
        y_values.extend(
            draw_fitted_trial(
                ax, averaged, row, subject, example_depth_mm, EXAMPLE_FAMILIES, fit_window_mm
            )
        )
        species = table.loc[subject, "species"] if subject in table.index else ""
        label = table.loc[subject, "label"] if subject in table.index else subject
        ax.set_title(f"{panel_title(label, species)}, {example_depth_mm:g} mm depth", loc="left")
        ax.set_xlabel(
            "distance from the wedge x (mm, log scale)" if n <= 2 else "distance x (mm, log scale)"
        )
    for ax in grid[:, 0]:
        ax.set_ylabel(DEFLECTION_LABEL)
    y_lo, y_hi = deflection_limits(y_values, example_depth_mm)
    axes[0].set_ylim(y_hi, y_lo)
    handles = [
        data_handle(),
        Line2D([], [], color=FAMILIES["waterbed"].colour, label="waterbed fit (eq. 19)"),
        Line2D([], [], color=FAMILIES["boussinesq"].colour, label="modified Boussinesq fit"),
        Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE),
    ]
    legend = fig.legend(
        handles=handles,
        loc="outside upper center",
        ncols=legend_columns(fig, handles, 4 if n > 1 else 2),
    )
    if example_note:  # above the key, where the layout keeps the panels clear of it
        legend.set_title(wrapped_note(fig, example_note), prop={"size": NOTE_FONT_PT})
        legend.get_title().set(gid="note", multialignment="center")
    add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- Figures 6 and 7


@styled
def figure_species_fits(averaged, fits, subjects, species, fit_window_mm, notice=""):
    """Figures 6 (monkeys) and 7 (humans): every depth of every subject with its waterbed fit.

    Panels follow the subject sheet (one per subject of the species, in its
    order) and each panel follows its data (one point series and one fitted
    line per depth present).  The colour of a depth is the same in every panel.
    The distance axis ends just beyond the farthest point of any subject of
    either species, so Figures 6 and 7 share one scale.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles of every subject (``subject``, ``depth_mm``,
        ``distance_mm``, ``deflection_mm``); all of them set the distance axis.
    fits : pandas.DataFrame
        The fit table (``subject``, ``depth_mm``, ``waterbed_L_mm``).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``, in display order.
    species : str
        ``monkey`` or ``human``.
    fit_window_mm : float
        Outer edge of the fitted region (mm), marked on every panel.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        With no subject of that species, one axis that says so.
    """
    table = subject_table(subjects)
    subject_ids = [s for s in table["subject"] if table.loc[s, "species"] == species]
    if not subject_ids:
        return message_figure(f"No {species} subjects in this dataset.", notice)
    rows = averaged[averaged["subject"].isin(subject_ids)]
    colours = depth_colours(rows["depth_mm"].astype(float))
    n = len(subject_ids)
    # two or three subjects in one row, four in two columns; more in three (or four),
    # panels lower, so that a dozen subjects still fit a page (and the monkeys' and the
    # humans' figures of the paper's seven subjects fit one page together)
    n_rows, n_columns = grid_shape(n, n if n <= 3 else 2 if n == 4 else 3 if n <= 12 else 4)
    panel_mm = {2: 56.0, 3: 44.0}.get(n_columns, 36.0) if n > 1 else 56.0
    width_mm = SINGLE_COLUMN_MM if n == 1 else DOUBLE_COLUMN_MM
    fig = new_figure(width_mm, 22.0 + panel_mm * n_rows)
    axes = fig.subplots(n_rows, n_columns, squeeze=False, sharex=True, sharey=True)
    present = np.zeros(axes.shape, dtype=bool)
    present.flat[:n] = True
    for ax in axes.flat[n:]:
        fig.delaxes(ax)
    distance_max_mm = float(averaged["distance_mm"].max()) if len(averaged) else 1.0
    # far enough to show every curve whole (eq. 19 comes back to zero at x = L), but no
    # further than twice the readings: one absurd L must not squash every panel
    shown_L = fits.loc[fits["subject"].isin(subject_ids), "waterbed_L_mm"].to_numpy(float)
    shown_L = shown_L[np.isfinite(shown_L)]
    largest_L = float(shown_L.max()) if shown_L.size else 0.0
    x_hi = 1.03 * max(distance_max_mm, min(largest_L, 2.0 * distance_max_mm))
    curve_mm = np.linspace(0.0, x_hi, 500)
    y_values = [np.zeros(1)]
    for ax, subject in zip(axes.flat[:n], subject_ids, strict=True):
        ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
        ax.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
        subject_rows = rows[rows["subject"] == subject]
        for depth_mm in sorted({float(d) for d in subject_rows["depth_mm"]}):
            colour = colours[depth_mm]
            distance_mm, deflection_mm = trial_points(rows, subject, depth_mm)
            model = model_curve_mm("waterbed", curve_mm, depth_mm, fit_row(fits, subject, depth_mm))
            if model is not None:
                ax.plot(curve_mm, model, color=colour, linewidth=1.0, gid=f"model:{depth_mm:g}")
                y_values.append(model)
            ax.plot(
                distance_mm,
                deflection_mm,
                linestyle="none",
                marker="o",
                markersize=2.6,
                markerfacecolor="white",
                markeredgecolor=colour,
                markeredgewidth=0.7,
                gid=f"data:{depth_mm:g}",
                zorder=3,
            )
            y_values.append(deflection_mm)
        if subject_rows.empty:
            ax.text(0.5, 0.5, "no profiles", transform=ax.transAxes, ha="center", va="center")
        ax.set_title(panel_title(table.loc[subject, "label"], species), loc="left")
    axes[0, 0].set_xlim(0.0, x_hi)
    y_lo, y_hi = padded_limits(np.concatenate(y_values), 0.04)
    axes[0, 0].set_ylim(y_hi, y_lo)
    if n_rows <= 2:
        label_outer_axes(axes, present, DISTANCE_LABEL, DEFLECTION_LABEL)
    else:  # one label for the whole left edge: a row is lower than the label is long
        label_outer_axes(axes, present, DISTANCE_LABEL, "")
        fig.supylabel(DEFLECTION_LABEL, fontsize=matplotlib.rcParams["axes.labelsize"])
    depth_handles = [
        Line2D(
            [],
            [],
            color=colours[d],
            marker="o",
            markersize=3,
            markerfacecolor="white",
            label=f"depth {d:g} mm",
        )
        for d in sorted(colours)
    ]
    key_handles = [
        Line2D(
            [],
            [],
            linestyle="none",
            marker="o",
            markersize=3,
            markerfacecolor="white",
            markeredgecolor="0.3",
            label="data: left/right mean",
        ),
        Line2D([], [], color="0.3", label="waterbed fit, eq. 19"),
        Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE),
    ]
    # depths on the first row(s), the key below, wrapped to the figure's width
    handles, n_columns = grid_legend(fig, [depth_handles, key_handles])
    legend_rows = -(-len(handles) // n_columns)
    if legend_rows > 2:  # a taller figure for a legend that wrapped, not lower panels
        fig.set_figheight(fig.get_figheight() + (legend_rows - 2) * LEGEND_ROW_MM / MM_PER_INCH)
    fig.legend(handles=handles, loc="outside upper center", ncols=n_columns)
    add_footer(fig, notice)
    return fig


@styled
def figure_digitised(subject, trials, notice=""):
    """Quality of photographed trials' digitising: one row per trial.

    Left, the loaded photograph near the wedge with the outline the workflow found
    (gid ``outline-loaded``), the resting outline moved onto it (``outline-rest``), the
    wedge's tip it placed (``tip``) and the distances it read (``grid``); right, the
    readings of both sides (``readings:left``, ``readings:right``) and, where it is
    known, the truth (``truth:left``, ``truth:right``).

    Parameters
    ----------
    subject : str
        The subject's label (a trial's own ``label``, where it has one, goes first).
    trials : list of dict
        Per trial: ``depth_mm``, ``image`` (the loaded photograph, 2-D), ``extent_mm``
        (``x0, x1, z0, z1`` of the image in tissue mm), ``outlines`` and ``readings``
        and ``tip_x_mm`` of :class:`lineload.rawdata.photographs.DigitisedTrial`; optionally
        ``truth``, side -> ``(distance_mm, deflection_mm)``.
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    n = len(trials)
    fig = new_figure(DOUBLE_COLUMN_MM, 16.0 + 50.0 * n)
    axes = fig.subplots(n, 2, squeeze=False, width_ratios=[1.3, 1.0])
    for row, trial in zip(axes, trials, strict=True):
        ax_image, ax_read = row
        x0, x1, z0, z1 = trial["extent_mm"]
        tip = trial["tip_x_mm"]
        ax_image.imshow(
            trial["image"],
            cmap="gray",
            extent=(x0, x1, z1, z0),
            origin="upper",
            interpolation="nearest",
            vmin=0,
            vmax=np.iinfo(trial["image"].dtype).max,
        )
        outlines = trial["outlines"]
        ax_image.plot(
            outlines["x_mm"],
            outlines["rest_mm"],
            color="#56B4E9",
            linewidth=0.8,
            linestyle="--",
            label="resting outline, registered",
            gid="outline-rest",
        )
        ax_image.plot(
            outlines["x_mm"],
            outlines["loaded_mm"],
            color="#E69F00",
            linewidth=0.8,
            label="loaded outline found",
            gid="outline-loaded",
        )
        ax_image.axvline(
            tip, color="#D55E00", linewidth=0.8, linestyle=":", label="wedge tip placed", gid="tip"
        )
        for side, sign in (("left", -1.0), ("right", 1.0)):
            distance = trial["readings"][side][0]
            ax_image.plot(
                tip + sign * distance,
                np.full(distance.size, z0 - 0.02 * (z0 - z1)),
                marker="|",
                color="#009E73",
                linestyle="none",
                markersize=4,
                gid="grid",
                label="distances read" if side == "left" else None,
            )
        span = 3.0
        ax_image.set_xlim(tip - span, tip + span)
        ax_image.set_title(
            f"{trial.get('label', subject)}, {trial['depth_mm']:g} mm: loaded photograph",
            loc="left",
        )
        ax_image.set_xlabel("x (mm)")
        ax_image.set_ylabel("z (mm)")
        left_d, left_w = trial["readings"]["left"]
        right_d, right_w = trial["readings"]["right"]
        ax_read.plot(
            left_d,
            left_w,
            marker="o",
            markersize=2.5,
            linewidth=0.8,
            color=MODEL_COLOURS["waterbed"],
            label="left",
            gid="readings:left",
        )
        ax_read.plot(
            right_d,
            right_w,
            marker="s",
            markersize=2.5,
            linewidth=0.8,
            color=MODEL_COLOURS["boussinesq"],
            label="right",
            gid="readings:right",
        )
        for side, (distance, deflection) in (trial.get("truth") or {}).items():
            ax_read.plot(
                distance,
                deflection,
                color="black",
                linewidth=0.6,
                linestyle=":",
                label="truth" if side == "left" else None,
                gid=f"truth:{side}",
            )
        ax_read.invert_yaxis()
        ax_read.set_title("readings of both sides", loc="left")
        ax_read.set_xlabel(DISTANCE_LABEL)
        ax_read.set_ylabel("deflection (mm)")
    handles = [
        *axes[0, 0].get_legend_handles_labels()[0],
        *axes[0, 1].get_legend_handles_labels()[0],
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=3)
    add_footer(fig, notice)
    return fig
