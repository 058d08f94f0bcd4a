"""The reproduction article: its facts come from the tables, its verdicts from the claims
table, its data statement from the data; read back from the PDF itself."""

import json
import re

import numpy as np
import pandas as pd
import pytest
from pypdf import PdfReader

import pdflayout
from conftest import REPO, SHARED_NOTICE
from lineload.claims import CLAIM_COLUMNS, CLAIM_KINDS
from lineload.figures.registry import FIGURES
from lineload.figures.style import MIN_FONT_PT, SCHEMATIC_MM
from lineload.fitting.batch import FIT_COLUMNS
from lineload.publishing.article import (
    article_facts,
    counted_words,
    join_words,
    number_words,
    shown,
    span_text,
)


def test_words_for_the_text():
    assert [number_words(n) for n in (0, 1, 4, 10, 11)] == ["no", "one", "four", "ten", "11"]
    # counts and their nouns agree through one function, in words or in digits
    assert [counted_words(n, "subject") for n in (1, 3, 12)] == [
        "one subject",
        "three subjects",
        "12 subjects",
    ]
    assert counted_words(1, "degree of freedom", "degrees of freedom") == "one degree of freedom"
    assert join_words(["a"]) == "a" and join_words(["a", "b", "c"]) == "a, b and c"
    assert span_text([2.0, np.nan, 1.25]) == "1.25 to 2.00 mm"
    assert span_text([3.0, 3.0], 1) == "3.0 mm" and span_text([]) == "none"
    assert shown({"a": 3.0, "b": [2.0, None], "c": None}) == {"a": "3", "b": "2, none", "c": "none"}


def small_tables():
    fits = pd.DataFrame(
        [
            {**dict.fromkeys(FIT_COLUMNS, 1.0), "subject": s, "species": sp, "depth_mm": d}
            for s, sp, d in (("A", "monkey", 1.0), ("A", "monkey", 2.0), ("B", "human", 1.0))
        ]
    )
    fits["waterbed_L_mm"] = [10.0, 11.0, 14.0]
    fits["shifted_L_mm"] = [10.2, 11.9, 14.1]
    fits["waterbed_rmse_mm"] = [0.01, 0.02, 0.01]
    fits["boussinesq_rmse_mm"] = [0.05, 0.01, 0.04]
    claims = pd.DataFrame(
        [
            dict.fromkeys(CLAIM_COLUMNS, "x") | {"claim": c, "verdict": v, "kind": CLAIM_KINDS[c]}
            for c, v in (("C1", "holds"), ("C2", "does not hold"), ("C7", "identity"))
        ]
    )
    checks = pd.DataFrame({"gap_shifted_mm": [0.002, 0.02, 0.001]})
    subjects = {
        "A": {"species": "monkey", "magnification": 20.0, "label": "A"},
        "B": {"species": "human", "magnification": 10.0, "label": "B"},
    }
    depths = {"A": [1.0, 2.0], "B": [1.0]}
    settings = {
        "fit_window_mm": 3.0,
        "claims": {"noise_mm": 0.01},
        "sensitivity": {"windows_mm": [2.0, None]},
        "figures": {
            "example_subjects": ["A", "B"],
            "example_depth_mm": 1.0,
            "outline_subjects": [],
            "outline_depth_mm": None,
        },
    }
    software = {
        "python": "3.11",
        "packages": {"numpy": "2", "x": None},
        "git": {"commit": None, "dirty": None},
    }
    return fits, claims, checks, subjects, depths, settings, software


def test_facts_follow_the_tables():
    fits, claims, checks, subjects, depths, settings, software = small_tables()
    facts = article_facts(fits, claims, checks, subjects, depths, settings, "", software)
    data = facts["data"]
    assert not data["synthetic"] and data["who"] == "one monkey and one human"
    assert data["n_trials"] == 3 and data["depths"] == "1 and 2 mm"
    assert data["magnification"] == "10 to 20"
    assert facts["fits"]["L_paper"] == {"monkey": "10.00 to 11.00 mm", "human": "14.00 mm"}
    assert facts["fits"]["waterbed_better"] == "2 of 3"  # the ratio is below 1 in one trial
    assert facts["fits"]["gap_above_noise"] == "1 of 3"
    assert facts["verdicts"]["evidence"] == 2 and facts["verdicts"]["n_claims"] == 2
    # C7, an identity of the method, is reported apart: neither a paper claim nor counted
    assert facts["verdicts"]["checks"] == 1 and facts["verdicts"]["identity"] == 0
    assert [c["evidence"] for c in facts["claims"]] == [True, True, False]
    assert facts["settings"]["sensitivity"]["windows_mm"] == "2, none"
    assert facts["software"]["git"]["commit"] == "unknown"
    assert facts["software"]["packages"] == {"numpy": "2"}
    assert facts["figures"]["example_subjects"] == "A and B"
    synthetic = article_facts(
        fits, claims, checks, subjects, depths, settings, "Made up.", software
    )
    assert synthetic["data"]["synthetic"] and synthetic["data"]["notice"] == "Made up."
    assert facts["built_in"] is None and synthetic["built_in"] is None
    # the generator's own list, when given, names what it built in and what follows
    built_in = [
        {"claim": "C1", "how": "tuned"},
        {"claim": "C3", "how": "follows"},
        {"claim": "C7", "how": "identity"},
        {"claim": "C8", "how": "by construction"},
        {"claim": "C9", "how": "tuned"},
    ]
    listed = article_facts(
        fits, claims, checks, subjects, depths, settings, "Made up.", software, built_in=built_in
    )
    assert listed["built_in"] == {
        "tuned": "C1 and C9",
        "by_construction": "C8",
        "follows": "C3",
        # C2, in the claims table but not in the list, is named as such
        "not_listed": "C2",
    }


def pdf_text(path):
    """The article's text as pypdf reads it, white space folded."""
    return " ".join(" ".join(page.extract_text() for page in PdfReader(path).pages).split())


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["small_build", "small_build_with_notice"])
def test_article_reports_the_claims_table_and_the_data(build, request):
    raw, results = request.getfixturevalue(build)
    notice = SHARED_NOTICE if (raw / "NOTICE.txt").exists() else ""
    text = pdf_text(results / "article" / "reproduction.pdf")
    claims = pd.read_csv(results / "tables" / "claims.csv")
    for claim, verdict in zip(claims["claim"], claims["verdict"], strict=True):
        # each claim's paragraph opens with "<claim>: <verdict>."
        found = re.findall(
            rf"\b{claim}: (holds|does not hold|cannot be checked on these data|identity)\.", text
        )
        assert found == [verdict], (claim, verdict, found)
    # this dataset's own numbers, not the paper's design
    fits = pd.read_csv(results / "tables" / "fits.csv")
    assert "one monkey and one human" in text and f"{len(fits)} trials" in text
    low, high = fits["waterbed_L_mm"].min(), fits["waterbed_L_mm"].max()
    assert f"{low:.2f} to {high:.2f} mm" in text
    if notice:
        assert "These results come from synthetic data." in text and notice in text
    else:
        assert "synthetic" not in text.lower()


def test_a_subject_measured_at_fewer_depths_is_named_not_folded_into_its_species():
    from lineload.publishing.article import group_depths_text

    depths = {"H1": [0.5, 1.0, 1.5, 2.0], "H2": [0.5, 1.0, 1.5, 2.0], "H3": [1.0, 2.0]}
    assert group_depths_text(["H1", "H2", "H3"], depths) == (
        "0.5, 1, 1.5 and 2 mm (H3: 1 and 2 mm)"
    )
    assert group_depths_text(["H1", "H2"], depths) == "0.5, 1, 1.5 and 2 mm"


def test_claim_lists_name_every_item_up_to_a_dozen():
    from lineload.claims.rows import _list

    trials = [f"M{k} at 2 mm" for k in range(1, 9)]
    assert _list(trials) == ", ".join(trials[:-1]) + " and M8 at 2 mm"  # all eight named
    many = [f"S{k}" for k in range(1, 15)]
    assert _list(many).endswith("S12 and 2 more (claims.csv per trial)")


def test_the_appendix_prints_each_trials_fits_up_to_its_limit():
    from lineload.publishing import article

    def trial(k):
        return {
            "subject": f"S{k}", "depth_mm": 1.0,
            "waterbed_L_mm": 12.0, "waterbed_L_ci_low_mm": 11.5,
            "waterbed_L_ci_high_mm": float("inf") if k == 1 else 12.5,
            "arc_L_mm": float("nan") if k == 2 else 12.2, "arc_L_ci_low_mm": 11.7,
            "arc_L_ci_high_mm": 12.7, "waterbed_rmse_mm": 0.0123, "boussinesq_rmse_mm": 0.05,
        }  # fmt: skip

    fits = pd.DataFrame([trial(k) for k in range(article.APPENDIX_TRIALS + 5)])
    facts = article._trial_facts(fits)
    assert (facts["n"], facts["shown"]) == (article.APPENDIX_TRIALS + 5, article.APPENDIX_TRIALS)
    first, second, third = facts["rows"][:3]
    assert first["waterbed"] == "12.00 [11.50, 12.50]" and first["rmse_waterbed"] == "12.3"
    assert second["waterbed"] == "12.00 [11.50, open]"  # an interval that does not close
    assert third["arc"] == "–"  # a fit that gave no L


# ---------------------------------------------------------------- the printed page


def typeset(source, folder):
    """A Typst document compiled in ``folder`` (with the figures it names copied there)."""
    import typst

    path = folder / "page.typ"
    path.write_text(source)
    typst.compile(str(path), output=str(folder / "page.pdf"))
    return folder / "page.pdf"


def test_the_page_measures_see_a_shrunken_figure_and_a_half_empty_page(tmp_path):
    """The measures the article's tests rely on can come out the other way."""
    from lineload.figures import schematics
    from lineload.figures.style import save_figure

    save_figure(
        schematics.figure_channel_schematic(0.15), tmp_path / "f.pdf", tmp_path / "f.png", 50
    )
    own = pdflayout.placed_figures(typeset('#image("f.pdf")', tmp_path))
    half = pdflayout.placed_figures(typeset('#image("f.pdf", width: 50%)', tmp_path))
    (own,), (half,) = own, half
    assert own.scale == pytest.approx(1.0, abs=1e-3)
    assert min(own.text_sizes_pt) == pytest.approx(MIN_FONT_PT, abs=0.01)
    text_width_mm = 210 - 2 * 25.0  # Typst's default A4 margins: 2.5 cm
    assert half.scale == pytest.approx(0.5 * text_width_mm / SCHEMATIC_MM, rel=1e-3)
    assert min(half.text_sizes_pt) == pytest.approx(MIN_FONT_PT * half.scale, rel=1e-3)
    # a figure whose type is too small is seen as such at its own size
    (tiny,) = pdflayout.placed_figures(_figure_with_small_type(tmp_path))
    assert min(tiny.text_sizes_pt) == pytest.approx(5.0, abs=0.01)
    # a full page of text, then a page with one line
    fills = pdflayout.page_fill(typeset("#lorem(900)\n#pagebreak()\nOne line.", tmp_path))
    assert fills[0] > 0.9 and fills[-1] < 0.1


def _figure_with_small_type(folder):
    from lineload.figures.style import new_figure, save_figure

    fig = new_figure(100.0, 40.0, layout=None)
    fig.text(0.5, 0.5, "five-point type", fontsize=5.0)
    save_figure(fig, folder / "g.pdf", folder / "g.png", 50)
    return typeset('#image("g.pdf")', folder)


@pytest.mark.e2e
def test_every_figure_prints_at_its_own_size_with_no_type_below_7_points(shipped_build):
    """Journals ask for about 7 pt at least, as printed: each figure's type measured in the
    article itself, where the page's matrix and the figure's own combine."""
    pdf = shipped_build[1] / "article" / "reproduction.pdf"
    figures = pdflayout.placed_figures(pdf)
    assert len(figures) == len(FIGURES)  # every figure of the workflow is in print
    for figure in figures:
        where = (figure.page, figure.texts[:4])
        assert figure.scale == pytest.approx(1.0, abs=1e-3), where
        smallest = min(figure.text_sizes_pt)
        assert smallest >= MIN_FONT_PT - 0.01, (where, smallest)


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_build", "photograph_build"])
def test_every_page_but_the_last_is_at_least_four_fifths_full(build, request):
    results = request.getfixturevalue(build)[1]
    fills = pdflayout.page_fill(results / "article" / "reproduction.pdf")
    assert len(fills) > 5
    thin = {page: round(fill, 2) for page, fill in enumerate(fills[:-1], start=1) if fill < 0.8}
    assert thin == {}


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_build", "photograph_build"])
def test_no_figure_of_the_body_prints_after_the_references_heading(build, request):
    """A figure floated to the foot of the page where the body ends let the References
    run in above it; only the appendix's figures (the digitised photographs, printed
    last) come after that heading."""
    from lineload.publishing.article import PHOTOGRAPH_FIGURES

    results = request.getfixturevalue(build)[1]
    pdf = results / "article" / "reproduction.pdf"
    figures = pdflayout.placed_figures(pdf)
    references = pdflayout.headings(pdf)["References"]
    in_appendix = min(len(list((results / "digitised").glob("*.pdf"))), PHOTOGRAPH_FIGURES)
    body = figures[: len(figures) - in_appendix]
    assert len(body) >= len(FIGURES) - 2  # the species' figures may be left out
    late = [(f.page, round(f.top_pt)) for f in body if pdflayout.placed_after(f, references)]
    assert late == [], references
    # the check can fail: the appendix's figures are after it
    assert all(pdflayout.placed_after(f, references) for f in figures[len(body) :])


def body_text(path):
    """The article's own text (its serif font), without the figures' (DejaVu Sans)."""
    runs = []

    def visit(text, cm, tm, font, size):
        if font is not None and "Libertinus" in str(font.get("/BaseFont", "")):
            runs.append(text)

    for page in PdfReader(path).pages:
        page.extract_text(visitor_text=visit)
    return "".join(runs)


@pytest.mark.e2e
def test_text_from_the_tables_gets_curly_quotes_like_the_rest(small_build_with_notice):
    """The claims' sentences come from claims.csv, where Typst's smart quotes do not reach."""
    text = body_text(small_build_with_notice[1] / "article" / "reproduction.pdf")
    assert "paper’s" in text and "‘Comparison" in text  # from claims.csv, curled
    assert "'" not in text and '"' not in text


def test_the_article_places_the_figures_in_the_registry_order_the_report_numbers_by():
    """The report labels a figure by its place in the registry; the article numbers
    figures as it places them: the same order gives the same numbers in both."""
    from lineload.figures.registry import report_label

    template = (REPO / "workflow" / "article" / "reproduction.typ").read_text()
    # by-species places a figure, or a sentence in its place that keeps its number
    placed = re.findall(r'#(?:fig|by-species)\("(\w+)"', template)
    assert placed == [figure.name for figure in FIGURES]
    labels = [" ".join(report_label(figure).split()) for figure in FIGURES]
    assert labels == [f"Figure {n}" for n in range(1, len(FIGURES) + 1)]


def test_counts_and_small_values_are_written_once_and_right():
    from lineload.publishing.tables import counted, every, percent_text

    assert counted(1, "degree of freedom", "degrees of freedom") == "1 degree of freedom"
    assert counted(5, "degree of freedom", "degrees of freedom") == "5 degrees of freedom"
    assert counted(0, "trial") == "0 trials" and counted(1, "trial") == "1 trial"
    assert [every(n, "trial") for n in (0, 1, 2, 3)] == [
        "no trials", "the one trial", "both trials", "all 3 trials",
    ]  # fmt: skip
    # a value too small for its decimals is not shown as zero; zero is
    assert percent_text(0.0003) == "< 0.1 %" and percent_text(-0.0003) == "> -0.1 %"
    assert percent_text(0.0) == "0 %" and percent_text(0.1234) == "12.3 %"
    assert percent_text(float("nan")) == "–"


def test_the_text_compares_the_models_as_the_counts_say():
    from lineload.publishing.article import _comparison_text, _coordinates_text, _ratio_decimals

    # a ratio is never printed as 0.0: the smallest keeps two significant digits
    assert _ratio_decimals([2.5, 9.4]) == 1 and _ratio_decimals([0.02, 0.05]) == 3
    assert _ratio_decimals([0.5, 5.3]) == 2 and _ratio_decimals([]) == 1

    assert "waterbed leaves smaller residuals than the half-space form in all 4" in (
        _comparison_text(4, 4)
    )
    assert "half-space form leaves smaller residuals than the waterbed in both" in (
        _comparison_text(0, 2)
    )
    mixed = _comparison_text(2, 4)
    assert "neither form" in mixed and "2 of 4 trials" in mixed
    assert _coordinates_text(0, 3).startswith("less than") and "3" in _coordinates_text(0, 3)
    assert _coordinates_text(1, 3) == "more than one reading's noise in 1 of 3 trials"


def test_the_abstract_names_the_other_model_only_where_it_wins_a_trial():
    from lineload.publishing.article import _comparison_short

    assert _comparison_short(4, 4) == (
        "the waterbed leaves the smaller residuals in all 4 trials with both fits"
    )
    assert _comparison_short(25, 26).endswith(
        "25 of 26 trials with both fits, the half-space form in the other one"
    )
    assert _comparison_short(2, 5).endswith("in the other 3")
    assert _comparison_short(0, 2).startswith(
        "the half-space form leaves the smaller residuals in both"
    )
    assert "half-space" not in _comparison_short(3, 3) and "waterbed" not in _comparison_short(0, 3)
    assert _comparison_short(0, 0).startswith("no trial")


def test_a_digitising_batch_is_named_and_its_figures_take_a_verb_that_agrees():
    """One figure "shows", two "show"; a batch of two subjects is named by both."""
    from lineload.publishing.article import photograph_facts

    trial = {
        "depth_mm": 1.0,
        "tip_x_mm": 8.0,
        "shift_x_mm": 0.01,
        "shift_z_mm": 0.0,
        "registration_rms_um": 1.5,
        "reading_sd_um": 0.8,
        "first_read_mm": {"left": 0.05, "right": 0.05},
        "readings": {"left": 27, "right": 27},
    }

    def batch(*members):
        return {
            "batch": f"{members[0]}+{len(members) - 1}",
            "subjects": [{"subject": m, "trials": [trial]} for m in members],
        }

    sheet = {m: {"label": f"monkey {m}"} for m in ("M1", "M2", "M3", "M4")}
    one = photograph_facts([batch("M1", "M2")], sheet, ["digitised/M1+1.pdf"])
    assert one["figures_show"] == "shows"
    assert one["figures"][0]["label"] == "the batch of M1 and M2"
    two = photograph_facts(
        [batch("M1"), batch("M2", "M3", "M4")], sheet, ["digitised/a.pdf", "digitised/b.pdf"]
    )
    assert two["figures_show"] == "show"
    assert [f["label"] for f in two["figures"]] == [
        "monkey M1",
        "the batch of 3 subjects from M2 to M4",
    ]


def test_the_elastic_ratios_are_printed_to_two_significant_digits_of_the_smallest():
    """A modulus ratio of 20.582 is printed 21, not to three decimals; a ratio below ten
    keeps its first decimal."""
    from lineload.publishing.article import elastic_facts

    def facts(ratios):
        n = len(ratios)
        elastic = pd.DataFrame(
            {
                "subject": [f"M{i}" for i in range(n)],
                "depth_mm": [1.0] * n,
                "elastic_layered_modulus_ratio": ratios,
                "elastic_layered_ratio_at_bound": [0] * n,
                "elastic_layered_ratio_ci_high": [1000.0] * n,
                "elastic_layered_rmse_mm": [0.05] * n,
                "elastic_homogeneous_rmse_mm": [0.2] * n,
                "elastic_layered_aicc": [-10.0] * n,
                "elastic_homogeneous_aicc": [0.0] * n,
            }
        )
        fits = elastic[["subject", "depth_mm"]].assign(waterbed_rmse_mm=0.01)
        return elastic_facts(elastic, fits)

    assert facts([20.582, 420.548])["free_range"] == "21 to 421"
    assert facts([2.46, 420.548])["free_range"] == "2.5 to 420.5"


def test_the_calibration_is_printed_only_for_the_design_it_was_computed_for():
    from lineload.publishing.article import calibration_design, dataset_design, design_text

    fits, *_ = small_tables()
    ours = dataset_design(fits)
    assert ours == {("monkey", 1.0): 1, ("monkey", 2.0): 1, ("human", 1.0): 1}
    trials = pd.DataFrame(
        {
            "dataset": [0, 0, 0, 1, 1, 1],
            "model": "waterbed",
            "parameter": "L_mm",
            "species": ["monkey", "monkey", "human"] * 2,
            "depth_mm": [1.0, 2.0, 1.0] * 2,
        }
    )
    assert calibration_design(trials) == ours  # replicates are not counted as trials
    assert calibration_design(trials.iloc[[0, 1, 3, 4]]) != ours
    assert design_text(ours) == "3 trials (2 monkey, 1 human) at 1 and 2 mm"


def test_the_byline_is_the_citation_files_authors_or_a_placeholder_shown_as_one():
    from lineload.publishing.citation import PLACEHOLDER_AUTHOR, author_names

    assert author_names({"authors": [{"name": PLACEHOLDER_AUTHOR}]}) == (PLACEHOLDER_AUTHOR, True)
    assert author_names({}) == ("", True)
    named = {
        "authors": [
            {"given-names": "Ada", "family-names": "Lovelace"},
            {"given-names": "Alan", "family-names": "Turing"},
            {"name": "A Lab"},
        ]
    }
    assert author_names(named) == ("Ada Lovelace, Alan Turing and A Lab", False)


def whole_on_one_page(pages, caption, rows):
    """Whether the table captioned ``caption`` shows its first and last rows (each the
    start of a row as the text reads it) on the page of its caption, and is not continued."""
    with_caption = [p for p in pages if caption in p]
    return (
        len(with_caption) == 1
        and all(row in with_caption[0] for row in (rows[0], rows[-1]))
        and not any(re.search(r"Table \d+, continued", p) and rows[-1] in p for p in pages)
    )


@pytest.mark.e2e
def test_the_verdict_calibrations_table_is_kept_whole_on_one_page(shipped_build):
    """A table shorter than a page is never cut: the verdict calibration (Table 5 of the
    shipped article) ran from page 10 to 13 in three pieces around four figures."""
    results = shipped_build[1]
    facts = json.loads((results / "article" / "facts.json").read_text())
    rows = [
        f"{r['claim']} {r['truth']} {r['n']} {r['holds']}" for r in facts["calibration"]["rows"]
    ]
    reader = PdfReader(results / "article" / "reproduction.pdf")
    pages = [" ".join(page.extract_text().split()) for page in reader.pages]
    caption = "Verdicts of each rule on simulated datasets"
    assert whole_on_one_page(pages, caption, rows)
    # the check sees a cut: the last rows on the next page, under a 'continued' header
    split = [f"{caption} {rows[0]}", f"Table 5, continued {rows[-1]}"]
    assert not whole_on_one_page(split, caption, rows)


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_build", "photograph_build"])
def test_the_replication_choices_are_kept_whole_on_one_page(build, request):
    """The choices table is shorter than a page: at the body's size its caption, header and
    first row sat at one page's foot (or its last row on a page of its own)."""
    results = request.getfixturevalue(build)[1]
    reader = PdfReader(results / "article" / "reproduction.pdf")
    pages = [" ".join(page.extract_text().split()) for page in reader.pages]
    rows = ["Averaging", "Fit window", "sensitivity.reach_fraction"]
    assert whole_on_one_page(pages, "The choices the paper leaves open", rows)
