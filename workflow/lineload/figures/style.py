"""The shared look of every figure, the one place figures are saved, and shared helpers.

Every figure function in :mod:`lineload.figures` draws inside :func:`figure_style`
(the :func:`styled` decorator) and returns a :class:`matplotlib.figure.Figure`;
none of them reads or writes files.  :func:`save_figure` writes a figure as PDF
and PNG with every time stamp and version string removed, so two builds give
identical bytes.

Conventions
-----------
* Lengths are tissue millimetres; the schematics (Figures 3-5) are drawn in
  units of the membrane half-width ``L``.
* Deflection is downward positive, as in the models.  Profile plots put the
  deflection axis downward (zero at the top), so the curves look like the skin
  surface they describe; residual plots use an ordinary upward axis.
* Artists that tests or readers may want to find carry a ``gid`` (listed in
  each figure function's docstring); the data notice is ``footer`` and the
  text of a figure with nothing to draw is ``message``.
"""

from __future__ import annotations

import math
import textwrap
from contextlib import contextmanager
from functools import wraps

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
from fontTools import subset as font_subset
from matplotlib import colormaps, ticker
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine
from matplotlib.lines import Line2D

from lineload import models
from lineload.fitting.families import FAMILIES
from lineload.io import replaced_atomically

__all__ = [
    "DATA_COLOUR",
    "DEFLECTION_LABEL",
    "DISTANCE_LABEL",
    "DOUBLE_COLUMN_MM",
    "FOOTER_FONT_PT",
    "LEGEND_ROW_MM",
    "MIN_FONT_PT",
    "MM_PER_INCH",
    "MODEL_COLOURS",
    "MODEL_LINESTYLES",
    "MODEL_NAMES",
    "NOTE_FONT_PT",
    "REST_COLOUR",
    "SCHEMATIC_MM",
    "SINGLE_COLUMN_MM",
    "SPECIES_MARKERS",
    "SPECIES_PLURAL",
    "STYLE",
    "WINDOW_STYLE",
    "add_footer",
    "depth_colours",
    "figure_style",
    "grid_legend",
    "grid_shape",
    "grid_ylabel",
    "label_outer_axes",
    "legend_columns",
    "log_distance_axis",
    "message_figure",
    "new_figure",
    "noted_legend",
    "padded_limits",
    "panel_title",
    "save_figure",
    "styled",
    "subject_table",
    "wrapped_note",
]

MM_PER_INCH = 25.4
#: Journal column widths (mm).  The article's text is as wide as a double column, so
#: every figure prints at its own size and its type at the sizes set here.
SINGLE_COLUMN_MM = 85.0
DOUBLE_COLUMN_MM = 175.0
#: Width of the schematics of the model (Figures 3-5), narrower than the text (mm).
SCHEMATIC_MM = 140.0
#: Smallest type in any figure as printed (points), the least journals ask for.  Sub-
#: and superscripts are written as Unicode characters (W₀, L²) so none is smaller.
MIN_FONT_PT = 7.0
#: Size of the data-notice footer (points).
FOOTER_FONT_PT = MIN_FONT_PT
#: Size of a note above a figure (points).
NOTE_FONT_PT = 7.0
#: Height of one row of a 7-point legend (mm), for figures that grow with their legend.
LEGEND_ROW_MM = 3.6

SPECIES_PLURAL = {"monkey": "monkeys", "human": "humans"}
#: Marker of each species wherever species are told apart by marker.
SPECIES_MARKERS = {"monkey": "o", "human": "s"}

#: Colour of each model of the fit table (the registry's: Okabe-Ito palette, safe for
#: colour-blind readers).
MODEL_COLOURS = {model: FAMILIES[model].colour for model in models.TABLE_MODELS}
#: Legend name of each model of the fit table (the sensitivity refits have their
#: own names, in :data:`lineload.fitting.sensitivity.MODEL_NAMES`).
MODEL_NAMES = {model: models.MODEL_NAMES[model].legend for model in models.TABLE_MODELS}
#: Line style of each model where several are drawn over each other.
MODEL_LINESTYLES = {model: FAMILIES[model].linestyle for model in models.TABLE_MODELS}
DATA_COLOUR = "black"
REST_COLOUR = "0.45"
WINDOW_STYLE = {"color": "0.55", "linestyle": ":", "linewidth": 0.9}

DEFLECTION_LABEL = "deflection w (mm, downward)"
DISTANCE_LABEL = "distance from the wedge x (mm)"

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


def styled(function):
    """Decorator: run a figure function inside :func:`figure_style`."""

    @wraps(function)
    def wrapper(*args, **kwargs):
        with figure_style():
            return function(*args, **kwargs)

    return wrapper


#: OpenType layout tables (substitutions, positioning, their definitions): a PDF viewer
#: draws an embedded TrueType font's glyphs by index and never reads them.
LAYOUT_TABLES = ("GSUB", "GPOS", "GDEF")


@contextmanager
def fonts_without_layout_tables():
    """Context manager: the fonts embedded in PDFs drop :data:`LAYOUT_TABLES`.

    matplotlib embeds each font (TrueType, ``pdf.fonttype`` 42) as a subset made by
    fontTools, which decompiles the layout tables to subset them: about two thirds of
    a figure's PDF time, for tables no PDF viewer uses (the glyphs are placed by
    matplotlib).  fontTools' default list of tables to drop gains them for the
    duration; the text drawn, its positions and its extraction are unchanged (tested).
    """
    options = font_subset.Options
    default = options._drop_tables_default
    options._drop_tables_default = [*default, *LAYOUT_TABLES]
    try:
        yield
    finally:
        options._drop_tables_default = default


def save_figure(fig, pdf_path, png_path, dpi):
    """Write a figure as PDF and PNG, byte-for-byte reproducibly.

    The layout engine (constrained or compressed) runs once and is then
    removed, so both files (and any later save of the same figure) share the
    same geometry, and neither save lays out or draws the figure more than
    once.  The PDF carries no creation or modification date and no
    creator/producer strings (which name the matplotlib version); the PNG
    carries no ``Software`` text chunk.
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
        engine = fig.get_layout_engine()
        if engine is not None:
            if not isinstance(engine, PlaceHolderLayoutEngine):
                engine.execute(fig)  # only the layout, not a whole (unrendered) draw
            # Then no engine at all: "none" would leave a placeholder engine, and
            # with any engine set, savefig draws the figure once more before saving.
            with matplotlib.rc_context(
                {"figure.autolayout": False, "figure.constrained_layout.use": False}
            ):
                fig.set_layout_engine(None)
        # each file appears under its name only when complete (a killed job leaves none)
        with replaced_atomically(pdf_path) as temporary, fonts_without_layout_tables():
            fig.savefig(
                temporary,
                format="pdf",
                metadata={"CreationDate": None, "ModDate": None, "Producer": None, "Creator": None},
            )
        with replaced_atomically(png_path) as temporary:
            fig.savefig(temporary, format="png", dpi=dpi, metadata={"Software": None})


# ---------------------------------------------------------------- building figures


def new_figure(width_mm, height_mm, layout="constrained"):
    """An empty figure of the given size (mm) with a layout engine."""
    return Figure(figsize=(width_mm / MM_PER_INCH, height_mm / MM_PER_INCH), layout=layout)


def add_footer(fig, notice):
    """Print the data notice as a grey footer and keep the layout clear of it.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    notice : str
        Footer text; empty for none (then nothing is added).
    """
    if not notice:
        return
    width_pt = fig.get_figwidth() * 72.0
    # DejaVu Sans averages about 0.55 em per character; leave a margin.
    per_line = max(20, int(0.92 * width_pt / (0.58 * FOOTER_FONT_PT)))
    lines = textwrap.wrap(as_typed(notice), per_line) or [as_typed(notice)]
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


def wrapped_note(fig, note, fontsize=None):
    """A sentence wrapped to the width of the figure, for a legend title (or '')."""
    if not note:
        return ""
    fontsize = fontsize or NOTE_FONT_PT
    width_pt = fig.get_figwidth() * 72.0
    per_line = max(20, int(0.92 * width_pt / (0.58 * fontsize)))
    return "\n".join(textwrap.wrap(note, per_line))


def message_figure(message, notice, width_mm=SINGLE_COLUMN_MM, height_mm=45.0):
    """A figure with one empty axis that says why there is nothing to draw.

    Parameters
    ----------
    message : str
        The reason, wrapped to the figure's width (gid ``message``).
    notice : str
        Footer text; empty for none.
    width_mm, height_mm : float, optional
        Size of the figure (mm).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = new_figure(width_mm, height_mm)
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
    add_footer(fig, notice)
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


def as_typed(text):
    """Text from the data (a label, the notice) as matplotlib should show it: as typed.

    A ``$`` would otherwise start mathtext, and a label such as ``$\\foo$`` stop the
    figure with a parse error; the workflow's own labels keep their maths.
    """
    return str(text).replace("$", r"\$")


def subject_table(subjects):
    """Subject sheet as a DataFrame indexed by id, with a label for every subject.

    Parameters
    ----------
    subjects : pandas.DataFrame
        ``subject``, ``species`` and optionally ``label`` (a missing or blank
        label falls back to the id).

    Returns
    -------
    pandas.DataFrame
        Labels as typed (:func:`as_typed`), ready for matplotlib.
    """
    table = pd.DataFrame(subjects).copy()
    if "label" not in table.columns:
        table["label"] = table["subject"]
    labels = table["label"].astype(object)
    missing = labels.isna() | (labels.astype(str).str.strip() == "")
    table["label"] = [
        as_typed(label) for label in np.where(missing, table["subject"], labels.astype(str))
    ]
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


# ---------------------------------------------------------------- axes and legends


def _legend_entry_pt(handle, fontsize):
    """Width (points) of one legend entry: handle, padding and label."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextToPath

    label = handle.get_label()
    width, _, _ = TextToPath().get_text_width_height_descent(
        label, FontProperties(size=fontsize), ismath="$" in label
    )
    rc = matplotlib.rcParams
    return (rc["legend.handlelength"] + rc["legend.handletextpad"]) * fontsize + float(width)


def _legend_fits(fig, columns_pt, fontsize):
    """Whether legend columns of these widths (points) fit the figure's width."""
    rc = matplotlib.rcParams
    spacing = (len(columns_pt) - 1) * rc["legend.columnspacing"] * fontsize
    border = 2 * rc["legend.borderpad"] * fontsize
    return sum(columns_pt) + spacing + border <= 0.98 * fig.get_figwidth() * 72.0


def _legend_font_pt():
    from matplotlib.font_manager import FontProperties

    return FontProperties(size=matplotlib.rcParams["legend.fontsize"]).get_size()


def legend_columns(fig, handles, max_columns):
    """The most columns, up to max_columns, in which a legend of these handles fits the
    figure's width (entries filled column by column, as matplotlib does)."""
    fontsize = _legend_font_pt()
    widths = [_legend_entry_pt(h, fontsize) for h in handles]
    n_columns = max(1, min(max_columns, len(widths)))
    while n_columns > 1:
        per_column = math.ceil(len(widths) / n_columns)
        columns = [max(widths[i : i + per_column]) for i in range(0, len(widths), per_column)]
        if _legend_fits(fig, columns, fontsize):
            break
        n_columns -= 1
    return n_columns


def noted_legend(fig, handles, max_columns, note, note_font_pt=7.0):
    """The figure's legend above its panels, titled by a note wrapped to the figure's width.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    handles : list of matplotlib.artist.Artist
        Legend handles with labels.
    max_columns : int
        At most this many columns; fewer where the entries would not fit the width
        (:func:`legend_columns`).
    note : str
        Sentence shown as the legend's title (:func:`wrapped_note`); empty for none.
    note_font_pt : float, optional
        Size of the note (points).

    Returns
    -------
    matplotlib.legend.Legend
    """
    return fig.legend(
        handles=handles,
        loc="outside upper center",
        ncols=legend_columns(fig, handles, max_columns),
        title=wrapped_note(fig, note, note_font_pt),
        title_fontsize=note_font_pt,
    )


def grid_legend(fig, blocks, max_columns=None):
    """Handles and column count for a figure legend that fits the figure's width.

    Each block (a list of handles) starts a new row and wraps onto as many rows
    as it needs; the column count is the largest (up to ``max_columns``) whose
    rows fit the width, measured from the labels' font metrics.  Legends fill
    column by column, so rows are interleaved, with invisible blank entries
    where a row is short.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    blocks : list of list of matplotlib.artist.Artist
        Legend handles with labels, one list per group of entries.
    max_columns : int, optional
        At most this many columns (default: the longest block).

    Returns
    -------
    handles : list
    n_columns : int
    """

    fontsize = _legend_font_pt()
    blocks = [list(block) for block in blocks if block]
    widths = [[_legend_entry_pt(h, fontsize) for h in block] for block in blocks]
    n_columns = min(max_columns or 99, max(len(block) for block in blocks))
    while n_columns > 1:
        rows = [w[i : i + n_columns] for w in widths for i in range(0, len(w), n_columns)]
        columns = [max(row[j] for row in rows if j < len(row)) for j in range(n_columns)]
        if _legend_fits(fig, columns, fontsize):
            break
        n_columns -= 1
    rows = [b[i : i + n_columns] for b in blocks for i in range(0, len(b), n_columns)]
    blank = Line2D([], [], linestyle="none", label=" ")
    handles = [row[j] if j < len(row) else blank for j in range(n_columns) for row in rows]
    return handles, n_columns


def grid_shape(n_panels, max_columns=2):
    """Rows and columns of a grid holding n_panels, at most max_columns wide."""
    n_columns = min(n_panels, max_columns)
    return math.ceil(n_panels / n_columns), n_columns


def grid_ylabel(fig, axes, text, fontsize=None):
    """One y label for a grid of panels, centred on the panels and no longer than they
    are high.

    ``Figure.supylabel`` centres its label on the whole figure, legend and footer
    included, so a label longer than the panels are high runs into the legend above
    them.  Here the figure is laid out once (its layout engine run), the label wrapped onto
    more lines where it is longer than the panels' height, and moved to their middle;
    the constrained layout keeps that height when it places the label again.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        With the constrained layout.
    axes : iterable of Axes
        The panels the label belongs to.
    text : str
    fontsize : float, optional
        Points; the axes labels' size by default.

    Returns
    -------
    matplotlib.text.Text
    """
    fontsize = fontsize or matplotlib.rcParams["axes.labelsize"]
    axes = list(axes)
    label = fig.supylabel(text, fontsize=fontsize)

    def panels_span():
        # the layout alone places the panels: drawing every artist as well (what
        # draw_without_rendering does after it) changed nothing here and took a
        # quarter of the time
        engine = fig.get_layout_engine()
        if engine is None:  # no layout engine: a whole draw places the panels
            fig.draw_without_rendering()
        else:
            engine.execute(fig)
        boxes = [ax.get_position() for ax in axes]
        return min(b.y0 for b in boxes), max(b.y1 for b in boxes)

    low, high = panels_span()
    # a character of DejaVu Sans is about 0.58 of the type size wide on average
    per_line = max(12, int((high - low) * fig.get_figheight() * 72.0 / (0.58 * fontsize)))
    if len(text) > per_line:
        # a parenthesis ('(mm, log scale)') starts a line of its own
        head, _, tail = text.partition(" (")
        parts = [head, f"({tail}"] if tail else [head]
        label.set_text("\n".join(line for part in parts for line in textwrap.wrap(part, per_line)))
        low, high = panels_span()
    label.set_y(0.5 * (low + high))
    return label


def label_outer_axes(axes_grid, present, xlabel, ylabel):
    """Axis labels on the left column and on the lowest panel of each column.

    Parameters
    ----------
    axes_grid : numpy.ndarray of Axes
        Two-dimensional, as from ``Figure.subplots(squeeze=False)``.
    present : numpy.ndarray of bool
        Same shape: which cells hold a panel.
    xlabel, ylabel : str
    """
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


def padded_limits(values, pad_fraction=0.06):
    """Axis limits around the finite values, widened by pad_fraction of their range.

    Returns
    -------
    tuple of float
        ``(low, high)``; ``(-1, 1)`` when no value is finite.
    """
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return -1.0, 1.0
    lo, hi = float(values.min()), float(values.max())
    pad = pad_fraction * (hi - lo) if hi > lo else max(abs(hi), 1.0) * 0.1
    return lo - pad, hi + pad


def log_distance_axis(ax):
    """Log distance axis with plain-number ticks at 1, 2 and 5 times powers of ten."""
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f"{value:g}"))
    ax.xaxis.set_minor_locator(ticker.LogLocator(base=10.0, subs=(3.0, 4.0, 6.0, 7.0, 8.0, 9.0)))
    ax.xaxis.set_minor_formatter(ticker.NullFormatter())
