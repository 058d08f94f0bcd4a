"""Figures of the line-load re-analysis: one shared style and one function per figure.

Every figure function takes data (numpy arrays, pandas DataFrames, plain
numbers) and returns a :class:`matplotlib.figure.Figure`; none of them reads
or writes files.  :func:`save_figure` is the single place where figures are
written, as PDF and PNG with every time stamp and version string removed, so
two builds give identical bytes.

Conventions
-----------
* Lengths are tissue millimetres; the schematics (Figures 3-5) are drawn in
  units of the membrane half-width ``L``.
* Deflection is downward positive, as in the models.  Profile plots put the
  deflection axis downward (zero at the top), so the curves look like the skin
  surface they describe; residual plots use an ordinary upward axis.
* Artists that tests or readers may want to find carry a ``gid``: ``data:<depth>``
  and ``model:<depth>`` in Figures 6 and 7, ``data``, ``model:waterbed`` and
  ``model:boussinesq`` in Figure 2, ``membrane-rest`` and ``membrane-deformed``
  in the schematics, ``footer`` for the data notice.
"""

from __future__ import annotations

import math
import textwrap
from functools import wraps

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from matplotlib import colormaps, patches, ticker
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine
from matplotlib.lines import Line2D

from . import models
from .sensitivity import MODEL_NAMES as SENSITIVITY_MODEL_NAMES

__all__ = [
    "DOUBLE_COLUMN_MM",
    "FIGURE_NAMES",
    "SINGLE_COLUMN_MM",
    "STYLE",
    "depth_colours",
    "figure_arc_vs_parabola",
    "figure_channel_schematic",
    "figure_coordinates",
    "figure_examples",
    "figure_free_body",
    "figure_material_point",
    "figure_outlines",
    "figure_residuals",
    "figure_sensitivity",
    "figure_species_fits",
    "figure_style",
    "panel_title",
    "save_figure",
    "shift_exaggeration_for",
]

#: Names of every figure the workflow makes (file stems under results/figures/).
FIGURE_NAMES = (
    "figure1",
    "figure2",
    "figure3",
    "figure4",
    "figure5",
    "figure6",
    "figure7",
    "supplement_residuals",
    "supplement_arc_vs_parabola",
    "supplement_sensitivity",
    "supplement_coordinates",
)

MM_PER_INCH = 25.4
#: Journal column widths (mm).
SINGLE_COLUMN_MM = 85.0
DOUBLE_COLUMN_MM = 175.0
#: Size of the data-notice footer (points).
FOOTER_FONT_PT = 6.5

SPECIES = ("monkey", "human")
SPECIES_PLURAL = {"monkey": "monkeys", "human": "humans"}

#: Colour of each model (Okabe-Ito palette, safe for colour-blind readers).
MODEL_COLOURS = {
    "waterbed": "#0072B2",
    "shifted": "#CC79A7",
    "arc": "#009E73",
    "boussinesq": "#D55E00",
}
MODEL_NAMES = {
    "waterbed": "waterbed parabola (eq. 19)",
    "shifted": "parabola in measured coordinates",
    "arc": "waterbed exact arc",
    "boussinesq": "modified Boussinesq",
}
DATA_COLOUR = "black"
REST_COLOUR = "0.45"
WINDOW_STYLE = {"color": "0.55", "linestyle": ":", "linewidth": 0.9}

#: Line style of each model where several are drawn over each other.
MODEL_LINESTYLES = {"waterbed": "-", "shifted": "-.", "arc": "--", "boussinesq": "-"}

#: The shared style (matplotlib rcParams), applied to every figure and on saving.
STYLE = {
    "font.family": "DejaVu Sans",
    "font.size": 8.0,
    "axes.titlesize": 8.0,
    "axes.labelsize": 8.0,
    "xtick.labelsize": 7.0,
    "ytick.labelsize": 7.0,
    "legend.fontsize": 7.0,
    "figure.titlesize": 8.5,
    "mathtext.default": "regular",
    "axes.linewidth": 0.6,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.titlepad": 4.0,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "xtick.minor.width": 0.4,
    "ytick.minor.width": 0.4,
    "xtick.major.size": 3.0,
    "ytick.major.size": 3.0,
    "lines.linewidth": 1.1,
    "lines.markersize": 3.0,
    "legend.frameon": False,
    "legend.handlelength": 2.2,
    "legend.columnspacing": 1.4,
    "figure.dpi": 100,
    "figure.constrained_layout.h_pad": 0.04,
    "figure.constrained_layout.w_pad": 0.04,
    "pdf.fonttype": 42,
    "savefig.facecolor": "white",
    "image.composite_image": True,
}


def figure_style():
    """Context manager applying :data:`STYLE` (used by every figure and by saving).

    Returns
    -------
    contextlib.AbstractContextManager
    """
    return matplotlib.rc_context(STYLE)


def _styled(function):
    """Run a figure function inside :func:`figure_style`."""

    @wraps(function)
    def wrapper(*args, **kwargs):
        with figure_style():
            return function(*args, **kwargs)

    return wrapper


def save_figure(fig, pdf_path, png_path, dpi):
    """Write a figure as PDF and PNG, byte-for-byte reproducibly.

    The layout is computed once and then frozen, so both files (and any later
    save of the same figure) share the same geometry.  The PDF carries no
    creation or modification date and no creator/producer strings (which name
    the matplotlib version); the PNG carries no ``Software`` text chunk.
    Rendering is otherwise deterministic (no random state, no time stamps), so
    the same figure gives the same bytes.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure to write.
    pdf_path, png_path : str or os.PathLike
        Destinations of the two formats.
    dpi : int
        Resolution of the PNG (dots per inch), also recorded in its pHYs chunk.
    """
    with figure_style():
        if not isinstance(fig.get_layout_engine(), (PlaceHolderLayoutEngine, type(None))):
            fig.draw_without_rendering()  # run the layout once...
            fig.set_layout_engine("none")  # ...and keep it for both formats
        fig.savefig(
            pdf_path,
            format="pdf",
            metadata={"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None},
        )
        fig.savefig(png_path, format="png", dpi=dpi, metadata={"Software": None})


# ---------------------------------------------------------------- helpers


def _inches(mm):
    return mm / MM_PER_INCH


def _new_figure(width_mm, height_mm, layout="constrained"):
    return Figure(figsize=(_inches(width_mm), _inches(height_mm)), layout=layout)


def _add_footer(fig, notice):
    """Print the data notice as a grey footer and keep the layout clear of it."""
    if not notice:
        return
    width_pt = fig.get_figwidth() * 72.0
    # DejaVu Sans averages about 0.55 em per character; leave a margin.
    per_line = max(20, int(0.92 * width_pt / (0.58 * FOOTER_FONT_PT)))
    lines = textwrap.wrap(notice, per_line) or [notice]
    height_pt = fig.get_figheight() * 72.0
    pad_pt = 3.0
    footer_pt = len(lines) * 1.25 * FOOTER_FONT_PT + 2 * pad_pt
    fig.text(
        0.5,
        pad_pt / height_pt,
        "\n".join(lines),
        ha="center",
        va="bottom",
        fontsize=FOOTER_FONT_PT,
        color="0.4",
        gid="footer",
    )
    bottom = footer_pt / height_pt
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.set(rect=(0.0, bottom, 1.0, 1.0 - bottom))


def _message_figure(message, notice, width_mm=SINGLE_COLUMN_MM, height_mm=45.0):
    """A figure with one empty axis that says why there is nothing to draw."""
    fig = _new_figure(width_mm, height_mm)
    ax = fig.add_subplot()
    ax.set_xticks([])
    ax.set_yticks([])
    for spine in ax.spines.values():
        spine.set_visible(True)
        spine.set_color("0.7")
    ax.text(
        0.5,
        0.5,
        "\n".join(textwrap.wrap(message, int(44 * width_mm / SINGLE_COLUMN_MM))),
        ha="center",
        va="center",
        transform=ax.transAxes,
        gid="message",
    )
    _add_footer(fig, notice)
    return fig


def panel_title(label, species):
    """Panel title naming a subject and its species.

    Parameters
    ----------
    label : str
        Display name of the subject (e.g. ``Monkey 1`` or an id).
    species : str
        ``monkey`` or ``human``.

    Returns
    -------
    str
        The label alone if it already names the species, else ``label (species)``.
    """
    return label if species.lower() in label.lower() else f"{label} ({species})"


def _subject_table(subjects):
    """Subject sheet as a DataFrame indexed by id, with a label for every subject."""
    table = pd.DataFrame(subjects).copy()
    if "label" not in table.columns:
        table["label"] = table["subject"]
    labels = table["label"].astype(object)
    missing = labels.isna() | (labels.astype(str).str.strip() == "")
    table["label"] = np.where(missing, table["subject"], labels.astype(str))
    return table.set_index("subject", drop=False)


def depth_colours(depths_mm):
    """One colour per depth, ordered from shallow (dark) to deep (light).

    Parameters
    ----------
    depths_mm : iterable of float
        Depths (mm); duplicates are ignored.

    Returns
    -------
    dict of float to tuple
        RGBA colour of each depth; the same depths always get the same colours.
    """
    unique = sorted({float(d) for d in depths_mm})
    cmap = colormaps["plasma"]
    if len(unique) == 1:
        return {unique[0]: cmap(0.0)}
    return {d: cmap(0.78 * i / (len(unique) - 1)) for i, d in enumerate(unique)}


def _depth_text(depth_mm):
    return f"{depth_mm:g} mm"


def _trial(averaged, subject, depth_mm):
    """Finite averaged points of one subject at one depth, sorted by distance."""
    rows = averaged[
        (averaged["subject"] == subject) & np.isclose(averaged["depth_mm"].astype(float), depth_mm)
    ]
    rows = rows[np.isfinite(rows["deflection_mm"].astype(float))]
    rows = rows.sort_values("distance_mm", kind="stable")
    return rows["distance_mm"].to_numpy(float), rows["deflection_mm"].to_numpy(float)


def _fit_row(fits, subject, depth_mm):
    """The fit-table row of one subject and depth, or None."""
    rows = fits[(fits["subject"] == subject) & np.isclose(fits["depth_mm"].astype(float), depth_mm)]
    return None if rows.empty else rows.iloc[0]


def _finite(value):
    return value is not None and np.isfinite(float(value))


def _model_curve_mm(model, distance_mm, depth_mm, row):
    """Deflection of a fitted model (fit-table row) at the given distances, or None."""
    if row is None:
        return None
    if model == "waterbed" and _finite(row["waterbed_L_mm"]):
        return models.waterbed_deflection_mm(distance_mm, depth_mm, float(row["waterbed_L_mm"]))
    if model == "shifted" and _finite(row["shifted_L_mm"]):
        return models.shifted_deflection_mm(distance_mm, depth_mm, float(row["shifted_L_mm"]))
    if model == "arc" and _finite(row["arc_L_mm"]):
        return models.arc_deflection_mm(distance_mm, depth_mm, float(row["arc_L_mm"]))
    if (
        model == "boussinesq"
        and _finite(row["boussinesq_A_mm"])
        and _finite(row["boussinesq_x0_mm"])
    ):
        return models.boussinesq_deflection_mm(
            distance_mm, float(row["boussinesq_A_mm"]), float(row["boussinesq_x0_mm"])
        )
    return None


def _two_row_legend(first_row, second_row):
    """Handles and column count for a legend with one row per list.

    Legends fill column by column, so the rows are interleaved, with invisible
    blank entries where one row is shorter.
    """
    n_columns = max(len(first_row), len(second_row))
    blank = Line2D([], [], linestyle="none", label=" ")
    handles = []
    for i in range(n_columns):
        handles.append(first_row[i] if i < len(first_row) else blank)
        handles.append(second_row[i] if i < len(second_row) else blank)
    return handles, n_columns


def _grid(n_panels, max_columns=2):
    n_columns = min(n_panels, max_columns)
    return math.ceil(n_panels / n_columns), n_columns


def _label_outer_axes(axes_grid, present, xlabel, ylabel):
    """Axis labels on the left column and on the lowest panel of each column."""
    n_rows, n_columns = axes_grid.shape
    for i in range(n_rows):
        for j in range(n_columns):
            if not present[i, j]:
                continue
            ax = axes_grid[i, j]
            lowest = not present[i + 1 :, j].any()
            ax.tick_params(labelbottom=lowest)
            if lowest:
                ax.set_xlabel(xlabel)
            if j == 0:
                ax.set_ylabel(ylabel)
            else:
                ax.tick_params(labelleft=False)


def _padded_limits(values, pad_fraction=0.06):
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return -1.0, 1.0
    lo, hi = float(values.min()), float(values.max())
    pad = pad_fraction * (hi - lo) if hi > lo else max(abs(hi), 1.0) * 0.1
    return lo - pad, hi + pad


def _log_distance_axis(ax):
    """Log distance axis with plain-number ticks at 1, 2 and 5 times powers of ten."""
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    ax.xaxis.set_minor_locator(ticker.LogLocator(base=10.0, subs=(3.0, 4.0, 6.0, 7.0, 8.0, 9.0)))
    ax.xaxis.set_minor_formatter(ticker.NullFormatter())


def _same_box_aspect(limits):
    """Widen the y-limits of some panels so every panel has the same height/width.

    Parameters
    ----------
    limits : list of ((x_lo, x_hi), (y_lo, y_hi))

    Returns
    -------
    list of ((x_lo, x_hi), (y_lo, y_hi))
        Equal-aspect panels of equal shape, so their titles line up.
    """
    ratio = max((y[1] - y[0]) / (x[1] - x[0]) for x, y in limits)
    out = []
    for x, y in limits:
        grow = ratio * (x[1] - x[0]) - (y[1] - y[0])
        out.append((x, (y[0] - grow / 2, y[1] + grow / 2)))
    return out


DEFLECTION_LABEL = "deflection w (mm, downward)"
DISTANCE_LABEL = "distance from the wedge x (mm)"


# ---------------------------------------------------------------- Figure 1


@_styled
def figure_outlines(outlines, subjects, subject_ids, depth_mm, notice=""):
    """Figure 1: resting and deformed outlines of fingertips, drawn to scale.

    Parameters
    ----------
    outlines : pandas.DataFrame
        Outline points in tissue mm: ``subject``, ``depth_mm``, ``state``
        (``resting`` or ``deformed``), ``x_mm`` (wedge at 0) and ``z_mm``
        (upward positive).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    subject_ids : list of str
        Subjects to draw, one panel each, top to bottom; empty gives a figure
        saying that the data hold no outlines.
    depth_mm : float or None
        Indentation depth of the photographs to draw.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Panels share one millimetre scale on both axes (equal aspect, equal
        limits), so fingers can be compared by size.
    """
    if not subject_ids or depth_mm is None:
        return _message_figure(
            "No outline files (outlines/<subject>.csv) in this dataset: there are no "
            "resting and deformed outlines to draw.",
            notice,
        )
    table = _subject_table(subjects)
    selected = {}
    for subject in subject_ids:
        rows = outlines[
            (outlines["subject"] == subject)
            & np.isclose(outlines["depth_mm"].astype(float), depth_mm)
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
    z_lo = min(float(np.min(all_z)) if all_z.size else -depth_mm, -depth_mm)
    z_lo -= 0.03 * half_span_mm
    z_hi = wedge_top_mm + 0.02 * half_span_mm
    n = len(subject_ids)
    width_mm = DOUBLE_COLUMN_MM
    axes_width_mm = width_mm - 14.0
    panel_height_mm = axes_width_mm * (z_hi - z_lo) / (2 * half_span_mm) + 9.0
    footer_mm = 5.0 if notice else 0.0
    fig = _new_figure(width_mm, n * panel_height_mm + 12.0 + footer_mm, layout="compressed")
    axes = fig.subplots(n, 1, squeeze=False, sharex=True, sharey=True)[:, 0]
    for ax, subject in zip(axes, subject_ids, strict=True):
        for state, style in (
            ("resting", {"color": REST_COLOUR, "linestyle": "--", "linewidth": 1.0}),
            ("deformed", {"color": DATA_COLOUR, "linestyle": "-", "linewidth": 1.2}),
        ):
            rows = selected[subject][state]
            for side in (rows[rows["x_mm"] <= 0], rows[rows["x_mm"] >= 0]):
                ax.plot(side["x_mm"], side["z_mm"], gid=f"outline:{state}", **style)
        apex_z = -depth_mm
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
        ax.set_title(f"{panel_title(label, species)}, wedge {depth_mm:g} mm deep", loc="left")
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
    _add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- Figure 2


@_styled
def figure_examples(averaged, fits, subjects, subject_ids, depth_mm, fit_window_mm, notice=""):
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
    subject_ids : list of str
        One panel per subject, left to right.
    depth_mm : float
        The indentation depth shown.
    fit_window_mm : float
        Outer edge of the fitted region (mm), marked on every panel.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not subject_ids:
        return _message_figure(
            f"No subject in this dataset has a profile at {depth_mm:g} mm depth.", notice
        )
    table = _subject_table(subjects)
    n = len(subject_ids)
    width_mm = SINGLE_COLUMN_MM if n == 1 else DOUBLE_COLUMN_MM
    fig = _new_figure(width_mm, 72.0)
    axes = fig.subplots(1, n, squeeze=False, sharey=True)[0]
    y_values = []
    for ax, subject in zip(axes, subject_ids, strict=True):
        distance_mm, deflection_mm = _trial(averaged, subject, depth_mm)
        keep = distance_mm > 0
        distance_mm, deflection_mm = distance_mm[keep], deflection_mm[keep]
        row = _fit_row(fits, subject, depth_mm)
        lo = distance_mm.min() / 1.3 if distance_mm.size else 0.05
        hi = distance_mm.max() * 1.3 if distance_mm.size else 10.0
        curve_mm = np.geomspace(lo, hi, 400)
        ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
        for model in ("boussinesq", "waterbed"):
            values = _model_curve_mm(model, curve_mm, depth_mm, row)
            if values is not None:
                ax.plot(curve_mm, values, color=MODEL_COLOURS[model], gid=f"model:{model}")
                y_values.append(values)
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
        y_values.append(deflection_mm)
        _log_distance_axis(ax)
        ax.set_xlim(lo, hi)
        ax.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
        species = table.loc[subject, "species"] if subject in table.index else ""
        label = table.loc[subject, "label"] if subject in table.index else subject
        ax.set_title(f"{panel_title(label, species)}, {depth_mm:g} mm depth", loc="left")
        ax.set_xlabel("distance from the wedge x (mm, log scale)")
    axes[0].set_ylabel(DEFLECTION_LABEL)
    values = np.concatenate([np.ravel(v) for v in y_values]) if y_values else np.array([])
    values = np.clip(values[np.isfinite(values)], -0.6 * depth_mm, 1.3 * depth_mm)
    y_lo, y_hi = _padded_limits(np.append(values, 0.0))
    axes[0].set_ylim(y_hi, y_lo)
    handles = [
        Line2D(
            [],
            [],
            linestyle="none",
            marker="o",
            markerfacecolor="white",
            markeredgecolor=DATA_COLOUR,
            label="data (mean of left and right)",
        ),
        Line2D([], [], color=MODEL_COLOURS["waterbed"], label="waterbed fit (eq. 19)"),
        Line2D([], [], color=MODEL_COLOURS["boussinesq"], label="modified Boussinesq fit"),
        Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE),
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=4 if n > 1 else 2)
    _add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- Figures 3-5


def _membrane(depth_ratio, n_points=801):
    """Whole membrane (X from -L to L, L = 1) at rest and deformed by eq. 19."""
    X = np.linspace(-1.0, 1.0, n_points)
    W = models.waterbed_deflection_mm(np.abs(X), depth_ratio, 1.0)
    return X, W


def _arrow(ax, start, end, colour="black", width=0.9, head=6.0, **kwargs):
    ax.annotate(
        "",
        xy=end,
        xytext=start,
        arrowprops={
            "arrowstyle": f"-|>,head_length={head / 10:.2f},head_width={head / 20:.2f}",
            "color": colour,
            "linewidth": width,
            "shrinkA": 0,
            "shrinkB": 0,
        },
        **kwargs,
    )


def _dimension(ax, start, end, text, text_offset=(0.0, 0.0), colour="0.25", **text_kwargs):
    """A double-headed dimension arrow with a label at its middle."""
    ax.annotate(
        "",
        xy=end,
        xytext=start,
        arrowprops={
            "arrowstyle": "<|-|>,head_length=0.35,head_width=0.15",
            "color": colour,
            "linewidth": 0.6,
            "shrinkA": 0,
            "shrinkB": 0,
        },
    )
    middle = ((start[0] + end[0]) / 2 + text_offset[0], (start[1] + end[1]) / 2 + text_offset[1])
    ax.text(*middle, text, color=colour, **text_kwargs)


@_styled
def figure_channel_schematic(depth_ratio, notice=""):
    """Figure 3: the waterbed model, drawn from eq. 19 at a given W0/L.

    A membrane of half-width ``L`` spans a rigid channel filled with
    incompressible fluid.  The load ``F`` on the axis OZ pushes the membrane
    down by ``W0``; the fluid pressure ``p`` pushes it back up, and the
    membrane bulges beyond ``X = L/3`` to keep the fluid's area.

    Parameters
    ----------
    depth_ratio : float
        W0 / L at which the deformed membrane is drawn (0 < ratio <= 0.4).
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Axes in units of L; the deformed membrane (gid ``membrane-deformed``)
        is ``Z = -W(|X|)`` with W from :func:`lineload.models.waterbed_deflection_mm`.
    """
    r = float(depth_ratio)
    X, W = _membrane(r)
    floor = -(r + 0.32)
    top = 0.42
    wall = 0.07
    fig = _new_figure(DOUBLE_COLUMN_MM, 88.0)
    ax = fig.add_subplot()
    fluid = patches.Polygon(
        np.column_stack([np.r_[X, 1.0, -1.0], np.r_[-W, floor, floor]]),
        closed=True,
        facecolor="#d6e9f5",
        edgecolor="none",
        zorder=0,
    )
    ax.add_patch(fluid)
    ax.text(0.5, floor + 0.09, "incompressible fluid", ha="center", va="center", color="0.25")
    for x0 in (-1.0 - wall, 1.0):
        ax.add_patch(
            patches.Rectangle(
                (x0, floor - wall),
                wall,
                top - 0.05 - floor + wall,
                facecolor="0.85",
                edgecolor="0.3",
                hatch="////",
                linewidth=0.6,
            )
        )
    ax.add_patch(
        patches.Rectangle(
            (-1.0 - wall, floor - wall),
            2 + 2 * wall,
            wall,
            facecolor="0.85",
            edgecolor="0.3",
            hatch="////",
            linewidth=0.6,
        )
    )
    ax.text(1.0 + wall / 2, top - 0.02, "rigid wall", ha="center", va="bottom")
    ax.text(-1.0 - wall / 2, top - 0.02, "rigid wall", ha="center", va="bottom")
    ax.plot(
        [-1.0, 1.0],
        [0.0, 0.0],
        color=REST_COLOUR,
        linestyle="--",
        linewidth=1.0,
        gid="membrane-rest",
    )
    ax.plot(X, -W, color=DATA_COLOUR, linewidth=1.5, gid="membrane-deformed")
    # load axis OZ and the load F
    ax.plot([0, 0], [floor, top], color="0.35", linestyle="-.", linewidth=0.6, zorder=1)
    ax.text(0.015, top, "Z", ha="left", va="top")
    ax.text(-0.02, 0.015, "O", ha="right", va="bottom")
    _arrow(ax, (0.0, 0.3), (0.0, -r), colour="#b2182b", width=1.4, head=8)
    ax.text(0.02, 0.27, "F", color="#b2182b", ha="left", va="center", fontsize=9, fontweight="bold")
    # pressure p: normal to the membrane, from the fluid side
    for x_p in (-0.9, -0.72, -0.55, -0.38, 0.38, 0.55, 0.72, 0.9):
        z_p = -float(models.waterbed_deflection_mm(abs(x_p), r, 1.0))
        slope_W = r * (6 * abs(x_p) - 4)  # dW/d|X|
        normal = np.array([np.sign(x_p) * slope_W, 1.0])
        normal /= np.hypot(*normal)
        start = np.array([x_p, z_p]) - 0.11 * normal
        _arrow(ax, tuple(start), (x_p, z_p), colour=MODEL_COLOURS["waterbed"], width=0.8, head=5)
    ax.text(
        -0.55,
        -float(models.waterbed_deflection_mm(0.55, r, 1.0)) - 0.14,
        "p",
        color=MODEL_COLOURS["waterbed"],
        ha="center",
        va="top",
        fontsize=9,
        fontstyle="italic",
    )
    # dimensions
    _dimension(ax, (0.0, 0.2), (1.0, 0.2), "L", text_offset=(0, 0.012), ha="center", va="bottom")
    ax.annotate(
        "",
        xy=(-0.035, -r),
        xytext=(-0.035, 0.0),
        arrowprops={
            "arrowstyle": "<|-|>,head_length=0.35,head_width=0.15",
            "color": "0.25",
            "linewidth": 0.6,
            "shrinkA": 0,
            "shrinkB": 0,
        },
    )
    ax.plot([-0.06, 0.0], [-r, -r], color="0.5", linewidth=0.5)
    ax.text(-0.05, -0.3 * r, "$W_0$", color="0.25", ha="right", va="center")
    ax.annotate(
        "membrane at rest",
        xy=(-0.8, 0.0),
        xytext=(-0.8, 0.12),
        ha="center",
        arrowprops={"arrowstyle": "-", "color": "0.4", "linewidth": 0.6},
    )
    ax.annotate(
        "deformed membrane",
        xy=(0.25, -float(models.waterbed_deflection_mm(0.25, r, 1))),
        xytext=(0.3, floor + 0.2),
        ha="left",
        arrowprops={"arrowstyle": "-", "color": "0.4", "linewidth": 0.6},
    )
    ax.text(
        -1.0,
        floor - wall - 0.02,
        f"deformed shape: eq. 19 drawn at $W_0/L$ = {r:g}; resting membrane dashed",
        ha="left",
        va="top",
    )
    ax.set_aspect("equal")
    ax.set_xlim(-1.0 - wall - 0.12, 1.0 + wall + 0.12)
    ax.set_ylim(floor - wall - 0.12, top + 0.07)
    ax.set_xlabel("X / L")
    ax.set_ylabel("Z / L (height; W = −Z)")
    _add_footer(fig, notice)
    return fig


def shift_exaggeration_for(depth_ratio, point_X_over_L, target_fraction=0.35):
    """Smallest 1-2-5 factor that makes the shift U visible at a point.

    Parameters
    ----------
    depth_ratio : float
        W0 / L.
    point_X_over_L : float
        Initial coordinate of the point, X / L.
    target_fraction : float
        The drawn shift should reach at least this fraction of X.

    Returns
    -------
    int
        1, 2, 5, 10, 20, 50, ... (1 when the shift is already visible).
    """
    shift = abs(float(models.waterbed_shift_mm(point_X_over_L, depth_ratio, 1.0)))
    wanted = target_fraction * point_X_over_L
    for exponent in range(7):
        for mantissa in (1, 2, 5):
            factor = mantissa * 10**exponent
            if factor * shift >= wanted:
                return factor
    return 10**7


@_styled
def figure_material_point(depth_ratio, notice="", point_X_over_L=0.2, shift_exaggeration=None):
    """Figure 4: a material point at (X, 0) moves to (X + U, W) (eqs. 19 and 20).

    Parameters
    ----------
    depth_ratio : float
        W0 / L at which the membrane is drawn.
    notice : str
        Footer text; empty for none.
    point_X_over_L : float
        Initial coordinate X / L of the point A that is followed.
    shift_exaggeration : float, optional
        Factor by which U is drawn larger than it is (it is a few percent of
        X); defaults to :func:`shift_exaggeration_for`.  Stated on the figure.

    Returns
    -------
    matplotlib.figure.Figure
        Half the membrane (0 <= X <= L), axes in units of L.  The deformed
        curve (gid ``membrane-deformed``) is ``(X + k U(X), -W(X))`` with k
        the exaggeration.
    """
    r = float(depth_ratio)
    k = shift_exaggeration or shift_exaggeration_for(r, point_X_over_L)
    X = np.linspace(0.0, 1.0, 401)
    W = models.waterbed_deflection_mm(X, r, 1.0)
    U = models.waterbed_shift_mm(X, r, 1.0)
    X_A = float(point_X_over_L)
    W_A = float(models.waterbed_deflection_mm(X_A, r, 1.0))
    U_A = float(models.waterbed_shift_mm(X_A, r, 1.0))
    x_A = X_A + k * U_A
    fig = _new_figure(DOUBLE_COLUMN_MM, 78.0)
    ax = fig.add_subplot()
    ax.plot(
        [0.0, 1.0],
        [0.0, 0.0],
        color=REST_COLOUR,
        linestyle="--",
        linewidth=1.0,
        gid="membrane-rest",
    )
    ax.plot(X + k * U, -W, color=DATA_COLOUR, linewidth=1.5, gid="membrane-deformed")
    ax.plot([0, 0], [-r - 0.1, 0.16], color="0.35", linestyle="-.", linewidth=0.6)
    ax.text(-0.012, 0.005, "O", ha="right", va="bottom")
    ax.plot(
        [X_A],
        [0.0],
        marker="o",
        markersize=5,
        markerfacecolor="white",
        markeredgecolor=DATA_COLOUR,
        linestyle="none",
        gid="point-initial",
        zorder=4,
    )
    ax.plot(
        [x_A],
        [-W_A],
        marker="o",
        markersize=5,
        color=DATA_COLOUR,
        linestyle="none",
        gid="point-final",
        zorder=4,
    )
    ax.text(X_A + 0.015, 0.045, "A at (X, 0)", ha="left", va="bottom")
    ax.text(x_A + 0.015, -W_A - 0.012, "A after loading: (X + U, W)", ha="left", va="top")
    _arrow(ax, (X_A, 0.0), (x_A, -W_A), colour="#b2182b", width=0.9, head=5)
    # dimensions: X above the rest line, x below the deformed point
    _dimension(ax, (0.0, 0.1), (X_A, 0.1), "X", text_offset=(0, 0.01), ha="center", va="bottom")
    ax.plot([X_A, X_A], [0.0, 0.1], color="0.6", linewidth=0.5)
    y_x = -r - 0.06
    _dimension(
        ax, (0.0, y_x), (x_A, y_x), "x = X + U", text_offset=(0.0, -0.012), ha="left", va="top"
    )
    ax.plot([x_A, x_A], [-W_A, y_x], color="0.6", linewidth=0.5)
    _dimension(
        ax,
        (x_A - 0.03, 0.0),
        (x_A - 0.03, -W_A),
        "W",
        text_offset=(-0.01, 0),
        ha="right",
        va="center",
    )
    ax.plot([x_A - 0.04, x_A + 0.01], [0.0, 0.0], color="0.6", linewidth=0.5)
    largest = 8 * r**2 / 9
    ax.text(
        1.0,
        -r - 0.1,
        f"drawn from eqs. 19 and 20 at $W_0/L$ = {r:g}, with U magnified {k:g}×\n"
        f"true shift at A: U = {U_A:.4f} L\n".replace("-", "−")
        + f"largest |U| = 8$W_0^2$/(9L) = {largest:.4f} L, at X = L/3",
        ha="right",
        va="bottom",
    )
    ax.set_aspect("equal")
    ax.set_xlim(-0.06, 1.03)
    ax.set_ylim(-r - 0.13, 0.17)
    ax.set_xlabel("horizontal coordinate / L")
    ax.set_ylabel("Z / L (height; W = −Z)")
    handles = [
        Line2D([], [], color=REST_COLOUR, linestyle="--", label="membrane at rest"),
        Line2D([], [], color=DATA_COLOUR, label=f"deformed membrane (U drawn {k:g}×)"),
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=2)
    _add_footer(fig, notice)
    return fig


@_styled
def figure_free_body(depth_ratio, notice=""):
    """Figure 5: free-body diagrams at the load (A) and of a membrane element (B).

    (A) The load F is held by the two membrane forces N, each at the angle
    theta0 = arctan(4 W0 / L) of the small-slope solution, so F = 2 N sin theta0;
    the three vectors are drawn to scale.  (B) An element of membrane with the
    tension N at both ends and the fluid pressure p, curved with the radius
    R = L**2 / (6 W0) of the parabola (eq. 19), so N = p R.

    Parameters
    ----------
    depth_ratio : float
        W0 / L of the solution the angles and radius come from.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    r = float(depth_ratio)
    theta0 = float(models.waterbed_load_angle_rad(r, 1.0))
    radius_L = 1.0 / (6.0 * r)  # 1 / W'' of eq. 19, in units of L
    fig = _new_figure(DOUBLE_COLUMN_MM, 72.0)
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1.0, 1.0])
    red, blue = "#b2182b", MODEL_COLOURS["waterbed"]
    # (A) at the load, N = 1 and F to scale
    f_len = 2.0 * np.sin(theta0)
    direction = np.array([np.cos(theta0), np.sin(theta0)])
    for side in (-1, 1):
        d = direction * [side, 1]
        ax_a.plot(
            [0, 1.35 * d[0]],
            [0, 1.35 * d[1]],
            color="0.82",
            linewidth=5.0,
            solid_capstyle="butt",
            zorder=1,
        )
        _arrow(ax_a, (0.0, 0.0), tuple(d), colour=blue, width=1.3, head=8)
        ax_a.text(
            *(d * 1.04 + [0, 0.06]),
            "N",
            color=blue,
            ha="center",
            va="bottom",
            fontsize=9,
            fontweight="bold",
        )
    _arrow(ax_a, (0.0, f_len), (0.0, 0.0), colour=red, width=1.3, head=8)
    ax_a.text(
        0.05, f_len * 0.6, "F", color=red, ha="left", va="center", fontsize=9, fontweight="bold"
    )
    ax_a.plot([0, 0.9], [0, 0], color="0.4", linestyle=":", linewidth=0.8)
    ax_a.add_patch(
        patches.Arc(
            (0, 0), 1.1, 1.1, theta1=0, theta2=np.degrees(theta0), color="0.2", linewidth=0.8
        )
    )
    mid = theta0 / 2
    ax_a.text(
        0.62 * np.cos(mid) + 0.02, 0.62 * np.sin(mid) - 0.03, r"$\theta_0$", ha="left", va="center"
    )
    ax_a.plot([0], [0], marker="o", markersize=3.5, color="black")
    ax_a.text(
        0.0,
        -0.2,
        f"F = 2N sin $\\theta_0$;  $\\theta_0$ = arctan(4$W_0$/L) = {np.degrees(theta0):.1f}°\n"
        f"at $W_0/L$ = {r:g} (vectors to scale, N = 1)",
        ha="center",
        va="top",
    )
    ax_a.set_title("(A) at the load", loc="left")
    limits_a = ((-1.45, 1.45), (-0.62, max(f_len, 1.35 * np.sin(theta0)) + 0.25))
    # (B) membrane element, arc of radius R around the centre C
    half = np.radians(22.0)
    angles = np.linspace(np.pi / 2 - half, np.pi / 2 + half, 120)
    centre = np.array([0.0, -radius_L])
    ax_b.plot(
        centre[0] + radius_L * np.cos(angles),
        centre[1] + radius_L * np.sin(angles),
        color=DATA_COLOUR,
        linewidth=3.0,
        solid_capstyle="butt",
    )
    n_len = 0.45 * radius_L
    for end in (np.pi / 2 - half, np.pi / 2 + half):
        point = centre + radius_L * np.array([np.cos(end), np.sin(end)])
        outward = np.sign(np.cos(end))
        tangent = outward * np.array([np.sin(end), -np.cos(end)])
        _arrow(ax_b, tuple(point), tuple(point + n_len * tangent), colour=blue, width=1.3, head=8)
        tip = point + n_len * tangent
        ax_b.text(
            tip[0],
            tip[1] + 0.05 * radius_L,
            "N",
            color=blue,
            ha="center",
            va="bottom",
            fontsize=9,
            fontweight="bold",
        )
        ax_b.plot(
            [centre[0], point[0]], [centre[1], point[1]], color="0.5", linestyle="--", linewidth=0.6
        )
    for angle in np.linspace(np.pi / 2 - 0.8 * half, np.pi / 2 + 0.8 * half, 5):
        unit = np.array([np.cos(angle), np.sin(angle)])
        point = centre + radius_L * unit
        _arrow(
            ax_b, tuple(point - 0.16 * radius_L * unit), tuple(point), colour=red, width=0.8, head=5
        )
    ax_b.text(
        0.0,
        radius_L * 0.8 + centre[1],
        "p",
        color=red,
        ha="center",
        va="top",
        fontsize=9,
        fontstyle="italic",
    )
    ax_b.plot(*centre, marker="+", color="0.3", markersize=6)
    ax_b.text(centre[0] + 0.03 * radius_L, centre[1], "C", ha="left", va="center")
    end = np.pi / 2 + half
    ax_b.text(
        centre[0] + 0.55 * radius_L * np.cos(end) - 0.04 * radius_L,
        centre[1] + 0.55 * radius_L * np.sin(end),
        "R",
        ha="right",
        va="center",
    )
    ax_b.text(
        0.0,
        centre[1] - 0.1 * radius_L,
        f"N = pR;  R = $L^2$/(6$W_0$) = {radius_L:.2f} L for eq. 19 at $W_0/L$ = {r:g}\n"
        "(element's angular size enlarged for clarity)",
        ha="center",
        va="top",
    )
    ax_b.set_title("(B) an element of the membrane", loc="left")
    limits_b = ((-0.95 * radius_L, 0.95 * radius_L), (centre[1] - 0.5 * radius_L, 0.42 * radius_L))
    for ax, (x_lim, y_lim) in zip(
        (ax_a, ax_b), _same_box_aspect([limits_a, limits_b]), strict=True
    ):
        ax.set_xlim(*x_lim)
        ax.set_ylim(*y_lim)
        ax.set_aspect("equal")
        ax.set_axis_off()
    _add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- Figures 6 and 7


@_styled
def figure_species_fits(
    averaged, fits, subjects, species, fit_window_mm, notice="", distance_max_mm=None
):
    """Figures 6 (monkeys) and 7 (humans): every depth of every subject with its waterbed fit.

    Panels follow the subject sheet (one per subject of the species, in its
    order) and each panel follows its data (one point series and one fitted
    line per depth present).  The colour of a depth is the same in every panel.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles of any subjects (``subject``, ``depth_mm``,
        ``distance_mm``, ``deflection_mm``).
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
    distance_max_mm : float, optional
        Right end of the distance axis (to share one scale between the two
        species); defaults to the largest distance in these panels.

    Returns
    -------
    matplotlib.figure.Figure
        With no subject of that species, one axis that says so.
    """
    table = _subject_table(subjects)
    subject_ids = [s for s in table["subject"] if table.loc[s, "species"] == species]
    if not subject_ids:
        return _message_figure(f"No {species} subjects in this dataset.", notice)
    rows = averaged[averaged["subject"].isin(subject_ids)]
    colours = depth_colours(rows["depth_mm"].astype(float))
    n = len(subject_ids)
    n_rows, n_columns = _grid(n)
    width_mm = SINGLE_COLUMN_MM if n == 1 else DOUBLE_COLUMN_MM
    fig = _new_figure(width_mm, 22.0 + 56.0 * n_rows)
    axes = fig.subplots(n_rows, n_columns, squeeze=False, sharex=True, sharey=True)
    present = np.zeros(axes.shape, dtype=bool)
    present.flat[:n] = True
    for ax in axes.flat[n:]:
        fig.delaxes(ax)
    if distance_max_mm is None:
        distance_max_mm = float(rows["distance_mm"].max()) if not rows.empty else 1.0
    x_hi = 1.03 * distance_max_mm
    curve_mm = np.linspace(0.0, x_hi, 500)
    y_values = [np.zeros(1)]
    for ax, subject in zip(axes.flat[:n], subject_ids, strict=True):
        ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
        ax.axhline(0.0, color="0.8", linewidth=0.6, zorder=0)
        subject_rows = rows[rows["subject"] == subject]
        for depth_mm in sorted({float(d) for d in subject_rows["depth_mm"]}):
            colour = colours[depth_mm]
            distance_mm, deflection_mm = _trial(rows, subject, depth_mm)
            model = _model_curve_mm(
                "waterbed", curve_mm, depth_mm, _fit_row(fits, subject, depth_mm)
            )
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
    y_lo, y_hi = _padded_limits(np.concatenate(y_values), 0.04)
    axes[0, 0].set_ylim(y_hi, y_lo)
    _label_outer_axes(axes, present, DISTANCE_LABEL, DEFLECTION_LABEL)
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
    if width_mm > SINGLE_COLUMN_MM:
        handles, n_columns = _two_row_legend(depth_handles, key_handles)
    else:  # too narrow for one row of each: two columns, filled top to bottom
        handles, n_columns = depth_handles + key_handles, 2
    fig.legend(handles=handles, loc="outside upper center", ncols=n_columns)
    _add_footer(fig, notice)
    return fig


# ---------------------------------------------------------------- supplement


@_styled
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
    table = _subject_table(subjects)
    species_rows = [s for s in SPECIES if (table["species"] == s).any()]
    depths = sorted({float(d) for d in averaged["depth_mm"]}) if not averaged.empty else []
    if not species_rows or not depths:
        return _message_figure("No profiles in this dataset: no residuals to show.", notice)
    n_rows, n_columns = len(species_rows), len(depths)
    width_mm = DOUBLE_COLUMN_MM if n_columns > 1 else SINGLE_COLUMN_MM
    fig = _new_figure(width_mm, 26.0 + 48.0 * n_rows)
    axes = fig.subplots(n_rows, n_columns, squeeze=False, sharex=True, sharey=True)
    all_x, all_r = [fit_window_mm], [0.0]
    for i, species in enumerate(species_rows):
        members = [s for s in table["subject"] if table.loc[s, "species"] == species]
        for j, depth_mm in enumerate(depths):
            ax = axes[i, j]
            ax.axhline(0.0, color="0.6", linewidth=0.6, zorder=0)
            ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
            drawn = False
            for subject in members:
                distance_mm, deflection_mm = _trial(averaged, subject, depth_mm)
                keep = (distance_mm > 0) & (distance_mm <= fit_window_mm)
                distance_mm, deflection_mm = distance_mm[keep], deflection_mm[keep]
                if distance_mm.size == 0:
                    continue
                row = _fit_row(fits, subject, depth_mm)
                for model in ("boussinesq", "waterbed", "shifted", "arc"):
                    values = _model_curve_mm(model, distance_mm, depth_mm, row)
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
            _log_distance_axis(ax)
    axes[0, 0].set_xlim(min(all_x) / 1.25, fit_window_mm * 1.25)
    axes[0, 0].set_ylim(*_padded_limits(all_r))
    present = np.ones(axes.shape, dtype=bool)
    _label_outer_axes(axes, present, "distance x (mm, log scale)", "data − model (mm)")
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
        for m in ("waterbed", "shifted", "arc", "boussinesq")
    ]
    handles.append(Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE))
    fig.legend(
        handles=handles,
        loc="outside upper center",
        ncols=3,
        title="one line per subject and model; positive: skin deeper than the model",
        title_fontsize=7,
    )
    _add_footer(fig, notice)
    return fig


@_styled
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
        return _message_figure("No finite waterbed fits in this dataset.", notice)
    n = len(depths)
    width_mm = DOUBLE_COLUMN_MM if n > 1 else SINGLE_COLUMN_MM
    fig = _new_figure(width_mm, 112.0)
    axes = fig.subplots(2, n, squeeze=False, sharex=True, sharey="row", height_ratios=[1.3, 1.0])
    profiles, differences = [0.0], [0.0]
    x_hi = 0.0
    for j, depth_mm in enumerate(depths):
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
        top, bottom = axes[0, j], axes[1, j]
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
            f"L = {L_median:.1f} mm ({L_values.size} fits)\n$W_0/L$ = {depth_mm / L_median:.3f}",
            transform=top.transAxes,
            ha="right",
            va="bottom",
            in_layout=False,
        )
        bottom.text(
            0.04,
            0.96,
            f"largest / $W_0$:\narc {100 * largest:.1f}%\n"
            f"shifted {100 * float(np.nanmax(np.abs(shifted_diff))) / depth_mm:.1f}%",
            transform=bottom.transAxes,
            ha="left",
            va="top",
            in_layout=False,
        )
    axes[0, 0].set_xlim(0.0, x_hi * 1.02)
    lo, hi = _padded_limits(profiles, 0.04)
    axes[0, 0].set_ylim(hi, lo)
    lo, hi = _padded_limits(differences, 0.1)
    axes[1, 0].set_ylim(lo, hi + 1.2 * (hi - lo))
    axes[0, 0].set_ylabel("deflection w (mm)")
    axes[1, 0].set_ylabel("minus eq. 19 (mm)")
    for ax in axes[1]:
        ax.set_xlabel("distance x (mm)")
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
        Line2D([], [], color=MODEL_COLOURS["arc"], label="exact arc (same $W_0$, L)"),
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
    fig.legend(
        handles=handles,
        loc="outside upper center",
        ncols=2,
        title="shapes drawn with $W_0$ = depth and the median fitted waterbed L",
        title_fontsize=7,
    )
    _add_footer(fig, notice)
    return fig


# Models of the sensitivity refits, in drawing order, with their colours and the
# names the sensitivity tables use.
SENSITIVITY_MODELS = {
    model: (colour, SENSITIVITY_MODEL_NAMES[model])
    for model, colour in (
        ("waterbed", MODEL_COLOURS["waterbed"]),
        ("waterbed_free_depth", "#56B4E9"),
        ("shifted", MODEL_COLOURS["shifted"]),
        ("arc", MODEL_COLOURS["arc"]),
        ("boussinesq", MODEL_COLOURS["boussinesq"]),
    )
}
SPECIES_MARKERS = {"monkey": "o", "human": "s"}


@_styled
def figure_sensitivity(sensitivity, checks, shift_limit=0.08, reach_claim_mm=3.0, notice=""):
    """Supplement: how the fits depend on the analysis choices, trial by trial.

    Four panels: (a) the fitted L of each waterbed variant in each fit window;
    (b) each model's AICc minus the best in that window; (c) the largest
    horizontal shift of the small-slope solution relative to X at L/3, with the
    paper's bound; (d) the distance up to which the waterbed stays within
    tolerance of the data, with the paper's 3 mm.

    Parameters
    ----------
    sensitivity : pandas.DataFrame
        Rows of ``lineload.sensitivity.SENSITIVITY_COLUMNS``.
    checks : pandas.DataFrame
        Rows of ``lineload.sensitivity.CHECK_COLUMNS``.
    shift_limit : float, optional
        The paper's bound on U/X at L/3 (a fraction), drawn as a line.
    reach_claim_mm : float, optional
        The distance to which the paper says the fit holds, drawn as a line.
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Point collections carry gids ``L:<model>``, ``aicc:<model>``, ``shift``
        and ``reach``.
    """
    if sensitivity is None or len(sensitivity) == 0:
        return _message_figure("No sensitivity refits in this dataset.", notice)
    windows = list(dict.fromkeys(sensitivity["window"]))
    fig = _new_figure(DOUBLE_COLUMN_MM, 120.0)
    (ax_L, ax_aicc), (ax_shift, ax_reach) = fig.subplots(2, 2)
    models = list(SENSITIVITY_MODELS)
    width = 0.8 / len(models)
    for k, model in enumerate(models):
        colour, name = SENSITIVITY_MODELS[model]
        rows = sensitivity[sensitivity["model"] == model]
        for axis, column, kind in ((ax_L, "L_mm", "L"), (ax_aicc, "delta_aicc", "aicc")):
            if kind == "L" and model == "boussinesq":
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
    ax_shift.text(
        depths[0] - 0.2,
        100 * shift_limit,
        f"paper's bound {100 * shift_limit:g} %",
        va="bottom",
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
    _add_footer(fig, notice)
    return fig


@_styled
def figure_coordinates(fits, checks, noise_mm, notice=""):
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
    noise_mm : float
        Digitising noise of one reading (mm), drawn as a line in (b).
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
        Point collections carry gids ``L:<model>`` and ``gap:<model>``.
    """
    usable = fits[np.isfinite(fits["waterbed_L_mm"].astype(float))]
    if usable.empty:
        return _message_figure("No finite waterbed fits in this dataset.", notice)
    fig = _new_figure(DOUBLE_COLUMN_MM, 82.0)
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
    lo, hi = _padded_limits(limits, 0.05)
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
    ax_gap.axhline(noise_mm, color="0.5", linestyle=":", linewidth=0.8)
    ax_gap.annotate(
        f"digitising noise of one reading ({noise_mm:g} mm)",
        xy=(0.02, noise_mm),
        xycoords=("axes fraction", "data"),
        xytext=(0, 2),
        textcoords="offset points",
        va="bottom",
        fontsize=7,
        color="0.4",
    )
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
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=4)
    _add_footer(fig, notice)
    return fig
