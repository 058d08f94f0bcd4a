"""The report's table pages: values with the digits their uncertainty supports."""

import math
from html.parser import HTMLParser

import pandas as pd
import pytest

from conftest import REPO
from lineload.io import read_results_csv
from lineload.publishing.reportpages import error_columns, table_page, with_supported_digits

COLUMNS = [
    "subject",
    "pretension_N_per_mm",
    "pretension_se_N_per_mm",
    "prestrain",
    "prestrain_se",
    "arc_L_mm",
    "arc_L_ci_low_mm",
    "arc_L_ci_high_mm",
    "chi2",
]


def test_each_value_finds_its_standard_error_or_its_interval():
    assert error_columns(COLUMNS) == {
        "pretension_N_per_mm": ("pretension_se_N_per_mm",),
        "prestrain": ("prestrain_se",),
        "arc_L_mm": ("arc_L_ci_low_mm", "arc_L_ci_high_mm"),
    }


def test_a_table_of_named_values_finds_their_standard_errors():
    columns = ["parameter", "value", "se", "source"]
    assert error_columns(columns) == {"value": ("se",)}
    assert error_columns(["parameter", "value"]) == {}
    rows = [["reading_sd_mm", 0.006400943831, 0.003036846578, "measured"]]
    rows.append(["depth_sd_mm", 0.01, math.nan, "prior"])
    shown = list(with_supported_digits(columns, rows))
    assert shown[0][1:3] == ["0.0064", "0.0030"]
    assert shown[1][1] == 0.01  # a prior: no error, shown as set


def test_a_unitless_value_finds_the_interval_that_names_it_by_its_last_word():
    columns = ["elastic_layered_modulus_ratio", "elastic_layered_ratio_ci_low"]
    assert error_columns(columns) == {}  # one end is no interval
    columns.append("elastic_layered_ratio_ci_high")
    assert error_columns(columns) == {
        "elastic_layered_modulus_ratio": (
            "elastic_layered_ratio_ci_low",
            "elastic_layered_ratio_ci_high",
        )
    }
    # the ratio to two significant digits of its interval, as the article prints it
    (shown,) = with_supported_digits(columns, [[236.3, 130.2, 396.4]])
    assert shown == ["236", "130", "396"]


def test_a_data_files_page_offers_the_file_and_a_record_is_shown_as_it_is():
    import base64
    import re

    from lineload.publishing.reportpages import download_link, record_page

    csv = b"subject,depth_mm\nM1,0.5\n"
    page = table_page(
        "t",
        ["subject", "depth_mm"],
        [["M1", 0.5]],
        download=download_link("fits.csv", csv, "text/csv"),
    )
    link = re.search(r'<a download="fits.csv"\s+href="data:text/csv;base64,([^"]+)"', page)
    assert link and base64.b64decode(link.group(1)) == csv
    assert "Download fits.csv</a>" in page and "<table>" in page
    assert "Download" not in table_page("t", ["subject"], [["M1"]])  # only where given
    record = '{\n  "git": {"commit": "<abc>"}\n}'
    page = record_page("r", record, download=download_link("p.json", record.encode(), "x"))
    assert "<pre>{\n  &#34;git&#34;: {&#34;commit&#34;: &#34;&lt;abc&gt;&#34;}\n}</pre>" in page


def test_values_keep_two_significant_digits_of_their_uncertainty():
    row = ["M1", 0.0840843, 0.00165539, 0.43899, 0.10645, 12.3456, 11.9, 12.8, 2.791041644]
    (shown,) = with_supported_digits(COLUMNS, [row])
    # SE 0.0017 -> 4 decimals; SE 0.11 -> 2; half-width 0.45 -> 2
    assert shown[1:8] == ["0.0841", "0.0017", "0.44", "0.11", "12.35", "11.90", "12.80"]
    assert shown[8] == row[8]  # no uncertainty: left as it was (6 significant digits shown)
    # an error that is not there (NaN, an open interval) leaves the value as it was
    open_row = [*row[:5], 12.3456, 11.9, math.inf, 2.0]
    (shown,) = with_supported_digits(COLUMNS, [open_row])
    assert shown[5] == 12.3456
    page = table_page("t", COLUMNS, [row])
    assert '<td class="num">0.0841</td>' in page and "0.0840843" not in page


def test_headers_carry_words_and_units_and_values_the_articles_digits():
    from lineload.publishing.reportpages import column_label

    assert column_label("waterbed_L_ci_low_mm") == "waterbed L 95 % CI low (mm)"
    assert column_label("boussinesq_x0_mm") == "Boussinesq x₀ (mm)"
    assert column_label("pretension_se_N_per_mm") == "pretension SE (N/mm)"
    assert column_label("waterbed_aicc") == "waterbed AICc" and column_label("chi2") == "chi2"
    # a sum of squares in mm², as the bending and elastic tables have one
    assert column_label("bending_sse_mm2") == "bending SSE (mm²)"
    # L to 0.01 mm as the article prints it, even when its interval supports one decimal
    columns = ["waterbed_L_mm", "waterbed_L_ci_low_mm", "waterbed_L_ci_high_mm"]
    columns += ["waterbed_rmse_mm", "waterbed_aicc", "n_points"]
    (shown,) = with_supported_digits(columns, [[14.7213, 13.9, 15.6, 0.0123456, -157.72209, 20]])
    assert shown == ["14.72", "13.90", "15.60", "0.0123", "-157.7", 20]
    # a depth or a window, set with few digits, is shown as it was set
    (depth,) = with_supported_digits(["depth_mm"], [[0.5]])
    assert depth == ["0.5"]
    page = table_page("t", columns, [[14.7213, 13.9, 15.6, 0.0123456, -157.72209, 20]])
    assert '<th title="waterbed_rmse_mm">waterbed RMSE (mm)</th>' in page


class _BodyCells(HTMLParser):
    """The text of each cell of a page's table body, row by row."""

    def __init__(self):
        super().__init__()
        self.rows, self._in_body, self._cell = [], False, None

    def handle_starttag(self, tag, attrs):
        if tag == "tbody":
            self._in_body = True
        elif self._in_body and tag == "tr":
            self.rows.append([])
        elif self._in_body and tag == "td":
            self._cell = ""

    def handle_endtag(self, tag):
        if tag == "tbody":
            self._in_body = False
        elif tag == "td" and self._cell is not None:
            self.rows[-1].append(self._cell)
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


def page_rows(page):
    """The rows of the table on an HTML page, each a list of its cells' text."""
    parser = _BodyCells()
    parser.feed(page)
    return parser.rows


def rows_not_shown(shown, frame):
    """Where the rows ``shown`` on a page (lists of cell text) differ from the table's:
    a list of (row, column, in the table, on the page), empty when every row is there.

    Text must match exactly; a number as the CSV writes it (six significant digits), or
    rounded to the decimals shown (at least one: a whole number shown for a fraction is
    a difference); an empty cell stands for a missing value.
    """
    differences = []
    if len(shown) != len(frame):
        differences.append(("rows", "", len(frame), len(shown)))
    for i, (row, cells) in enumerate(zip(frame.itertuples(index=False), shown, strict=False)):
        for column, value, text in zip(frame.columns, row, cells, strict=True):
            if isinstance(value, (str, bool)):
                same = text == str(value)
            elif math.isnan(value):
                same = text == ""
            else:
                decimals = len(text.partition(".")[2])
                same = text == f"{value:.6g}" or (decimals > 0 and text == f"{value:.{decimals}f}")
            if not same:
                differences.append((i, column, value, text))
    return differences


def test_a_data_files_rows_are_on_its_page():
    """Every row of a data file, every cell, is on its page (numbers to the digits shown);
    a page missing a row, or with one reading changed, is caught."""
    path = REPO / "data" / "raw" / "profiles" / "M1.csv"
    frame = read_results_csv(path)
    page = table_page("Readings: M1", list(frame.columns), frame.itertuples(index=False))
    shown = page_rows(page)
    assert len(shown) == len(frame) > 50
    assert rows_not_shown(shown, frame) == []
    # planted: the page loses its tenth row, or one reading is shown 0.1 mm off
    assert rows_not_shown(shown[:9] + shown[10:], frame)
    for k in (3, 20):
        changed = [list(row) for row in shown]
        changed[k][3] = f"{float(changed[k][3]) + 0.1:g}"
        assert [d[:2] for d in rows_not_shown(changed, frame)] == [(k, frame.columns[3])]
    # and a value rounded past the digits it is shown with
    assert rows_not_shown(
        [["M1", "0.5", "left", "1", "10"]],
        pd.DataFrame(
            [["M1", 0.5, "left", 1.0, 10.4]], columns=["subject", "depth", "side", "x", "z"]
        ),
    )


def test_a_paragraph_in_a_cell_is_set_wide_and_a_word_is_not():
    page = table_page("t", ["claim", "rule"], [["C1", "x " * 300], ["C2", "a rule"]])
    assert page.count('<td class="paragraph">') == 1 and "<td>a rule</td>" in page


@pytest.mark.parametrize("name", ["converted", "averaged"])
def test_a_batch_of_readings_is_captioned_by_its_subjects_not_its_file_name(name):
    """A batch's file name (``H1+2``) says which subjects it holds only to one who knows
    the naming: the caption says it in words, and a lone subject is named alone."""
    from jinja2 import Template

    source = (REPO / "workflow" / "report" / f"{name}.rst").read_text(encoding="utf-8")

    def rendered(batch):
        text = Template(source).render(snakemake={"config": {}, "wildcards": {"batch": batch}})
        return " ".join(text.split())

    assert "the batch H1+2 (H1 and the next 2 subjects of the subject sheet)" in rendered("H1+2")
    assert "(M1 and the next 1 subject of the subject sheet)" in rendered("M1+1")
    assert "subject M1 " in rendered("M1") and "batch" not in rendered("M1").split(".")[0]
    assert "subject(s)" not in rendered("H1+2")


def test_the_claims_caption_counts_as_evidence_only_what_the_article_counts():
    """The article counts only the paper's claims about fingers; the report's caption
    once called every 'holds' evidence, C12's (later work) and C6's (a property of the
    method) among them.  Each kind of claim is named in it."""
    from lineload.claims.verdicts import KINDS, PAPER_CLAIM

    text = " ".join((REPO / "workflow" / "report" / "claims.rst").read_text().split())
    assert f"only where the column 'kind' says '{PAPER_CLAIM}'" in text
    assert [kind for kind in KINDS if f"'{kind}'" not in text] == []


def test_a_figure_with_a_panel_per_species_is_described_for_any_species():
    """Figure 2 and the bending and elastic examples draw the first subject of each species
    in the data: the photograph example has monkeys only, so neither the report's title
    nor its caption may promise a human."""
    from lineload.figures.registry import FIGURES

    for figure in FIGURES:
        if figure.name not in ("figure2", "supplement_bending", "supplement_elastic"):
            continue
        caption = (REPO / "workflow" / "report" / f"{figure.name}.rst").read_text()
        # the paper's own choice may be named as such
        caption = " ".join(caption.split()).replace("(the paper's: a monkey and a human)", "")
        for text in (figure.title, caption):
            assert "human" not in text, (figure.name, text)
