"""Fit tables and species summary: one row per trial, booktabs LaTeX, statistics by numpy."""

import re

import numpy as np
import pandas as pd
import pytest

from lineload.fitting.batch import FIT_COLUMNS
from lineload.publishing import tables
from lineload.publishing.tables import (
    SUMMARY_COLUMNS,
    escape_latex,
    escape_markdown,
    fits_latex,
    fits_markdown,
    format_fixed,
    markdown_table,
    notice_footer,
    sensitivity_markdown,
    span_text,
    summarise_fits,
    summary_latex,
    summary_markdown,
)

TRIALS = [
    ("Mk_1", "monkey", 0.5),
    ("Mk_1", "monkey", 1.0),
    ("Mk_1", "monkey", 2.0),
    ("Hu_1", "human", 1.0),
    ("Hu_1", "human", 2.0),
    ("Mk_2", "monkey", 1.0),
    ("Mk_2", "monkey", 2.0),
    ("Hu_2", "human", 1.0),
]


@pytest.fixture
def fits():
    """A fit table made here: random but plausible values, not the workflow's output."""
    rng = np.random.default_rng(42)
    rows = []
    for subject, species, depth_mm in TRIALS:
        wb = rng.uniform(0.005, 0.1)
        rows.append(
            {
                "subject": subject,
                "species": species,
                "depth_mm": depth_mm,
                "fit_window_mm": 3.0,
                "n_points": int(rng.integers(15, 25)),
                "max_distance_mm": 3.0,
                "waterbed_L_mm": rng.uniform(9.0, 16.0),
                "waterbed_rmse_mm": wb,
                "waterbed_max_abs_residual_mm": 2 * wb,
                "waterbed_aicc": -100.0,
                "arc_L_mm": rng.uniform(9.0, 16.0),
                "arc_rmse_mm": wb * rng.uniform(0.8, 1.0),
                "arc_max_abs_residual_mm": 2 * wb,
                "arc_aicc": -101.0,
                "boussinesq_A_mm": rng.uniform(0.1, 0.4),
                "boussinesq_x0_mm": rng.uniform(8.0, 40.0),
                "boussinesq_rmse_mm": wb * rng.uniform(1.1, 9.0),
                "boussinesq_max_abs_residual_mm": 4 * wb,
                "boussinesq_aicc": -80.0,
            }
        )
    return pd.DataFrame(rows, columns=FIT_COLUMNS)


def markdown_body(text):
    """Cells of the body rows of the (first) pipe table in a Markdown text."""
    lines = [ln for ln in text.splitlines() if ln.startswith("|")]
    return [[c.strip() for c in ln.strip("|").split(" | ")] for ln in lines[2:]]


def latex_body(text):
    """Body lines of a booktabs table: between \\midrule and \\bottomrule."""
    lines = text.splitlines()
    return lines[lines.index(r"\midrule") + 1 : lines.index(r"\bottomrule")]


def test_format_fixed_rounds_and_marks_missing():
    assert format_fixed(0.04964, 4) == "0.0496"
    assert format_fixed(12.345678, 2) == "12.35"
    assert format_fixed(-0.00001, 3) == "0.000"
    assert format_fixed(float("nan"), 2) == "–"
    assert format_fixed(None, 2, missing="n/a") == "n/a"
    assert format_fixed(float("inf"), 2, missing="x") == "x"


def test_span_text_gives_the_finite_range_once():
    assert span_text([2.0, np.nan, 1.25, np.inf]) == "1.25 to 2.00 mm"
    assert span_text([3.0, 3.004], 2) == "3.00 mm"  # ends that print the same
    assert span_text([0.5, 1.5], 1, "") == "0.5 to 1.5" and span_text([np.nan]) == "none"


def test_notice_footer_is_one_line_or_nothing():
    footer = notice_footer("Synthetic data.\nSee README.\n")
    assert footer == "\nNote: Synthetic data. See README.\n"
    assert notice_footer("") == "" and notice_footer(None) == ""


def test_escape_latex_covers_the_special_characters():
    assert escape_latex("a_b & 5% #1 $x$ {y}") == r"a\_b \& 5\% \#1 \$x\$ \{y\}"
    assert escape_latex("~^\\") == r"\textasciitilde{}\textasciicircum{}\textbackslash{}"


def test_markdown_table_escapes_pipes_and_checks_shape():
    text = markdown_table(["a", "b"], [["x|y", "1"]], "lr")
    assert text.splitlines() == ["| a | b |", "|---|--:|", "| x\\|y | 1 |"]
    with pytest.raises(ValueError):
        markdown_table(["a", "b"], [["only one"]], "lr")


def test_fits_markdown_has_one_row_per_subject_and_depth(fits):
    body = markdown_body(fits_markdown(fits))
    assert len(body) == len(fits)
    assert [(row[0], float(row[2])) for row in body] == [(s, d) for s, _, d in TRIALS]
    for row, (_, trial) in zip(body, fits.iterrows(), strict=True):
        assert float(row[4]) == pytest.approx(trial["waterbed_L_mm"], abs=0.005)
        rmse = [float(cell) for cell in row[5:8]]
        expected = trial[["waterbed_rmse_mm", "arc_rmse_mm", "boussinesq_rmse_mm"]]
        assert rmse == pytest.approx(list(expected), abs=0.00005)


def test_fits_latex_is_booktabs_with_escaped_names_and_one_row_per_trial(fits):
    text = fits_latex(fits)
    assert text.startswith(r"\begin{table}") and text.rstrip().endswith(r"\end{table}")
    assert r"\documentclass" not in text
    positions = [text.index(rule) for rule in (r"\toprule", r"\midrule", r"\bottomrule")]
    assert positions == sorted(positions)
    body = latex_body(text)
    assert len(body) == len(fits)
    assert all(line.endswith(r"\\") and line.count(" & ") == 7 for line in body)
    assert body[0].startswith(r"Mk\_1 & monkey & 0.50 &")
    assert not re.search(r"(?<!\\)_", "\n".join(body))  # every underscore escaped
    assert r"\caption{" in text and r"\label{tab:fits}" in text


def test_notice_is_a_footer_in_markdown_and_a_note_in_latex(fits):
    notice = "Made-up data_set, 100% synthetic"
    md, tex = fits_markdown(fits, notice), fits_latex(fits, notice)
    assert md.rstrip().splitlines()[-1] == f"Note: {notice}"
    assert r"Made-up data\_set, 100\% synthetic" in tex
    assert tex.index(r"\bottomrule") < tex.index("Note.") < tex.index(r"\end{table}")
    for text in (fits_markdown(fits, ""), fits_latex(fits, "")):
        assert "Note" not in text
    assert summary_markdown(summarise_fits(fits), notice).rstrip().endswith(notice)


def test_summary_statistics_match_numpy(fits):
    summary = summarise_fits(fits)
    assert list(summary.columns) == SUMMARY_COLUMNS
    # monkey rows first, then human; depths ascending within each
    keys = list(zip(summary["species"], summary["depth_mm"], strict=True))
    assert keys == [
        ("monkey", 0.5),
        ("monkey", 1.0),
        ("monkey", 2.0),
        ("human", 1.0),
        ("human", 2.0),
    ]
    for _, row in summary.iterrows():
        group = fits[(fits["species"] == row["species"]) & (fits["depth_mm"] == row["depth_mm"])]
        L = group["waterbed_L_mm"].to_numpy()
        ratio = (group["boussinesq_rmse_mm"] / group["waterbed_rmse_mm"]).to_numpy()
        assert row["n_trials"] == len(group)
        assert row["waterbed_L_mean_mm"] == pytest.approx(np.mean(L))
        if len(group) > 1:
            assert row["waterbed_L_sd_mm"] == pytest.approx(np.std(L, ddof=1))
        else:
            assert np.isnan(row["waterbed_L_sd_mm"])
        for model in ("waterbed", "arc", "boussinesq"):
            expected = np.mean(group[f"{model}_rmse_mm"])
            assert row[f"{model}_rmse_mean_mm"] == pytest.approx(expected)
        assert row["rmse_ratio_boussinesq_to_waterbed_mean"] == pytest.approx(np.mean(ratio))
        assert row["rmse_ratio_boussinesq_to_waterbed_min"] == pytest.approx(np.min(ratio))


def test_summary_tables_have_one_row_per_species_and_depth(fits):
    summary = summarise_fits(fits)
    assert len(markdown_body(summary_markdown(summary))) == len(summary) == 5
    body = latex_body(summary_latex(summary))
    assert len(body) == 5 and body[0].startswith("monkey & 0.50 & 1 &")
    # a single trial has no SD: shown as a dash, not as 0 or nan
    assert "nan" not in summary_markdown(summary) and " – " in summary_markdown(summary)


def test_tables_are_deterministic(fits):
    shuffled_columns = fits[list(reversed(FIT_COLUMNS))]
    assert fits_markdown(fits) == fits_markdown(shuffled_columns)
    assert summary_latex(summarise_fits(fits)) == summary_latex(summarise_fits(fits.copy()))


def sensitivity_frames():
    """Refit rows and per-trial checks made here (not the workflow's), species out of order."""
    refits, checks = [], []
    models = ("waterbed", "waterbed_free_depth", "shifted", "arc", "boussinesq")
    trials = [("H1", "human", 1.0), ("X1", "axolotl", 1.0), ("M1", "monkey", 2.0)]
    for k, (subject, species, depth_mm) in enumerate(trials):
        for window in ("2 mm", "whole"):
            for j, model in enumerate(models):
                refits.append(
                    {
                        "subject": subject,
                        "species": species,
                        "depth_mm": depth_mm,
                        "window": window,
                        "model": model,
                        "L_mm": np.nan if model == "boussinesq" else 10.0 + k + j / 10,
                        "delta_aicc": 0.0 if j == k else 1.5,
                    }
                )
        checks.append(
            {
                "subject": subject,
                "depth_mm": depth_mm,
                **{
                    name: 0.5
                    for name in (
                        "waterbed_L_mm",
                        "shifted_L_mm",
                        "arc_L_mm",
                        "gap_shifted_mm",
                        "gap_arc_mm",
                        "shift_fraction_at_third",
                        "reach_tolerance_mm",
                        "reach_mm",
                        "rmse_within_window_mm",
                    )
                },
                "rmse_beyond_window_mm": np.nan,
            }
        )
    return pd.DataFrame(refits), pd.DataFrame(checks)


def test_sensitivity_markdown_orders_species_as_the_paper_and_names_every_refit():
    refits, checks = sensitivity_frames()
    text = sensitivity_markdown(refits, checks, "Made-up data")
    tables = [
        [line for line in block.splitlines() if line.startswith("|")]
        for block in text.split("\n\n")
        if block.startswith("|")
    ]
    assert len(tables) == 3
    medians = [[c.strip() for c in ln.strip("|").split(" | ")] for ln in tables[0][2:]]
    assert [row[0] for row in medians] == ["monkey", "human", "axolotl"]
    assert "parabola, W₀ free, whole" in tables[0][0] and "Boussinesq" not in tables[0][0]
    assert medians[0][1:3] == ["2", "12.00"]  # M1, the third trial: L = 10 + 2
    best = [[c.strip() for c in ln.strip("|").split(" | ")] for ln in tables[1]]
    assert best[0] == [
        "window",
        "parabola, W₀ = depth",
        "parabola, W₀ free",
        "parabola in measured coordinates",
        "exact arc, W₀ = depth",
        "Boussinesq",
    ]
    assert best[2] == ["2 mm", "1", "1", "1", "0", "0"]
    assert len(tables[2]) == 2 + len(checks) and "| – |" in tables[2][2]
    assert text.rstrip().endswith("*Data: Made-up data*")
    assert "Data:" not in sensitivity_markdown(refits, checks)


@pytest.mark.parametrize(
    ("uncertainty", "decimals"), [(0.14, 2), (1.4, 1), (14.0, 0), (0.0014, 4), (0.099, 3)]
)
def test_decimals_show_two_digits_of_the_uncertainty(uncertainty, decimals):
    assert tables.decimals_for(uncertainty) == decimals
    # the last decimal shown is the uncertainty's second significant digit
    shown = round(uncertainty, decimals)
    assert shown != 0 and abs(shown - uncertainty) <= 0.5 * 10.0**-decimals


def test_a_value_is_given_to_the_digits_its_interval_supports():
    assert tables.with_interval(13.28123, 13.15344, 13.41981) == "13.28 (13.15–13.42)"
    # ten times narrower: one more decimal; ten times wider: one fewer
    assert tables.with_interval(13.28123, 13.26844, 13.29498) == "13.281 (13.268–13.295)"
    assert tables.with_interval(13.28123, 11.9, 14.6) == "13.3 (11.9–14.6)"
    assert tables.with_interval(float("nan"), 1.0, 2.0) == "–"


def test_html_from_the_data_is_shown_as_typed_in_markdown():
    # a notice or label holding markup must not become markup in claims.md or fits.md
    cell = escape_markdown("<script>alert(1)</script> <!-- x --> p < 0.05 & a|b")
    assert "<script" not in cell and "</script" not in cell and "<!--" not in cell
    assert cell.startswith("&lt;script>alert(1)&lt;/script> &lt;!-- x -->")
    assert "p < 0.05" in cell and "a\\|b" in cell  # a comparison stays as written
    footer = notice_footer("Synthetic <b>reconstruction</b>")
    assert footer == "\nNote: Synthetic &lt;b>reconstruction&lt;/b>\n"
