"""The calibration's figure: coverage of the intervals when the stated priors are wrong.

The coverage study (:mod:`lineload.simulation.coverage`) makes data with errors of
known size and fits them with the priors the workflow states.  Where the true sizes
differ from the stated ones, the intervals' coverage shows what a wrong prior costs.
The function takes the study's summary (``docs/calibration/coverage.csv``, the committed
calibration) and returns a :class:`matplotlib.figure.Figure`.

gids: ``coverage:<model>:<parameter>`` (the errorbar lines of a family against the
true/stated ratio), ``other:<model>:<parameter>`` (the other misspecified worlds),
``nominal`` (the 95 % line) and ``footer``.
"""

from __future__ import annotations

import textwrap

import numpy as np
from matplotlib.ticker import NullLocator

from lineload.figures.style import (
    DOUBLE_COLUMN_MM,
    MIN_FONT_PT,
    MODEL_COLOURS,
    MODEL_NAMES,
    add_footer,
    message_figure,
    new_figure,
    noted_legend,
    styled,
)

__all__ = ["NOMINAL", "SHOWN", "figure_coverage_misspecified"]

#: Nominal coverage of the intervals (their level).
NOMINAL = 0.95
#: The intervals drawn: (model, parameter) with its symbol.
SHOWN = (
    ("waterbed", "L_mm", "L"),
    ("arc", "L_mm", "L"),
    ("boussinesq", "A_mm", "A"),
)
#: What the scenarios whose priors are scaled are called in the summary's
#: ``misspecified`` column; ``none`` is the world the fit assumes (ratio 1).
SCALED = "shared errors' sizes"
AS_ASSUMED = "none"
#: Tick labels of the worlds whose short name reads ambiguously alone.
_WORLD_LABELS = {AS_ASSUMED: "as stated"}
#: Marker of each family (colour from the model registry).
_MARKERS = {"waterbed": "o", "arc": "s", "boussinesq": "D"}


def _label(model, symbol):
    return f"{MODEL_NAMES.get(model, model)} {symbol}"


def _errorbar(ax, x, rows, model, symbol, gid, line=True):
    coverage = 100 * rows["coverage"].astype(float).to_numpy()
    low = 100 * rows["ci_low"].astype(float).to_numpy()
    high = 100 * rows["ci_high"].astype(float).to_numpy()
    drawn = ax.errorbar(
        x,
        coverage,
        yerr=np.vstack([coverage - low, high - coverage]),
        color=MODEL_COLOURS.get(model, "black"),
        marker=_MARKERS.get(model, "o"),
        markersize=3.5,
        linewidth=1.0 if line else 0.0,
        elinewidth=0.8,
        capsize=2.0,
        label=_label(model, symbol),
    )
    drawn.lines[0].set_gid(gid)
    return drawn


@styled
def figure_coverage_misspecified(coverage, notice=""):
    """Coverage of the 95 % intervals against the ratio of the errors' true to stated size.

    Left: the errors the left-right differences cannot measure (the priors) made at
    0.5 to 3 times the size the fit states, per family (waterbed L, arc L, Boussinesq
    A), each point with its Clopper-Pearson 95 % interval; the world the fit assumes
    at ratio 1.  Right: the other misspecified worlds of the study (depth error alone
    at a larger size, a resting curvature error, misreads, a tracing correlation and
    reading tails the estimator does not assume), beside the world it assumes.  A
    dashed line marks the nominal 95 %.

    Parameters
    ----------
    coverage : pandas.DataFrame
        The coverage study's summary (``scenario``, ``misspecified``,
        ``prior_ratio``, ``model``, ``parameter``, ``species``, ``coverage``,
        ``ci_low``, ``ci_high``); the pooled rows (``species`` ``all``) are drawn.
    notice : str, optional
        Footer text; empty for none.

    Returns
    -------
    matplotlib.figure.Figure
    """
    needed = {"misspecified", "prior_ratio", "scenario", "coverage", "ci_low", "ci_high"}
    if coverage is None or not needed <= set(coverage.columns):
        return message_figure(
            "The coverage table has no misspecified worlds: run the calibration "
            "(snakemake calibration) and commit its tables.",
            notice,
        )
    pooled = coverage[coverage["species"].astype(str) == "all"]
    fig = new_figure(DOUBLE_COLUMN_MM, 92.0)
    left, right = fig.subplots(1, 2, sharey=True, width_ratios=[1.0, 1.25])
    scaled = pooled[pooled["misspecified"].isin([SCALED, AS_ASSUMED])]
    others = pooled[~pooled["misspecified"].isin([SCALED])]
    worlds = list(dict.fromkeys(others["scenario"]))
    offsets = np.linspace(-0.06, 0.06, len(SHOWN))
    positions = np.arange(len(worlds), dtype=float)
    spread = np.linspace(-0.2, 0.2, len(SHOWN))
    lowest = [NOMINAL * 100]
    for (model, parameter, symbol), offset, step in zip(SHOWN, offsets, spread, strict=True):
        mine = scaled[(scaled["model"] == model) & (scaled["parameter"] == parameter)]
        mine = mine.sort_values("prior_ratio", kind="stable")
        ratio = mine["prior_ratio"].astype(float).to_numpy()
        if ratio.size:
            # the offsets keep the families' intervals apart on a log axis
            _errorbar(
                left, ratio * np.exp(offset), mine, model, symbol, f"coverage:{model}:{parameter}"
            )
            lowest.append(100 * float(mine["ci_low"].astype(float).min()))
        theirs = others[(others["model"] == model) & (others["parameter"] == parameter)]
        at = [worlds.index(s) for s in theirs["scenario"]]
        if at:
            _errorbar(
                right,
                positions[at] + step,
                theirs,
                model,
                symbol,
                f"other:{model}:{parameter}",
                line=False,
            )
            lowest.append(100 * float(theirs["ci_low"].astype(float).min()))
    for ax in (left, right):
        ax.axhline(100 * NOMINAL, color="0.4", linestyle="--", linewidth=0.8, gid="nominal")
    left.set_xscale("log")
    ratios = sorted({float(r) for r in scaled["prior_ratio"]})
    left.set_xticks(ratios, [f"{r:g}" for r in ratios])
    left.xaxis.set_minor_locator(NullLocator())
    left.set_xlabel("true / stated size of the priors")
    left.set_ylabel("coverage of the 95 % intervals (%)")
    left.set_title("The priors' errors made larger or smaller", fontsize="medium")
    # the short name of each world (what it makes differently), as the table gives it
    short = dict(zip(others["scenario"], others["misspecified"], strict=False))
    right.set_xticks(
        positions,
        [textwrap.fill(_WORLD_LABELS.get(short[w], short[w]), 11) for w in worlds],
        fontsize=MIN_FONT_PT,  # "small" would print at 6.7 pt
    )
    right.set_title("Other errors the fit does not state", fontsize="medium")
    right.set_xlim(-0.6, len(worlds) - 0.4)
    left.set_ylim(max(0.0, min(lowest) - 5.0), 101.0)
    handles, _ = left.get_legend_handles_labels()
    noted_legend(
        fig,
        handles,
        len(handles),
        "Coverage with its Clopper-Pearson 95 % interval; dashed: the nominal 95 %.",
    )
    add_footer(fig, notice)
    return fig
