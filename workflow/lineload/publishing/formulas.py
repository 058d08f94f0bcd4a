"""The claims' rules with their formulas typeset: plain text for the CSV, math for the article.

The claims table states each rule in plain text (``g = √(max(D − 2s², 0)/n)/W₀``), which
a spreadsheet shows as it is.  The article sets the same formulas as Typst math: each
entry of :data:`FORMULAS` finds one formula of the plain text (a regular expression)
and gives its Typst math (a template that may use the expression's groups), and
:func:`segments` cuts a rule into plain pieces and formulas.  An entry that no longer
finds its formula leaves it in plain text, never wrong; the tests ask every entry to
find its formula in the shipped data's rules, and that no formula sign is left in the
plain pieces.
"""

from __future__ import annotations

import re

__all__ = ["FORMULAS", "PLAIN_FORMULA_SIGNS", "segments"]

#: A number as the rules print one (``0.05``, ``1.64``, ``2``).
_NUMBER = r"\d+(?:\.\d+)?"

#: (plain text, as a regular expression; its Typst math).  Longer formulas first: at one
#: place of the text the first entry that matches there wins.
FORMULAS = (
    # C1
    (
        r"z = \(human extent - monkey extent\) / the root of the sum of their squared "
        r"standard errors",
        r'z = ("human extent" - "monkey extent") \/ sqrt("SE"_"human"^2 + "SE"_"monkey"^2)',
    ),
    # a one-sided normal quantile; with the Bonferroni count of C2
    (
        rf"z\(1 - ({_NUMBER})/\(2 x trials\)\)",
        r'z_(1 - \1 \/ (2 times "trials"))',
    ),
    (rf"z\(1 - ({_NUMBER})\)", r"z_(1 - \1)"),
    # C2
    (r"D = mean\(d²\) − trace\(C\)/n", r'D = "mean"(d^2) - "trace"(C) \/ n'),
    (
        rf"D ([+-]) (z_\S+|z\(1 - {_NUMBER}(?:/\(2 x trials\))?\)) SE ([<>]) \(({_NUMBER}) W₀\)²",
        None,  # built below: the quantile inside it is a formula of its own
    ),
    # C3
    (r"D = SSE_Boussinesq - SSE_waterbed", r'D = "SSE"_"Boussinesq" - "SSE"_"waterbed"'),
    (r"D = sum \(f_w - f_B\)\(2 y - f_w - f_B\)", r"D = sum (f_w - f_B)(2 y - f_w - f_B)"),
    (r"2 sqrt\(d' C d\)", r"2 sqrt(d' C d)"),
    (r"d = f_w - f_B", r"d = f_w - f_B"),
    # C4
    (r"W < 0", r"W < 0"),
    (r"L/3 < distance < L", r'L\/3 < "distance" < L'),
    (r"\bm - f\b", r"m - f"),
    # C6
    (
        r"d = \(L of the paper's procedure − L of the arc\) / L of the arc",
        r'd = (L_"paper" - L_"arc") \/ L_"arc"',
    ),
    (r"\|U\(L/3\)\| / \(L/3\)", r"abs(U(L\/3)) \/ (L\/3)"),
    (r"\|U\|/X", r"abs(U) \/ X"),
    (r"x = X \+ U", r"x = X + U"),
    (r"W₀/L", r"W_0 \/ L"),
    # C7
    (r"\[0, 2L/3\]", r"[0, 2L\/3]"),
    (r"\bL/3\b", r"L\/3"),
    # C8
    (r"q = \(RMSE² − s²\) / W₀²", r'q = ("RMSE"^2 - s^2) \/ W_0^2'),
    (r"trace\(C\) − g'Cg/g'g over n", "(\"trace\"(C) - (g' C g) \\/ (g' g)) \\/ n"),
    (r"g = dm/dL", r"g = partial m \/ partial L"),
    # C10
    (r"r = \(inner - outer\) / whole", r'r = ("inner" - "outer") \/ "whole"'),
    # C11
    (r"F = 2lN sin θ₀", r"F = 2 l N sin theta_0"),
    (r"N = Eε", r"N = E epsilon"),
    (rf"1/({_NUMBER}) = ({_NUMBER})", r"1 \/ \1 = \2"),
    (r"\bs²(?= plus the part)", r"s^2"),
    (rf"force_sd_N = ({_NUMBER}) N", r'"force_sd_N" = \1 "N"'),
    (r"N₀/E", r"N_0 \/ E"),
    # C12
    (r"D = SSE\(homogeneous\) − SSE\(layered\)", r'D = "SSE"_"homogeneous" - "SSE"_"layered"'),
    (
        rf"g = √\(max\(D − ({_NUMBER})s², 0\)/n\)/W₀",
        r"g = sqrt(max(D - \1 s^2, 0) \/ n) \/ W_0",
    ),
    (r"D/s²", r"D \/ s^2"),
    # C13
    (
        r"b = \(RMSE²\(waterbed\) − RMSE²\(bending\) − s²/\(2n\)\) / W₀²",
        r'b = ("RMSE"_"waterbed"^2 - "RMSE"_"bending"^2 - s^2 \/ (2 n)) \/ W_0^2',
    ),
    (
        r"n\(RMSE²\(waterbed\) − RMSE²\(bending\)\)",
        r'n ("RMSE"_"waterbed"^2 - "RMSE"_"bending"^2)',
    ),
    (rf"({_NUMBER}) s⁴", r"\1 s^4"),
    (r"s²/2", r"s^2 \/ 2"),
    # symbols standing alone
    (r"W₀²", r"W_0^2"),
    (r"W₀", r"W_0"),
    (r"s²", r"s^2"),
    (r"θ₀", r"theta_0"),
    (r"N₀", r"N_0"),
    # a one-letter symbol of the formulas standing alone in a sentence ("if D exceeds
    # zero", "C the covariance"); not N (also the unit newton), not in "(b)" or a path
    (r"(?<![\w(./-])([CDEFLUWXbdfglmnqrz])(?![\w(/-])", r"\1"),
)


def _equivalence_bound(match):
    """C2's bounds: ``D + z(1 - 0.05) SE < (0.05 W₀)²``, the quantile set as one."""
    sign, quantile, relation, margin = match.groups()
    inner = segments(quantile)
    quantile_math = inner[0]["math"] if len(inner) == 1 and "math" in inner[0] else quantile
    return f'D {sign} {quantile_math} "SE" {relation} ({margin} W_0)^2'


_COMPILED = tuple(
    (re.compile(pattern), math if math is not None else _equivalence_bound)
    for pattern, math in FORMULAS
)

#: Signs that belong to a formula: one left in a plain piece is a formula not typeset.
PLAIN_FORMULA_SIGNS = ("²", "⁴", "√", "₀", "sqrt(", "SSE_", "f_w", "θ", "ε")


def segments(text, formulas=_COMPILED):
    """Cut plain text into plain pieces and formulas.

    Parameters
    ----------
    text : str
        A rule as the claims table states it.
    formulas : sequence of (re.Pattern, str or callable), optional
        Each formula's pattern and its Typst math: a template for ``Match.expand`` or a
        function of the match (:data:`FORMULAS`, compiled).

    Returns
    -------
    list of dict
        In text order, each ``{"text": ...}`` or ``{"math": ...}`` (Typst math, without
        the dollar signs); joining the pieces' plain text gives ``text`` back.
    """
    pieces, position = [], 0
    while position < len(text):
        best = None
        for pattern, math in formulas:
            match = pattern.search(text, position)
            if match and match.end() > match.start():
                if best is None or match.start() < best[0].start():
                    best = (match, math)
        if best is None:
            break
        match, math = best
        if match.start() > position:
            pieces.append({"text": text[position : match.start()]})
        formula = math(match) if callable(math) else match.expand(math)
        pieces.append({"math": formula, "plain": match.group(0)})
        position = match.end()
    if position < len(text):
        pieces.append({"text": text[position:]})
    return pieces
