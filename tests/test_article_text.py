"""The article says only what its own data say: built on datasets with different verdicts
(the shipped reconstruction, the photograph example, and monkeys whose profiles follow the
half-space form, without forces), each PDF is read back against its own tables and data;
and the template holds no number or comparison of its own."""

import re

import numpy as np
import pandas as pd
import pytest

import articletext
from conftest import REPO, reading_grid_mm, shared_build
from lineload.claims.rows import NAMED_FIGURES
from lineload.publishing.article import calibration_design

TEMPLATE = REPO / "workflow" / "article" / "reproduction.typ"
OUTPUTS = ["tables/fits.csv", "tables/claims.csv", "article/reproduction.pdf"]


def write_half_space_dataset(folder, seed=11):
    """Two monkeys whose skin follows the half-space form ``w = A ln(x0 / x)`` (no humans,
    no forces, no outlines): there the Boussinesq form fits better than the waterbed."""
    raw = folder  # the shared build's raw folder
    (raw / "profiles").mkdir(parents=True)
    rng = np.random.default_rng(seed)
    lines = ["subject,species,magnification,label"]
    for subject, extent_mm in (("MA", 5.0), ("MB", 6.0)):
        lines.append(f"{subject},monkey,20,monkey {subject}")
        rows = ["depth_mm,side,distance_image_mm,deflection_image_mm"]
        for depth_mm in (1.0, 2.0):
            x = reading_grid_mm(extent_mm)
            shape = np.log(extent_mm / x) / np.log(extent_mm / x[0])
            for side in ("left", "right"):
                w = np.clip(depth_mm * shape + rng.normal(0, 0.005, x.size), 0, None)
                rows += [
                    f"{depth_mm:g},{side},{20 * a:.3f},{20 * b:.3f}"
                    for a, b in zip(x, w, strict=True)
                ]
        (raw / "profiles" / f"{subject}.csv").write_text("\n".join(rows) + "\n")
    (raw / "subjects.csv").write_text("\n".join(lines) + "\n")
    return raw


@pytest.fixture(scope="session")
def half_space_build(tmp_path_factory):
    return shared_build(tmp_path_factory, "half-space", write_half_space_dataset, OUTPUTS)


@pytest.fixture(scope="session")
def shipped_article(shipped_build):
    return shipped_build


def read_back(raw, results, pdf=None):
    """The contradictions between an article and its own build."""
    text = articletext.pdf_text(pdf or results / "article" / "reproduction.pdf")
    trials = pd.read_csv(REPO / "docs" / "calibration" / "bootstrap_trials.csv")
    return articletext.contradictions(
        text,
        pd.read_csv(results / "tables" / "claims.csv"),
        pd.read_csv(results / "tables" / "fits.csv"),
        articletext.dataset_contents(raw),
        calibration_design(trials),
    )


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_article", "photograph_build", "half_space_build"])
def test_no_sentence_contradicts_its_own_tables_or_data(build, request):
    raw, results = request.getfixturevalue(build)
    assert read_back(raw, results) == []


#: A symbol whose subscript is written as a plain letter or digit.
SYMBOL_AS_LETTERS = re.compile(r"\b(?:W0|l_b|theta0|x0)\b")


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_article", "photograph_build"])
def test_names_are_set_as_code_symbols_as_symbols_and_appendices_cited_by_letter(build, request):
    """Read back from the PDF: no config key, column or function in the serif of the prose
    (the rules quote many), no W0 or l_b in plain letters, and the appendices, the
    digitised figures among them, numbered and cited by one letter."""
    raw, results = request.getfixturevalue(build)
    pdf = results / "article" / "reproduction.pdf"
    assert articletext.names_in_prose(pdf) == []
    text = articletext.pdf_text(pdf)
    assert SYMBOL_AS_LETTERS.findall(text) == []
    for letter, title in (("A", "Every trial"), ("B", "The rules")):
        assert f"Appendix {letter}. {title}" in text
    assert "Rule: Appendix B, C8." in text and "Appendix Appendix" not in text
    if articletext.dataset_contents(raw)["photographs"]:
        assert "Appendix C. Digitising the photographs" in text
        # a figure per digitising batch, cited where the data are described and in their
        # appendix, captioned by its letter
        n = len(list((results / "digitised").glob("*.pdf")))
        names = [f"Figure C{i}" for i in range(1, n + 1)]
        cited = names[0] if n == 1 else ", ".join(names[:-1]) + " and " + names[-1]
        assert n >= 1 and text.count(cited) >= 2
        assert all(f"{name}: How" in text for name in names)
        assert not re.search(r"Figure D\d", text)


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_article", "photograph_build"])
def test_the_claims_cite_a_figure_by_its_number(build, request):
    """The claims table names a figure as its reader finds it (by its file's name); the
    article prints its number instead, where the claims' text names one."""
    _, results = request.getfixturevalue(build)
    text = articletext.pdf_text(results / "article" / "reproduction.pdf")
    plain = text.replace("‘", "'").replace("’", "'")
    claims = pd.read_csv(results / "tables" / "claims.csv")
    named = " ".join(claims["our_value"].tolist() + claims["reason"].tolist())
    for name in NAMED_FIGURES:
        assert name not in plain
        if name in named:
            assert re.search(r"instead \(Figure \d+\)|coordinates \(Figure \d+\)", text)


@pytest.mark.e2e
@pytest.mark.parametrize("build", ["shipped_article", "photograph_build", "half_space_build"])
def test_the_limitations_say_which_later_models_are_fitted(build, request):
    """The Limitations name the bending skin and the elastic finger as not fitted only on
    a build that has no such fits; and the rules' >= and <= are printed as signs."""
    _, results = request.getfixturevalue(build)
    text = articletext.pdf_text(results / "article" / "reproduction.pdf")
    elastic = results / "tables" / "elastic_fits.csv"
    has_elastic = elastic.is_file() and (
        pd.read_csv(elastic)["elastic_layered_modulus_ratio"].notna().any()
    )
    later = re.search(r"later model of the same group \([^)]*\), is (not fitted|fitted only)", text)
    assert later and (later.group(1) == "fitted only") == has_elastic
    assert ">=" not in text and "<=" not in text


def test_names_in_the_prose_are_found():
    """The check above can fail: a key in the serif is found, a symbol written out is not."""
    assert articletext.is_code_name("large_depth_mm") and articletext.is_code_name("arc_L_mm")
    assert articletext.is_code_name("lineload.claims.chord_curvature")
    assert articletext.is_code_name("lineload.mechanics")  # a module, with no underscore
    for symbol in ("f_w", "SSE_waterbed", "SSE_Boussinesq", "0.05", "claims.csv"):
        assert not articletext.is_code_name(symbol), symbol
    assert SYMBOL_AS_LETTERS.findall("at the data's W0/L; W₀/L") == ["W0"]


@pytest.mark.e2e
def test_the_datasets_differ_in_what_the_text_must_say(half_space_build, shipped_article):
    """The test datasets are chosen so that the text must change: C3 fails on one and holds
    or is open on the other, one has humans and forces, the other neither."""
    verdicts = {}
    for name, (_, results) in (("half", half_space_build), ("shipped", shipped_article)):
        claims = pd.read_csv(results / "tables" / "claims.csv")
        verdicts[name] = dict(zip(claims["claim"], claims["verdict"], strict=True))
    assert verdicts["half"]["C3"] == "does not hold"
    assert verdicts["shipped"]["C3"] != "does not hold"
    contents = articletext.dataset_contents(half_space_build[0])
    assert contents["species"] == {"monkey"} and not contents["forces"]
    text = articletext.pdf_text(half_space_build[1] / "article" / "reproduction.pdf")
    assert "half-space form leaves smaller residuals than the waterbed" in text or (
        "neither form leaves the smaller residuals" in text
    )
    assert "These data hold no humans" in text and "carry no force readings" in text


@pytest.mark.e2e
def test_a_planted_contradiction_is_found(half_space_build, tmp_path):
    """Each kind of check comes out the other way on an article that says what its data
    do not: the verdicts, the comparison, humans, forces and counts written for other data."""
    raw, results = half_space_build
    text = articletext.pdf_text(results / "article" / "reproduction.pdf")
    claims = pd.read_csv(results / "tables" / "claims.csv")
    fits = pd.read_csv(results / "tables" / "fits.csv")
    contents = articletext.dataset_contents(raw)
    assert articletext.contradictions(text, claims, fits, contents) == []
    n = len(fits)
    planted = [
        "C3: holds.",
        "Near the wedge the waterbed follows the readings better than the half-space form.",
        "Humans: the same for the human subjects.",
        "the fitted membrane with tension at rest.",
        f"better in {n + 1} of {n + 1} trials",
        "In all 2 trials; 1 degrees of freedom; largest 0.0 %.",
    ]
    for sentence in planted:
        assert articletext.contradictions(text + " " + sentence, claims, fits, contents), sentence
    # a dataset said to be photographed, or another design's calibration, is caught too
    photographed = {**contents, "photographs": True}
    said = text + " Readings on the enlargements were divided by the magnification."
    assert articletext.contradictions(said, claims, fits, photographed)
    design = {("human", 1.0): 7}
    assert articletext.contradictions(text + " Wrong, % (95 % CI)", claims, fits, contents, design)


def test_the_template_types_no_number_or_comparison_of_its_own():
    assert articletext.typed_by_hand(TEMPLATE.read_text()) == []


def test_a_number_or_comparison_typed_into_the_template_is_found():
    template = TEMPLATE.read_text()
    for planted in (
        "In 25 of 26 trials the fits agree.",
        "Near the wedge the waterbed follows the readings better than the half-space form.",
        "The Boussinesq form is better than the waterbed.",
    ):
        found = articletext.typed_by_hand(template + "\n" + planted + "\n")
        assert found, planted
    # a number inside an equation or a comment is the model's or the code's, not the data's
    assert articletext.typed_by_hand("$ w = 3 x^2 $ // 5 mm\n") == []
