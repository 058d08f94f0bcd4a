"""Pages of the HTML report: tables shown as tables and figures with their captions.

Snakemake's report shows an HTML, PNG or PDF result on the page but offers a CSV
only as a download, and keeps each caption behind an icon.  The workflow
therefore gives the report one small, self-contained HTML page per table and per
figure, with the caption written out beside it.  Pure functions: text in, text
out; the figure's PNG is embedded as a data URI so the page needs no other file.

The pages are jinja2 templates, autoescaped (text is escaped, the caption's HTML
comes in marked safe).  They live here, not in files of their own, so the module
works wherever the package is installed (the package carries no data files but
its schemas).
"""

from __future__ import annotations

import base64
import math

import jinja2
from markupsafe import Markup

__all__ = [
    "caption",
    "column_label",
    "download_link",
    "error_columns",
    "figure_page",
    "page",
    "record_page",
    "table_page",
    "versions_page",
    "with_supported_digits",
]

_STYLE = """
body { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; font-size: 14px;
       color: #1f2937; margin: 16px; max-width: 1200px; }
h1 { font-size: 18px; margin: 0 0 8px 0; }
.caption { background: #f3f4f6; border-left: 4px solid #0072b2; padding: 8px 12px;
           margin: 8px 0 14px 0; line-height: 1.45; }
.notice { background: #fdf1dc; border-left: 4px solid #d55e00; padding: 6px 12px;
          margin: 8px 0 14px 0; }
table { border-collapse: collapse; font-size: 13px; display: block; max-width: 100%;
        overflow-x: auto; }
th, td { border-bottom: 1px solid #e5e7eb; padding: 4px 8px; text-align: left;
         vertical-align: top; }
th { background: #f9fafb; position: sticky; top: 0; min-width: 4em; max-width: 9em;
     white-space: normal; font-weight: 600; }
td.paragraph { min-width: 24em; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
th:first-child, td:first-child { position: sticky; left: 0; background: #ffffff; }
th:first-child { z-index: 1; background: #f9fafb; }
img { width: 100%; max-width: 1100px; height: auto; border: 1px solid #e5e7eb; }
.download { margin: 0 0 12px 0; }
pre { font-size: 12px; background: #f9fafb; padding: 8px 12px; overflow-x: auto; }
"""


#: The page: a title, the caption, the data notice, then the content (written by the
#: templates that extend it).  Autoescaped: text is escaped, markup comes in as Markup.
_PAGE = """\
<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>{{ title }}</title><style>{{ style }}</style></head><body>
<h1>{{ title }}</h1>
{% if caption_html %}<div class="caption">{{ caption_html }}</div>
{% endif %}{% if notice %}<div class="notice">{{ notice }}</div>
{% endif %}{% if download %}<p class="download"><a download="{{ download.name }}"
 href="data:{{ download.mime }};base64,{{ download.base64 }}">Download {{ download.name }}</a>
 ({{ download.size }}: the file as the workflow wrote it, which this page shows)</p>
{% endif %}{% block content %}{{ body }}{% endblock %}
</body></html>
"""

#: A table: headers with the CSV's own names as tooltips, numbers right-aligned.
_TABLE = """\
{% extends "page" %}{% block content %}<table><thead><tr>
{%- for column in columns %}<th title="{{ column }}">{{ column | label }}</th>{% endfor -%}
</tr></thead><tbody>
{%- for row in rows %}<tr>{% for value in row %}{{ value | cell }}{% endfor %}</tr>{% endfor -%}
</tbody></table>{% endblock %}"""

#: A record (JSON) as it is, indented.
_RECORD = """\
{% extends "page" %}{% block content %}<pre>{{ record }}</pre>{% endblock %}"""

#: A figure, embedded as a data URI.
_FIGURE = """\
{% extends "page" %}{% block content -%}
<img alt="{{ title }}" src="data:image/png;base64,{{ png_base64 }}">
{%- endblock %}"""


def page(title, body, caption_html="", notice=""):
    """One self-contained HTML page: a title, the caption, the notice, then the body.

    Parameters
    ----------
    title : str
        Plain text (escaped here).
    body : str
        HTML of the content.
    caption_html : str, optional
        The caption, already HTML.
    notice : str, optional
        The data notice, plain text; shown above the content when non-empty.

    Returns
    -------
    str
    """
    return _render("page", title, caption_html, notice, body=Markup(body))


class _Fixed(str):
    """A number already written with the digits its uncertainty supports."""


#: A column's unit, by the suffix of its name, as a header writes it.
_UNITS = {
    "_N_per_mm": "N/mm",
    "_um2_per_mm": "µm²/mm",
    "_um2": "µm²",
    "_um": "µm",
    "_mm2": "mm²",
    "_mm": "mm",
    "_N": "N",
    "_deg": "°",
}

#: Words of the column names as the article writes them.
_WORDS = {
    "rmse": "RMSE",
    "sse": "SSE",
    "aicc": "AICc",
    "boussinesq": "Boussinesq",
    "x0": "x₀",
    "W0": "W₀",
    "ci": "95 % CI",
    "n": "number of",
    "se": "SE",
    "sd": "SD",
    "abs": "absolute",
    "max": "largest",
}


def column_label(column):
    """A header for a table column: its words, then its unit in brackets.

    ``waterbed_L_ci_low_mm`` -> ``waterbed L 95 % CI low (mm)``; ``waterbed_aicc`` ->
    ``waterbed AICc``; the CSV's own name is kept as the header's tooltip.
    """
    name, unit = str(column), ""
    for suffix, shown in _UNITS.items():
        if name.endswith(suffix) and len(name) > len(suffix):
            name, unit = name[: -len(suffix)], f" ({shown})"
            break
    words = [_WORDS.get(word, word) for word in name.split("_") if word]
    return " ".join(words) + unit


#: Decimals of a value without an uncertainty, by its column's unit or kind (the first
#: suffix that matches), as the article prints them: mm to the micrometre and a tenth
#: (RMSE 0.0172), AICc to 0.1; the smallest and largest L over the fit windows as L
#: itself (0.01 mm), a prior's (or the wedge's) share of an interval to 0.001.
_PLAIN_DECIMALS = (
    ("_aicc", 1),
    ("_window_min_mm", 2),
    ("_window_max_mm", 2),
    ("_prior_share", 3),
    ("_wedge_share", 3),
    ("_mm", 4),
    ("_mm2", 4),
    ("_um", 1),
    ("_N", 3),
)

#: The fewest decimals a value with an uncertainty is shown with, by unit: the article
#: prints L to 0.01 mm (14.72) whatever its interval.
_MIN_DECIMALS = (("_mm", 2),)


def _decimals_by_suffix(column, table):
    for suffix, decimals in table:
        if str(column).endswith(suffix):
            return decimals
    return None


def error_columns(columns):
    """The uncertainty of each value column that has one.

    ``x`` with a column ``x_se`` (``pretension_N_per_mm`` with
    ``pretension_se_N_per_mm``) has a standard error; ``..._L_mm`` with
    ``..._L_ci_low_mm`` and ``..._L_ci_high_mm`` has an interval; a table of named
    values (the noise table) has ``value`` with its ``se``.

    Returns
    -------
    dict
        Value column -> the columns of its uncertainty (one: a standard error;
        two: an interval's ends).
    """
    columns = list(columns)
    found = {"value": ("se",)} if {"value", "se"} <= set(columns) else {}
    for column in columns:
        head, _, rest = column.partition("_")
        se = f"{head}_se" + (f"_{rest}" if rest else "")
        if se in columns:
            found[column] = (se,)
        if column.endswith("_mm"):
            ends = (column[: -len("_mm")] + "_ci_low_mm", column[: -len("_mm")] + "_ci_high_mm")
            if all(end in columns for end in ends):
                found[column] = ends
        # a value without a unit whose interval names it by its last word
        # (elastic_layered_modulus_ratio: elastic_layered_ratio_ci_low and _ci_high)
        words = column.split("_")
        if len(words) >= 3 and column not in found:
            stem = "_".join(words[:-2] + words[-1:])
            ends = (f"{stem}_ci_low", f"{stem}_ci_high")
            if all(end in columns for end in ends):
                found[column] = ends
    return found


def _supported_decimals(value, bounds):
    """Decimals that show an uncertainty to two significant digits (None: unknown).

    ``bounds`` holds a standard error, or an interval's two ends around ``value``.
    """
    try:
        if len(bounds) == 1:
            error = abs(float(bounds[0]))
        else:
            error = (float(bounds[1]) - float(bounds[0])) / 2
    except (TypeError, ValueError):
        return None
    if not (math.isfinite(error) and error > 0 and math.isfinite(float(value))):
        return None
    return max(0, 1 - math.floor(math.log10(error)))


def with_supported_digits(columns, rows):
    """Rows with each value that has an uncertainty, and the uncertainty, rounded to the
    digits it supports (two significant digits of the error, and at least the article's
    digits for its unit); other numbers with the article's decimals for their unit
    (:data:`_PLAIN_DECIMALS`), the rest as they were."""
    columns = list(columns)
    errors = error_columns(columns)
    index = {c: i for i, c in enumerate(columns)}
    # the rest by their unit, as the article prints them
    bound = {b for ends in errors.values() for b in ends}
    plain = {
        c: d
        for c in columns
        if c not in errors
        and c not in bound
        and (d := _decimals_by_suffix(c, _PLAIN_DECIMALS)) is not None
    }
    for row in rows:
        cells = list(row)
        for column, decimals in plain.items():
            number = cells[index[column]]
            if isinstance(number, float) and math.isfinite(number):
                # a value set with few digits (a depth, a window) is shown as it was set
                short = f"{number:g}"
                exact = float(short) == number and len(short.lstrip("-")) <= 5
                cells[index[column]] = _Fixed(short if exact else f"{number:.{decimals}f}")
        for column, bounds in errors.items():
            value = cells[index[column]]
            decimals = _supported_decimals(value, [cells[index[b]] for b in bounds])
            if decimals is None:
                continue
            decimals = max(decimals, _decimals_by_suffix(column, _MIN_DECIMALS) or 0)
            for name in (column, *bounds):
                number = cells[index[name]]
                if isinstance(number, (int, float)) and math.isfinite(float(number)):
                    cells[index[name]] = _Fixed(f"{float(number):.{decimals}f}")
        yield cells


#: A text cell longer than this (characters, a paragraph) is set at least 24 em wide:
#: in the claims table each rule, reason and value, a paragraph, otherwise narrowed to a
#: few words a line and a row ran to three screens.
_PARAGRAPH = 400


def _cell(value):
    """A table cell: numbers right-aligned with up to 6 significant digits, text escaped."""
    if isinstance(value, _Fixed):
        return Markup('<td class="num">{}</td>').format(value)
    if isinstance(value, bool):
        return Markup("<td>{}</td>").format(value)
    if isinstance(value, (int, float)):
        if isinstance(value, float) and math.isnan(value):
            return Markup('<td class="num"></td>')
        return Markup('<td class="num">{}</td>').format(f"{value:.6g}")
    text = str(value)
    if len(text) > _PARAGRAPH:
        return Markup('<td class="paragraph">{}</td>').format(text)
    return Markup("<td>{}</td>").format(text)


_TEMPLATES = jinja2.Environment(
    loader=jinja2.DictLoader(
        {"page": _PAGE, "table": _TABLE, "figure": _FIGURE, "record": _RECORD}
    ),
    autoescape=True,
    keep_trailing_newline=True,
    undefined=jinja2.StrictUndefined,
)
_TEMPLATES.filters["label"] = column_label
_TEMPLATES.filters["cell"] = _cell


def caption(path, config, wildcards=None):
    """A caption file (reStructuredText with Jinja, as Snakemake reads a report caption)
    as HTML.

    Parameters
    ----------
    path : str or os.PathLike
        The caption file (``workflow/report/*.rst``).
    config : dict
        The configuration, as ``snakemake.config`` inside the caption.
    wildcards : dict, optional
        Those of the job whose output it describes.

    Returns
    -------
    str
        The caption's body as HTML.
    """
    from pathlib import Path

    from docutils.core import publish_parts

    text = jinja2.Template(Path(path).read_text(encoding="utf-8")).render(
        snakemake={"config": config, "wildcards": wildcards or {}}
    )
    return publish_parts(text, writer_name="html5")["body"]


def download_link(name, data, mime):
    """What a page needs to offer its file for download: the file embedded as a data URI.

    Parameters
    ----------
    name : str
        The file's name, as the download saves it.
    data : bytes
        The file's bytes.
    mime : str
        Its type (``text/csv``, ``application/json``).

    Returns
    -------
    dict
        ``name``, ``mime``, ``base64`` and ``size`` (``"3.6 kB"``).
    """
    size = f"{len(data) / 1000:.1f} kB" if len(data) >= 1000 else f"{len(data)} bytes"
    return {
        "name": name,
        "mime": mime,
        "base64": base64.b64encode(data).decode("ascii"),
        "size": size,
    }


def _render(template, title, caption_html, notice, download=None, **values):
    """A page from one of the templates: the caption is HTML, everything else text."""
    return _TEMPLATES.get_template(template).render(
        title=title,
        style=Markup(_STYLE),
        caption_html=Markup(caption_html),
        notice=notice,
        download=download,
        **values,
    )


def table_page(title, columns, rows, caption_html="", notice="", download=None):
    """A table as an HTML page.

    Parameters
    ----------
    title : str
    columns : list of str
        Column names, shown as labels with their units (:func:`column_label`).
    rows : iterable of sequence
        Cell values (numbers or text), one sequence per row.  A value with an
        uncertainty in the table (:func:`error_columns`) is shown with the digits
        that uncertainty supports; the CSV keeps every digit.
    caption_html, notice : str, optional
        As for :func:`page`.
    download : dict, optional
        The table's file (:func:`download_link`), offered above it: Snakemake's report
        shows an HTML page but only downloads a CSV, so the page is the report's item
        and the file its download.

    Returns
    -------
    str
    """
    columns = [str(c) for c in columns]
    rows = with_supported_digits(columns, rows)
    return _render("table", title, caption_html, notice, download, columns=columns, rows=rows)


def record_page(title, record_text, caption_html="", notice="", download=None):
    """A record (a JSON file's text) shown as it is, with the file to download.

    Parameters
    ----------
    title, record_text : str
        Plain text (escaped here).
    caption_html, notice : str, optional
        As for :func:`page`.
    download : dict, optional
        As for :func:`table_page`.

    Returns
    -------
    str
    """
    return _render("record", title, caption_html, notice, download, record=record_text)


def figure_page(title, png_bytes, caption_html="", notice=""):
    """A figure (PNG) with its caption, as an HTML page.

    Parameters
    ----------
    title : str
    png_bytes : bytes
        The figure, embedded as a data URI.
    caption_html, notice : str, optional
        As for :func:`page`.

    Returns
    -------
    str
    """
    data = base64.b64encode(png_bytes).decode("ascii")
    return _render("figure", title, caption_html, notice, png_base64=data)


def versions_page(title, rows, caption_html=""):
    """A two-column page of names and values (software versions, source commit).

    Parameters
    ----------
    title : str
    rows : iterable of (str, str)
    caption_html : str, optional

    Returns
    -------
    str
    """
    return table_page(title, ["name", "value"], rows, caption_html)
