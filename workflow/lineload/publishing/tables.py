"""Fit tables and the per-species summary as CSV, Markdown and LaTeX text.

Pure functions: a fit table (one row per subject and depth, the columns of
:data:`lineload.fitting.batch.FIT_COLUMNS`) goes in, text or a DataFrame comes out.
Numbers are rounded to fixed decimals so that the same inputs always give the
same bytes; writing files is left to :mod:`lineload.io`.

The LaTeX tables use the ``booktabs`` rules (``\\toprule``, ``\\midrule``,
``\\bottomrule``) and are a bare ``table`` environment, ready for ``\\input``.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd

from lineload import paper
from lineload.fitting.families import family
from lineload.models import MODEL_NAMES

__all__ = [
    "AT_BOUND_MARK",
    "SUMMARY_COLUMNS",
    "at_bound",
    "counted",
    "decimals_for",
    "escape_latex",
    "escape_markdown",
    "every",
    "fits_latex",
    "fits_markdown",
    "format_fixed",
    "latex_table",
    "markdown_table",
    "notice_footer",
    "percent_text",
    "sensitivity_markdown",
    "span_text",
    "summarise_fits",
    "summary_latex",
    "summary_markdown",
    "with_interval",
]


#: The models whose RMSE the Markdown and LaTeX tables show, as (column prefix, label).
MODELS = tuple((model, names.short) for model, names in MODEL_NAMES.items() if names.short)

#: Columns of the summary table (one row per species and depth).
SUMMARY_COLUMNS = [
    "species",
    "depth_mm",
    "n_trials",
    "waterbed_n_at_bound",
    "waterbed_L_mean_mm",
    "waterbed_L_sd_mm",
    "waterbed_rmse_mean_mm",
    "arc_rmse_mean_mm",
    "boussinesq_rmse_mean_mm",
    "rmse_ratio_boussinesq_to_waterbed_mean",
    "rmse_ratio_boussinesq_to_waterbed_min",
]

#: Decimals shown in the Markdown and LaTeX tables (the CSV files keep full precision).
DEPTH_DECIMALS = 2
LENGTH_DECIMALS = 2
RMSE_DECIMALS = 4
RATIO_DECIMALS = 2

_LATEX_SPECIALS = {
    "\\": r"\textbackslash{}",
    "&": r"\&",
    "%": r"\%",
    "$": r"\$",
    "#": r"\#",
    "_": r"\_",
    "{": r"\{",
    "}": r"\}",
    "~": r"\textasciitilde{}",
    "^": r"\textasciicircum{}",
}


def format_fixed(value, decimals, missing="–"):
    """Format a number with a fixed count of decimals; NaN or None gives ``missing``.

    Parameters
    ----------
    value : float or None
        Number to format.
    decimals : int
        Digits after the decimal point.
    missing : str, optional
        Text for a missing or non-finite value.

    Returns
    -------
    str
        For example ``format_fixed(0.04964, 4) == "0.0496"``; ``-0.0`` prints as ``0.0``.
    """
    if value is None:
        return missing
    value = float(value)
    if not math.isfinite(value):
        return missing
    text = f"{value:.{decimals}f}"
    if float(text) == 0.0:
        text = text.lstrip("-")
    return text


def decimals_for(uncertainty, significant=2, most=6):
    """Decimals that show ``significant`` digits of an uncertainty (and no more).

    Parameters
    ----------
    uncertainty : float
        A standard error or an interval's half-width (> 0).
    significant : int, optional
        Digits of the uncertainty to keep.
    most : int, optional
        Never more decimals than this (an uncertainty of 0 or NaN gets it too).

    Returns
    -------
    int
        For example 2 for 0.14 (``13.28``), 1 for 1.4, 0 for 14.
    """
    if not (uncertainty > 0 and math.isfinite(uncertainty)):
        return most
    return int(min(most, max(0, significant - 1 - math.floor(math.log10(uncertainty)))))


def with_interval(value, low, high, missing="–"):
    """``value (low–high)`` to the decimals the interval's half-width supports.

    Parameters
    ----------
    value, low, high : float
        An estimate and the ends of its interval; NaN ends print as ``missing``.

    Returns
    -------
    str
    """
    half = 0.5 * (float(high) - float(low))
    decimals = decimals_for(half)
    if not math.isfinite(float(value)):
        return missing
    if not math.isfinite(half):
        return format_fixed(value, decimals)
    return (
        f"{format_fixed(value, decimals)} "
        f"({format_fixed(low, decimals, missing)}–{format_fixed(high, decimals, missing)})"
    )


def span_text(values, decimals=2, unit=" mm"):
    """The range of the finite values as text, for a sentence.

    Parameters
    ----------
    values : array_like
        Numbers; NaN and infinities are left out.
    decimals : int, optional
        Digits after the decimal point (:func:`format_fixed`).
    unit : str, optional
        Appended once, after the range (``" mm"``; ``""`` for none).

    Returns
    -------
    str
        ``"1.25 to 2.00 mm"``; one value (``"3.0 mm"``) if both ends print the same;
        ``"none"`` if no value is finite.
    """
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    if values.size == 0:
        return "none"
    low, high = format_fixed(values.min(), decimals), format_fixed(values.max(), decimals)
    return f"{low}{unit}" if low == high else f"{low} to {high}{unit}"


def notice_footer(notice):
    """The data notice as the last line of a Markdown summary.

    Parameters
    ----------
    notice : str
        Data notice; its whitespace (line breaks included) collapses to single spaces.

    Returns
    -------
    str
        ``"\\nNote: <notice>\\n"``, to append after a table; empty for an empty notice.
    """
    return f"\nNote: {escape_markdown(notice)}\n" if notice else ""


def escape_latex(text):
    """Escape the characters LaTeX treats specially (``_``, ``&``, ``%`` and the like).

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return "".join(_LATEX_SPECIALS.get(char, char) for char in str(text))


#: A ``<`` that starts HTML markup: a tag, a closing tag, a comment or a declaration.
_HTML_OPENING = re.compile(r"<(?=[A-Za-z/!?])")


def counted(count, noun, plural=None):
    """A count with its noun in the right number: ``"1 degree of freedom"``, ``"3 trials"``.

    Parameters
    ----------
    count : int
        How many.
    noun : str
        The noun in the singular (``"trial"``; ``"degree of freedom"``).
    plural : str, optional
        The plural where it is not ``noun + "s"`` (``"degrees of freedom"``).
    """
    count = int(count)
    return f"{count} {noun if count == 1 else plural or noun + 's'}"


def every(count, noun, plural=None):
    """All of a count, as a sentence says it: ``"the one trial"``, ``"both trials"``,
    ``"all 3 trials"`` (``"no trials"`` for none)."""
    count = int(count)
    many = plural or noun + "s"
    if count == 0:
        return f"no {many}"
    if count == 1:
        return f"the one {noun}"
    if count == 2:
        return f"both {many}"
    return f"all {count} {many}"


def percent_text(fraction, decimals=1):
    """A fraction in percent, never shown as zero when it is not: ``0.1234 -> "12.3 %"``,
    ``0.00001 -> "< 0.1 %"``, ``0 -> "0 %"``; NaN gives ``"–"``."""
    if fraction is None or not math.isfinite(float(fraction)):
        return "–"
    value = 100.0 * float(fraction)
    if value == 0:
        return "0 %"
    smallest = 0.5 * 10.0**-decimals
    if abs(value) < smallest:
        return f"{'> -' if value < 0 else '< '}{format_fixed(2 * smallest, decimals)} %"
    return f"{format_fixed(value, decimals)} %"


def join_words(items):
    """``["a", "b", "c"]`` -> ``"a, b and c"``."""
    items = [str(item) for item in items]
    if len(items) <= 1:
        return "".join(items)
    return ", ".join(items[:-1]) + " and " + items[-1]


def escape_markdown(text):
    """Make text safe inside a Markdown table cell (pipes escaped, one line, no HTML).

    A ``<`` that would open an HTML tag, comment or entity's markup (``<b>``,
    ``</td>``, ``<!--``) becomes ``&lt;``, so text from the data is shown as
    typed; ``p < 0.05`` stays as written.

    Parameters
    ----------
    text : str

    Returns
    -------
    str
    """
    return _HTML_OPENING.sub("&lt;", " ".join(str(text).replace("|", "\\|").split()))


def markdown_table(headers, rows, align):
    """A pipe table in GitHub-flavoured Markdown.

    Parameters
    ----------
    headers : list of str
        Column titles.
    rows : list of list of str
        Cells, already formatted.
    align : str
        One letter per column: ``l`` (left) or ``r`` (right).

    Returns
    -------
    str
        The table, one line per row, ending with a newline.
    """
    if len(align) != len(headers) or any(len(row) != len(headers) for row in rows):
        raise ValueError("every row and the alignment must have one entry per column")
    rule = {"l": "---", "r": "--:"}
    lines = [
        "| " + " | ".join(escape_markdown(h) for h in headers) + " |",
        "|" + "|".join(rule[a] for a in align) + "|",
    ]
    lines += ["| " + " | ".join(escape_markdown(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def latex_table(head_lines, rows, column_spec, caption, label, notice=""):
    """A booktabs ``table`` environment, ready for ``\\input``.

    Parameters
    ----------
    head_lines : list of str
        LaTeX lines of the header (already escaped, each ending in ``\\\\`` or a
        ``\\cmidrule``), placed between ``\\toprule`` and ``\\midrule``.
    rows : list of list of str
        Body cells as plain text; they are escaped here.
    column_spec : str
        The tabular column specification, e.g. ``llrr``.
    caption : str
        Caption, LaTeX markup allowed (not escaped).
    label : str
        Label for ``\\ref``.
    notice : str, optional
        Plain text printed as a note under the table; empty for none.

    Returns
    -------
    str
    """
    if any(len(row) != len(column_spec) for row in rows):
        raise ValueError("every row must have one cell per column of column_spec")
    lines = [
        r"\begin{table}[htbp]",
        r"\centering",
        rf"\caption{{{caption}}}",
        rf"\label{{{label}}}",
        rf"\begin{{tabular}}{{{column_spec}}}",
        r"\toprule",
        *head_lines,
        r"\midrule",
        *(" & ".join(escape_latex(cell) for cell in row) + r" \\" for row in rows),
        r"\bottomrule",
        r"\end{tabular}",
    ]
    if notice:
        lines += [r"\par\smallskip", rf"{{\footnotesize \emph{{Note.}} {escape_latex(notice)}}}"]
    lines.append(r"\end{table}")
    return "\n".join(lines) + "\n"


def _species_rank(species):
    """Sort key: the species of :data:`lineload.paper.SPECIES` first, in that order, then others."""
    species = str(species)
    if species in paper.SPECIES:
        return (paper.SPECIES.index(species), "")
    return (len(paper.SPECIES), species)


def _fit_window_text(fits):
    """'0 < x <= 3 mm' from the fit table's window column, or a generic phrase."""
    windows = pd.unique(fits["fit_window_mm"].dropna()) if "fit_window_mm" in fits else []
    if len(windows) == 1:
        return f"{float(windows[0]):g} mm"
    return "the fit window"


def _fit_rows(fits):
    """Formatted cells of the fit table, one list per subject and depth."""
    rows = []
    for _, trial in fits.iterrows():
        rows.append(
            [
                str(trial["subject"]),
                str(trial["species"]),
                format_fixed(trial["depth_mm"], DEPTH_DECIMALS),
                str(int(trial["n_points"])),
                _L_cell(trial, "waterbed"),
                *(format_fixed(trial[f"{m}_rmse_mm"], RMSE_DECIMALS) for m, _ in MODELS),
            ]
        )
    return rows


#: Mark of a fitted L that ends on a bound of its search (the caption explains it).
AT_BOUND_MARK = "†"


def at_bound(trial, model):
    """Whether the fit table's row ``trial`` has ``model``'s L on a bound of its search
    (False where the table has no such column, as an older table)."""
    value = trial.get(f"{model}_L_at_bound", False)
    if isinstance(value, str):
        return value.strip().lower() == "true"
    return bool(value) if value == value else False


def _L_cell(trial, model):
    """A fitted L with its interval; one on a bound of its search marked, its interval
    one-sided (the bound is its lower end)."""
    text = with_interval(
        trial[f"{model}_L_mm"], trial[f"{model}_L_ci_low_mm"], trial[f"{model}_L_ci_high_mm"]
    )
    return text + AT_BOUND_MARK if at_bound(trial, model) else text


def _fits_caption(fits):
    window = _fit_window_text(fits)
    bounded = sum(at_bound(trial, "waterbed") for _, trial in fits.iterrows())
    caption = (
        "Fits to the left/right mean profile of each subject and depth, using the n points "
        f"that lie between the wedge and {window} from it. L is the fitted half-width of "
        "the small-slope waterbed for that window, whose depth under the wedge is held at "
        "the indentation depth; the RMSE columns give the root-mean-square residual of each "
        "model on the same points."
    )
    if bounded:
        caption += (
            f" {AT_BOUND_MARK} L ended on a bound of its search in {bounded} of "
            f"{len(fits)} rows (the farthest point fitted, below which the membrane would "
            "not reach every point, or a flat membrane): there L is a bound, not a "
            "measurement, and its interval is one-sided."
        )
    return caption


def fits_markdown(fits, notice=""):
    """The fit table as Markdown: waterbed L and each model's RMSE per subject and depth.

    Parameters
    ----------
    fits : pandas.DataFrame
        Fit table (columns of :data:`lineload.fitting.batch.FIT_COLUMNS`), rows in the
        order they are to be shown.
    notice : str, optional
        Data notice; when non-empty it is added as a footer line.

    Returns
    -------
    str
    """
    headers = [
        "Subject",
        "Species",
        "Depth (mm)",
        "n",
        "Waterbed L (mm, 95 % interval)",
        *(f"RMSE {label} (mm)" for _, label in MODELS),
    ]
    text = "# Model fits per subject and depth\n\n" + _fits_caption(fits) + "\n\n"
    text += markdown_table(headers, _fit_rows(fits), "llrrrrrr")
    return text + notice_footer(notice)


def fits_latex(fits, notice=""):
    """The fit table as a booktabs LaTeX ``table`` (same content as :func:`fits_markdown`).

    Parameters
    ----------
    fits : pandas.DataFrame
        Fit table, rows in display order.
    notice : str, optional
        Data notice; when non-empty it becomes a note under the table.

    Returns
    -------
    str
    """
    head = [
        r" & & & & Waterbed & \multicolumn{3}{c}{RMSE (mm)} \\",
        r"\cmidrule(lr){6-8}",
        r"Subject & Species & Depth (mm) & $n$ & $L$ (mm, 95\,\% interval) & "
        + " & ".join(escape_latex(label) for _, label in MODELS)
        + r" \\",
    ]
    caption = escape_latex(_fits_caption(fits))
    return latex_table(head, _fit_rows(fits), "llrrrrrr", caption, "tab:fits", notice)


def summarise_fits(fits):
    """Per species and depth: trials, waterbed L (mean, SD, and how many of the fits
    ended on a bound of their search, which the mean includes), mean RMSE of each model.

    The RMSE ratio Boussinesq / waterbed is computed per trial first; the table
    gives the mean and the smallest of these per-trial ratios (a ratio above 1
    means the waterbed fitted that trial better).

    Parameters
    ----------
    fits : pandas.DataFrame
        Fit table with ``species``, ``depth_mm``, ``waterbed_L_mm`` and the
        ``*_rmse_mm`` columns.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`SUMMARY_COLUMNS`, one row per species and depth: species
        in the order of :data:`lineload.paper.SPECIES` (others after, sorted), depths
        ascending.  The SD uses ``n - 1`` and is NaN for a single trial.
    """
    rows = []
    keys = sorted(
        {(str(s), float(d)) for s, d in zip(fits["species"], fits["depth_mm"], strict=True)},
        key=lambda key: (_species_rank(key[0]), key[1]),
    )
    for species, depth_mm in keys:
        group = fits[(fits["species"].astype(str) == species) & (fits["depth_mm"] == depth_mm)]
        L_mm = group["waterbed_L_mm"].to_numpy(dtype=float)
        bq_rmse_mm = group["boussinesq_rmse_mm"].to_numpy(dtype=float)
        wb_rmse_mm = group["waterbed_rmse_mm"].to_numpy(dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = bq_rmse_mm / wb_rmse_mm
        finite_ratio = ratio[np.isfinite(ratio)]
        rows.append(
            {
                "species": species,
                "depth_mm": depth_mm,
                "n_trials": len(group),
                "waterbed_n_at_bound": sum(at_bound(t, "waterbed") for _, t in group.iterrows()),
                "waterbed_L_mean_mm": _mean(L_mm),
                "waterbed_L_sd_mm": _sd(L_mm),
                "waterbed_rmse_mean_mm": _mean(group["waterbed_rmse_mm"]),
                "arc_rmse_mean_mm": _mean(group["arc_rmse_mm"]),
                "boussinesq_rmse_mean_mm": _mean(group["boussinesq_rmse_mm"]),
                "rmse_ratio_boussinesq_to_waterbed_mean": _mean(finite_ratio),
                "rmse_ratio_boussinesq_to_waterbed_min": (
                    float(finite_ratio.min()) if finite_ratio.size else np.nan
                ),
            }
        )
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)


def _mean(values):
    """Mean of the finite values; NaN if there are none."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return float(values.mean()) if values.size else np.nan


def _sd(values):
    """Sample standard deviation (n - 1) of the finite values; NaN below two."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return float(values.std(ddof=1)) if values.size > 1 else np.nan


def _summary_rows(summary):
    rows = []
    for _, row in summary.iterrows():
        rows.append(
            [
                str(row["species"]),
                format_fixed(row["depth_mm"], DEPTH_DECIMALS),
                _trials_cell(row),
                format_fixed(row["waterbed_L_mean_mm"], LENGTH_DECIMALS),
                format_fixed(row["waterbed_L_sd_mm"], LENGTH_DECIMALS),
                *(format_fixed(row[f"{m}_rmse_mean_mm"], RMSE_DECIMALS) for m, _ in MODELS),
                format_fixed(row["rmse_ratio_boussinesq_to_waterbed_mean"], RATIO_DECIMALS),
                format_fixed(row["rmse_ratio_boussinesq_to_waterbed_min"], RATIO_DECIMALS),
            ]
        )
    return rows


def _trials_cell(row):
    """Trials of a summary row, with how many of their L are on a bound (if any)."""
    text = str(int(row["n_trials"]))
    bounded = row.get("waterbed_n_at_bound", 0)
    bounded = int(bounded) if bounded == bounded else 0
    return f"{text} ({bounded}{AT_BOUND_MARK})" if bounded else text


def _summary_caption(summary):
    caption = (
        "Summary per species and indentation depth: number of trials (subjects), mean and "
        "standard deviation (n - 1) of the waterbed half-width L, mean RMSE of each model, "
        "and the ratio of Boussinesq to waterbed RMSE, formed trial by trial and then "
        "averaged (mean) or minimised over trials (min). A ratio above 1 means the waterbed "
        "fitted better."
    )
    if "waterbed_n_at_bound" in summary and summary["waterbed_n_at_bound"].fillna(0).sum():
        caption += (
            f" In brackets ({AT_BOUND_MARK}), how many of the trials' L ended on a bound of "
            "its search: a bound, not a measurement, which the mean and SD include."
        )
    return caption


def summary_markdown(summary, notice=""):
    """The species summary (output of :func:`summarise_fits`) as Markdown.

    Parameters
    ----------
    summary : pandas.DataFrame
        Columns :data:`SUMMARY_COLUMNS`.
    notice : str, optional
        Data notice; when non-empty it is added as a footer line.

    Returns
    -------
    str
    """
    headers = [
        "Species",
        "Depth (mm)",
        "Trials",
        "Mean L (mm)",
        "SD L (mm)",
        *(f"Mean RMSE {label} (mm)" for _, label in MODELS),
        "RMSE ratio B/W, mean",
        "RMSE ratio B/W, min",
    ]
    text = "# Summary per species and depth\n\n" + _summary_caption(summary) + "\n\n"
    text += markdown_table(headers, _summary_rows(summary), "lrrrrrrrrr")
    return text + notice_footer(notice)


def summary_latex(summary, notice=""):
    """The species summary as a booktabs LaTeX ``table``.

    Parameters
    ----------
    summary : pandas.DataFrame
        Columns :data:`SUMMARY_COLUMNS`.
    notice : str, optional
        Data notice; when non-empty it becomes a note under the table.

    Returns
    -------
    str
    """
    head = [
        r" & & & \multicolumn{2}{c}{Waterbed $L$ (mm)} & \multicolumn{3}{c}{Mean RMSE (mm)}"
        r" & \multicolumn{2}{c}{RMSE ratio B/W} \\",
        r"\cmidrule(lr){4-5} \cmidrule(lr){6-8} \cmidrule(lr){9-10}",
        r"Species & Depth (mm) & Trials & mean & SD & "
        + " & ".join(escape_latex(label) for _, label in MODELS)
        + r" & mean & min \\",
    ]
    caption = escape_latex(_summary_caption(summary))
    return latex_table(
        head, _summary_rows(summary), "lrrrrrrrrr", caption, "tab:fit-summary", notice
    )


def sensitivity_markdown(sensitivity, checks, notice=""):
    """Reviewer's summary of the sensitivity refits and the per-trial checks.

    Parameters
    ----------
    sensitivity : pandas.DataFrame
        Rows of :data:`lineload.fitting.sensitivity.SENSITIVITY_COLUMNS` for every trial.
    checks : pandas.DataFrame
        Rows of :data:`lineload.fitting.sensitivity.CHECK_COLUMNS` for every trial.
    notice : str, optional
        Footer line about the data (empty for none).

    Returns
    -------
    str
        Markdown: median L per species, depth, model and window; how often each
        model has the lowest AICc in each window; the per-trial U shift and reach.
    """
    refit_models = tuple(MODEL_NAMES)  # every model, in the order of the refits
    windows = list(dict.fromkeys(sensitivity["window"]))
    parts = [
        "# Sensitivity of the fits to the analysis choices\n",
        "Median fitted half-width L (mm) over the subjects of each species, by depth, "
        "model and fit window.\n",
    ]
    with_L = [m for m in refit_models if any(p.name == "L_mm" for p in family(m).parameters)]
    headers = ["species", "depth (mm)"] + [
        f"{MODEL_NAMES[m].refit}, {w}" for m in with_L for w in windows
    ]
    rows = []
    groups = sensitivity.groupby(["species", "depth_mm"], sort=False)
    keys = sorted(groups.groups, key=lambda k: (_species_rank(k[0]), k[1]))
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
        rows.append([window] + [str(int(counts.get(m, 0))) for m in refit_models])
    headers = ["window"] + [MODEL_NAMES[m].refit for m in refit_models]
    parts.append(markdown_table(headers, rows, "l" + "r" * len(refit_models)))
    parts.append(
        "\nPer trial: L under the paper's procedure and in measured coordinates (shifted "
        "parabola, exact arc), and the largest vertical gap between each of those fitted "
        "curves and the paper's over the fitted range; the largest horizontal shift of the "
        "small-slope solution, 8W₀²/(9L) at X = L/3, as a fraction of that X; and the "
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
