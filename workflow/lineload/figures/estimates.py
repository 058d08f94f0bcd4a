"""One fitted parameter of every trial, by species and depth, each with its interval.

The bending skin's bending length and the elastic finger's modulus ratio are drawn
alike: a panel per species, the trials of each subject side by side at each depth, the
interval as a bar, and an estimate at an end of its fitted range drawn open.
"""

from __future__ import annotations

import numpy as np
from matplotlib import ticker
from matplotlib.lines import Line2D

from lineload.figures.style import (
    DOUBLE_COLUMN_MM,
    SINGLE_COLUMN_MM,
    SPECIES_MARKERS,
    SPECIES_PLURAL,
    add_footer,
    legend_columns,
    new_figure,
    subject_table,
)

__all__ = ["draw_estimates_by_depth"]


def draw_estimates_by_depth(
    rows,
    subjects,
    *,
    value,
    low,
    high,
    at_bound,
    gid,
    ylabel,
    bound_label,
    ylim,
    notice="",
    extra_handles=(),
    decorate=None,
    legend_loc="upper left",
):
    """A figure of one parameter by species and depth, on a log scale.

    Parameters
    ----------
    rows : pandas.DataFrame
        The trials to draw: ``subject``, ``species``, ``depth_mm`` and the columns named
        by ``value``, ``low``, ``high`` and ``at_bound``.
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label`` (the subjects' order and names).
    value, low, high, at_bound : str
        Columns of the estimate, its interval's ends and its at-a-bound flag (> 0).
    gid : str
        Prefix of the drawn lines' ids: ``{gid}-interval:S``, ``{gid}:S`` and
        ``{gid}-bound:S`` for an estimate at a bound.
    ylabel, bound_label : str
        The y axis's label; the legend's words for an open marker.
    ylim : tuple of float
        The y range (from the data's ends, chosen by the caller).
    notice : str
        Footer text; empty for none.
    extra_handles : sequence of matplotlib artists
        Further entries of the figure's legend.
    decorate : callable, optional
        ``decorate(ax)`` draws anything else on each panel (before its legend).
    legend_loc : str
        Where each panel's key of subjects goes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    table = subject_table(subjects)
    present = [s for s in ("monkey", "human") if (rows["species"] == s).any()]
    present += sorted(set(rows["species"]) - set(present))
    fig = new_figure(SINGLE_COLUMN_MM if len(present) == 1 else DOUBLE_COLUMN_MM, 70.0)
    axes = fig.subplots(1, len(present), squeeze=False, sharey=True)[0]
    for ax, species in zip(axes, present, strict=True):
        mine = rows[rows["species"] == species]
        members = [s for s in table.index if s in set(mine["subject"])]
        members += sorted(set(mine["subject"]) - set(members))
        depths = sorted(set(mine["depth_mm"].astype(float)))
        step = min(np.diff(depths)) if len(depths) > 1 else 0.5
        marker = SPECIES_MARKERS.get(species, "D")
        for k, subject in enumerate(members):
            offset = (k - (len(members) - 1) / 2) * 0.6 * step / max(len(members), 1)
            colour = f"C{k % 10}"
            for _, row in mine[mine["subject"] == subject].iterrows():
                x = float(row["depth_mm"]) + offset
                bound = float(row.get(at_bound, 0.0)) > 0
                ax.plot(
                    [x, x],
                    [float(row[low]), float(row[high])],
                    color=colour,
                    linewidth=0.9,
                    gid=f"{gid}-interval:{subject}",
                )
                ax.plot(
                    x,
                    float(row[value]),
                    linestyle="none",
                    marker=marker,
                    markersize=4.0,
                    color=colour,
                    markerfacecolor="white" if bound else colour,
                    gid=f"{gid}-bound:{subject}" if bound else f"{gid}:{subject}",
                )
            label = table.loc[subject, "label"] if subject in table.index else subject
            ax.plot([], [], linestyle="none", marker=marker, color=colour, label=str(label))
        if decorate is not None:
            decorate(ax)
        ax.set_yscale("log")
        # plain numbers: a power of ten's exponent would print below the 7-point floor
        ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(ticker.NullFormatter())
        ax.set_ylim(*ylim)
        ax.set_xticks(depths, [f"{d:g}" for d in depths])
        ax.set_xlabel("indentation depth W₀ (mm)")
        ax.set_title(SPECIES_PLURAL.get(species, species).capitalize(), loc="left")
        ax.legend(loc=legend_loc, ncols=2, fontsize=7.0)
    axes[0].set_ylabel(ylabel)
    handles = [
        Line2D([], [], linestyle="none", marker="o", color="0.3", label="estimate, 95 % interval"),
        Line2D(
            [],
            [],
            linestyle="none",
            marker="o",
            color="0.3",
            markerfacecolor="white",
            label=bound_label,
        ),
        *extra_handles,
    ]
    fig.legend(
        handles=handles,
        loc="outside upper center",
        ncols=legend_columns(fig, handles, len(handles)),
    )
    add_footer(fig, notice)
    return fig
