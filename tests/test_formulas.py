"""The rules' formulas: plain text in the claims table, Typst math in the article."""

import json
import re

import pandas as pd
import pytest

from lineload.publishing.formulas import FORMULAS, PLAIN_FORMULA_SIGNS, segments

#: A rule written as C12's is, with a sentence around its formula.
C12_LIKE = (
    "it is beyond the geometry if g = √(max(D − 2s², 0)/n)/W₀ exceeds the margin; "
    "(b) a trial is layered if both, and D/s² is large."
)


def plain(pieces):
    return "".join(p.get("text", p.get("plain", "")) for p in pieces)


def math_of(pieces):
    return [p["math"] for p in pieces if "math" in p]


def typeset_math(formulas, folder):
    """Compile every formula as inline math; Typst refuses a malformed one."""
    import typst

    (folder / "formulas.json").write_text(json.dumps(formulas))
    source = (
        '#for m in json("formulas.json") [#math.equation(block: false, eval(m, mode: "math"))\n]'
    )
    (folder / "page.typ").write_text(source)
    return typst.compile(str(folder / "page.typ"))


def test_a_rule_is_cut_into_text_and_formulas_that_join_back():
    pieces = segments(C12_LIKE)
    assert plain(pieces) == C12_LIKE
    assert "g = sqrt(max(D - 2 s^2, 0) \\/ n) \\/ W_0" in math_of(pieces)
    assert "D \\/ s^2" in math_of(pieces)
    # '(b)' is a list's letter, not the symbol b
    assert "(b)" in "".join(p.get("text", "") for p in pieces)
    # no formula sign is left in the plain pieces
    left = [s for p in pieces if "text" in p for s in PLAIN_FORMULA_SIGNS if s in p["text"]]
    assert left == []


def test_text_without_formulas_stays_one_piece():
    text = "Holds if every trial is inside; cannot be checked otherwise."
    assert segments(text) == [{"text": text}]


def test_the_check_for_untypeset_formulas_can_fail():
    # a formula no entry knows keeps its signs in a plain piece, where the e2e test sees it
    pieces = segments("the spread is √(κ²) here")
    assert any(s in pieces[0]["text"] for s in PLAIN_FORMULA_SIGNS)


def test_every_formula_typesets(tmp_path):
    assert typeset_math(math_of(segments(C12_LIKE)), tmp_path)[:4] == b"%PDF"
    # a malformed one is refused: the check can fail
    with pytest.raises(Exception):  # noqa: B017 (typst raises its own error type)
        typeset_math(["sqrt(D"], tmp_path)


@pytest.mark.e2e
def test_the_shipped_rules_formulas_are_all_found_and_typeset(shipped_build, tmp_path):
    """Every entry finds its formula in the shipped data's rules (a rule reworded leaves
    an entry unused: that fails here), no formula sign is left in plain text, and Typst
    sets every formula."""
    claims = pd.read_csv(shipped_build[1] / "tables" / "claims.csv")
    found, formulas = set(), []
    for rule in claims["rule"]:
        pieces = segments(rule)
        assert plain(pieces) == rule
        left = [s for p in pieces if "text" in p for s in PLAIN_FORMULA_SIGNS if s in p["text"]]
        assert left == [], rule
        formulas += math_of(pieces)
        found |= {pattern for pattern, _ in FORMULAS if re.search(pattern, rule)}
    assert [pattern for pattern, _ in FORMULAS if pattern not in found] == []
    typeset_math(formulas, tmp_path)
    facts = json.loads((shipped_build[1] / "article" / "facts.json").read_text())
    assert facts["rules"]["C12"] == segments(claims.set_index("claim").loc["C12", "rule"])
