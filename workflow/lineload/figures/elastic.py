"""Figures of the elastic finger: its fits on a monkey's and a human's points; the fitted ratio.

Every function takes data (pandas DataFrames, plain numbers) and returns a
:class:`matplotlib.figure.Figure`; parameter names follow
:data:`lineload.figures.registry.ARGUMENTS`, with two more a registry entry would add:
``elastic`` (the elastic fits, tables/elastic_fits.csv) and ``elastic_library`` (the kept
library, data/elastic/library.csv). Not yet in the registry: every registered figure is
printed in the article, whose captions are written there.

gids: ``data``, ``elastic:homogeneous``, ``elastic:layered`` and ``fit-window`` in the
examples; ``ratio:<subject>`` (an estimate with its interval) and ``ratio-bound:<subject>``
(an estimate at the library's end, drawn open) in the ratios; ``footer`` for the notice.
"""

from __future__ import annotations

import numpy as np
from matplotlib import ticker
from matplotlib.lines import Line2D

from lineload.figures.data import example_per_species
from lineload.figures.estimates import draw_estimates_by_depth
from lineload.figures.style import (
    DEFLECTION_LABEL,
    DOUBLE_COLUMN_MM,
    SINGLE_COLUMN_MM,
    WINDOW_STYLE,
    add_footer,
    legend_columns,
    message_figure,
    new_figure,
    panel_title,
    styled,
)
from lineload.fitting.elastic import find_block, fitted_curve_mm, library_blocks

__all__ = ["figure_elastic_examples", "figure_elastic_ratios"]

#: How each fit is drawn (Okabe-Ito colours not taken by the paper's families).
STYLES = {
    "homogeneous": {"color": "#999999", "linestyle": "--", "label": "homogeneous elastic finger"},
    "layered": {"color": "#000000", "linestyle": "-", "label": "layered elastic finger"},
}
#: The depth the examples prefer (the paper's Fig. 2), else the trial's deepest.
EXAMPLE_DEPTH_MM = 1.0


def _fitted(elastic):
    if elastic is None or not len(elastic):
        return elastic
    return elastic[np.isfinite(elastic["elastic_layered_modulus_ratio"].astype(float))]


@styled
def figure_elastic_examples(averaged, elastic, elastic_library, subjects, fit_window_mm, notice=""):
    """The homogeneous and the layered elastic finger on the averaged points of a monkey and
    a human, each curve drawn from the library at the fitted section, layer and ratio.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Averaged profiles (``subject``, ``depth_mm``, ``distance_mm``, ``deflection_mm``).
    elastic : pandas.DataFrame
        The elastic fits (:data:`lineload.fitting.elastic.ELASTIC_COLUMNS`).
    elastic_library : pandas.DataFrame
        The solution library the fits were made from.
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
    fitted = _fitted(elastic)
    if fitted is None or not len(fitted):
        return message_figure("No trial of this dataset has an elastic fit.", notice)
    chosen, table = example_per_species(fitted, subjects, EXAMPLE_DEPTH_MM)
    blocks = library_blocks(elastic_library)
    fig = new_figure(SINGLE_COLUMN_MM if len(chosen) == 1 else DOUBLE_COLUMN_MM, 75.0)
    axes = fig.subplots(1, len(chosen), squeeze=False)[0]
    for ax, (subject, species, depth_mm) in zip(axes, chosen, strict=True):
        row = fitted[
            (fitted["subject"] == subject) & np.isclose(fitted["depth_mm"].astype(float), depth_mm)
        ].iloc[0]
        points = averaged[
            (averaged["subject"] == subject)
            & np.isclose(averaged["depth_mm"].astype(float), depth_mm)
        ]
        x = points["distance_mm"].astype(float).to_numpy()
        y = points["deflection_mm"].astype(float).to_numpy()
        ax.plot(x, y, linestyle="none", marker="o", markersize=3.0, color="0.2", gid="data")
        block = find_block(blocks, species, depth_mm)
        near_mm, far_mm = block.reach_mm
        curve_x = np.geomspace(max(near_mm, x[x > 0].min()), min(far_mm, fit_window_mm), 300)
        lowest = [np.nanmin(y)]
        for name, style in STYLES.items():
            ratio = 1.0 if name == "homogeneous" else float(row["elastic_layered_modulus_ratio"])
            thickness = row.get("elastic_layered_layer_thickness_mm", block.thicknesses_mm[0])
            curve = fitted_curve_mm(
                block, curve_x, int(row[f"elastic_{name}_section"]), float(thickness), ratio
            )
            lowest.append(float(np.min(curve)))
            ax.plot(
                curve_x,
                curve,
                color=style["color"],
                linestyle=style["linestyle"],
                linewidth=1.2,
                gid=f"elastic:{name}",
            )
        ax.axvline(fit_window_mm, gid="fit-window", **WINDOW_STYLE)
        ax.set_ylim(max(depth_mm, np.nanmax(y)) * 1.05, min(0.0, *lowest) - 0.05 * depth_mm)
        label = table.loc[subject, "label"] if subject in table.index else subject
        bound = " (the library's largest)" if row["elastic_layered_ratio_at_bound"] > 0 else ""
        ax.set_title(
            f"{panel_title(label, species)}, {depth_mm:g} mm depth\n"
            f"modulus ratio {row['elastic_layered_modulus_ratio']:.3g}{bound}",
            loc="left",
        )
        ax.set_xlabel("distance from the wedge x (mm)")
        ax.set_ylabel(DEFLECTION_LABEL)
    handles = [
        Line2D([], [], linestyle="none", marker="o", markersize=3.0, color="0.2", label="data"),
        *[
            Line2D([], [], color=s["color"], linestyle=s["linestyle"], label=s["label"])
            for s in STYLES.values()
        ],
        Line2D([], [], label=f"fit window edge ({fit_window_mm:g} mm)", **WINDOW_STYLE),
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=legend_columns(fig, handles, 2))
    add_footer(fig, notice)
    return fig


@styled
def figure_elastic_ratios(elastic, subjects, notice=""):
    """The fitted modulus ratio of every trial, by species and depth, with its interval; an
    estimate at an end of the library's ratios is drawn open.

    Parameters
    ----------
    elastic : pandas.DataFrame
        The elastic fits.
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label``.
    notice : str
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    rows = _fitted(elastic)
    if rows is None or not len(rows):
        return message_figure("No trial of this dataset has an elastic fit.", notice)
    high = float(np.nanmax(rows["elastic_layered_ratio_ci_high"].astype(float)))

    def ratio_ticks(ax):
        ax.yaxis.set_major_locator(ticker.FixedLocator([1, 2, 5, 10, 20, 50, 100, 200, 500]))

    return draw_estimates_by_depth(
        rows,
        subjects,
        value="elastic_layered_modulus_ratio",
        low="elastic_layered_ratio_ci_low",
        high="elastic_layered_ratio_ci_high",
        at_bound="elastic_layered_ratio_at_bound",
        gid="ratio",
        ylabel="outer layer's modulus / pulp's (log scale)",
        bound_label="at the library's end",
        ylim=(0.8, 1.6 * high),  # from below the homogeneous finger's 1
        notice=notice,
        decorate=ratio_ticks,
        legend_loc="lower left",
    )
