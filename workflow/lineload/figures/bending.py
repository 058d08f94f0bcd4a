"""Figures of the bending skin: every model family on one trial, and the bending lengths.

Every function takes data (pandas DataFrames, plain numbers) and returns a
:class:`matplotlib.figure.Figure`; parameter names are those of
:data:`lineload.figures.registry.ARGUMENTS`.

gids: ``data``, ``model:<family>`` and ``fit-window`` in the comparison;
``lb:<subject>`` (an estimate with its interval), ``lb-bound:<subject>`` (an
estimate at the range's end, drawn open with its one-sided interval) and
``first-reading`` in the bending lengths; ``footer`` for the data notice.
"""

from __future__ import annotations

from collections import ChainMap

import numpy as np
from matplotlib.lines import Line2D

from lineload.figures.data import (
    data_handle,
    deflection_limits,
    draw_fitted_trial,
    example_per_species,
    fit_row,
)
from lineload.figures.estimates import draw_estimates_by_depth
from lineload.figures.style import (
    DEFLECTION_LABEL,
    DOUBLE_COLUMN_MM,
    MODEL_NAMES,
    SINGLE_COLUMN_MM,
    WINDOW_STYLE,
    add_footer,
    legend_columns,
    message_figure,
    new_figure,
    panel_title,
    styled,
)
from lineload.fitting.families import FAMILIES

__all__ = ["figure_bending_examples", "figure_bending_lengths"]

#: Colour of the bending skin's curve (the registry's: Okabe-Ito orange, apart from the others).
BENDING_COLOUR = FAMILIES["bending"].colour
BENDING_NAME = "bending skin"
#: The families drawn beside the bending skin, in drawing order.
OTHER_FAMILIES = ("boussinesq", "waterbed", "arc")


def _bending_row(bending, subject, depth_mm):
    return fit_row(bending, subject, depth_mm) if bending is not None and len(bending) else None


@styled
def figure_bending_examples(averaged, fits, bending, subjects, fit_window_mm, notice=""):
    """Every model family on the averaged points of a monkey and a human.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles (``subject``, ``depth_mm``, ``distance_mm``, ``deflection_mm``).
    fits : pandas.DataFrame
        The fit table (waterbed, arc and Boussinesq parameters per trial).
    bending : pandas.DataFrame
        The bending fits (``bending_L_mm``, ``bending_length_mm`` per trial).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    fit_window_mm : float
        Outer edge of the fitted region (mm), marked on every panel.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    chosen, table = example_per_species(bending[np.isfinite(bending["bending_L_mm"])], subjects)
    if not chosen:
        return message_figure("No trial of this dataset has a bending fit.", notice)
    n = len(chosen)
    fig = new_figure(SINGLE_COLUMN_MM if n == 1 else DOUBLE_COLUMN_MM, 78.0)
    axes = fig.subplots(1, n, squeeze=False, sharey=False)[0]
    for ax, (subject, species, depth_mm) in zip(axes, chosen, strict=True):
        bent = _bending_row(bending, subject, depth_mm)
        # the fit table's families and the bending skin, read from one row
        rows = (bent, fit_row(fits, subject, depth_mm))
        row = ChainMap(*(dict(r) for r in rows if r is not None))
        drawn = draw_fitted_trial(
            ax,
            averaged,
            row,
            subject,
            depth_mm,
            (*OTHER_FAMILIES, "bending"),
            fit_window_mm,
            reach_mm=fit_window_mm,
            n_curve=500,
            emphasis={"bending": {"linewidth": 1.4, "zorder": 2.5}},
        )
        y_lo, y_hi = deflection_limits(drawn, depth_mm)
        ax.set_ylim(y_hi, y_lo)
        label = table.loc[subject, "label"] if subject in table.index else subject
        lb_mm = float(bent["bending_length_mm"])
        at_bound = float(bent.get("bending_length_at_bound", 0.0)) > 0
        lb_text = "at its lower bound (a membrane)" if at_bound else f"{lb_mm:.3g} mm"
        ax.set_title(
            f"{panel_title(label, species)}, {depth_mm:g} mm depth\nbending length {lb_text}",
            loc="left",
        )
        ax.set_xlabel("distance from the wedge x (mm, log scale)")
        ax.set_ylabel(DEFLECTION_LABEL)
    handles = [
        data_handle(),
        *[
            Line2D(
                [],
                [],
                color=FAMILIES[m].colour,
                linestyle=FAMILIES[m].linestyle,
                label=MODEL_NAMES[m],
            )
            for m in OTHER_FAMILIES
        ],
        Line2D(
            [],
            [],
            color=BENDING_COLOUR,
            linewidth=1.4,
            linestyle=FAMILIES["bending"].linestyle,
            label=BENDING_NAME,
        ),
        Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE),
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=legend_columns(fig, handles, 3))
    add_footer(fig, notice)
    return fig


@styled
def figure_bending_lengths(bending, averaged, subjects, notice=""):
    """The fitted bending length of every trial, by species and depth, with its interval.

    An estimate at the lower end of its range (the skin cannot be told from the paper's
    membrane) is drawn open, its interval one-sided from that end.  The dotted line is
    the closest reading to the wedge: a bending length well below it is hidden between
    the wedge and the first reading.

    Parameters
    ----------
    bending : pandas.DataFrame
        The bending fits.
    averaged : pandas.DataFrame
        Averaged profiles (for the closest reading to the wedge).
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    rows = bending[np.isfinite(bending["bending_length_mm"].astype(float))] if len(bending) else []
    if not len(rows):
        return message_figure("No trial of this dataset has a bending fit.", notice)
    low_end = float(np.nanmin(rows["bending_length_ci_low_mm"].astype(float)))
    high_end = float(np.nanmax(rows["bending_length_ci_high_mm"].astype(float)))
    distances = averaged["distance_mm"].astype(float) if len(averaged) else []
    first_mm = float(np.min(distances[distances > 0])) if len(distances) else np.nan

    def first_reading(ax):
        if np.isfinite(first_mm):
            ax.axhline(first_mm, gid="first-reading", **WINDOW_STYLE)

    return draw_estimates_by_depth(
        rows,
        subjects,
        value="bending_length_mm",
        low="bending_length_ci_low_mm",
        high="bending_length_ci_high_mm",
        at_bound="bending_length_at_bound",
        gid="lb",
        # the symbol is the caption's: a subscript in matplotlib's mathtext would print
        # below the 7-point floor
        ylabel="bending length (mm, log scale)",
        bound_label="at the range's end (one-sided interval)",
        ylim=(low_end / 2, high_end * 40),  # room above for the subjects' key
        notice=notice,
        extra_handles=[Line2D([], [], label="closest reading to the wedge", **WINDOW_STYLE)],
        decorate=first_reading,
    )
