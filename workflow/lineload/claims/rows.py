"""One row of the claims table, and the words its numbers are put in.

Every claim's function ends in :func:`_row`, which adds the registry's text and
kind to the numbers, verdict, reason and rule the function found.
"""

from __future__ import annotations

from lineload.claims.registry import CLAIM_KINDS, CLAIM_TEXT
from lineload.claims.verdicts import HOLDS, MARGIN_GRID, NO_MARGIN, UNTESTABLE, VERDICTS
from lineload.publishing.tables import counted, every, format_fixed, join_words, percent_text

#: How the claims table names a figure (its file's name, for a reader of the CSV).
COORDINATES_FIGURE = "supplementary figure 'coordinates'"
#: Each figure the claims' text names -> the figure's file name, which the article
#: labels it with and replaces the name by the figure's number.
NAMED_FIGURES = {COORDINATES_FIGURE: "supplement_coordinates"}


def _mm(value, decimals=2):
    return f"{format_fixed(value, decimals)} mm"


def _pct(fraction, decimals=1):
    return percent_text(fraction, decimals)


#: '1 trial', '3 trials' (:func:`lineload.publishing.tables.counted`).
_n = counted

#: 'the one trial', 'both trials', 'all 3 trials' (:func:`lineload.publishing.tables.every`).
_every = every


def _list(labels, limit=12):
    """'a, b and c': every item up to ``limit``; beyond it the first ones and a count.

    A dataset of thousands of trials cannot be listed in a sentence: then the
    first ``limit`` are named and the rest counted (claims.csv holds each trial).
    """
    labels = list(labels)
    if len(labels) <= limit:
        return join_words(labels)
    return ", ".join(labels[:limit]) + f" and {len(labels) - limit} more (claims.csv per trial)"


def _row(claim, our_value, verdict, reason, rule, smallest_margin=""):
    """One row of the claims table; ``smallest_margin`` only for the equivalence tests."""
    statement, location, paper_value = CLAIM_TEXT[claim]
    if verdict not in VERDICTS:
        raise ValueError(f"{claim}: unknown verdict {verdict!r}")
    return {
        "claim": claim,
        "kind": CLAIM_KINDS[claim],
        "statement": statement,
        "paper_location": location,
        "paper_value": paper_value,
        "our_value": our_value,
        "verdict": verdict,
        "smallest_margin": smallest_margin,
        "reason": reason,
        "rule": rule,
    }


def _smallest_margin(decide):
    """The smallest margin of :data:`MARGIN_GRID` at which ``decide(margin)`` says
    ``holds``, as a percentage ('4 %'), or :data:`NO_MARGIN`."""
    for margin in MARGIN_GRID:
        if decide(margin) == HOLDS:
            return _pct(margin, 0)
    return NO_MARGIN


def _too_few_subjects(claim, slopes, species, rule, min_df=1):
    """The row of a slope test across subjects with fewer than ``min_df`` degrees of
    freedom left for the spread between subjects (config ``claims: slope_min_df``)."""
    df = max(len(slopes) - len(species), 0)
    needed = max(len(species), 1) + min_df
    return _row(
        claim,
        f"{_n(len(slopes), 'subject')} measured at two or more depths, "
        f"{_n(len(species), 'species', 'species')}: "
        f"{_n(df, 'degree of freedom', 'degrees of freedom')} for the spread between "
        f"subjects, fewer than the {min_df} the rule requires (config claims: slope_min_df)",
        UNTESTABLE,
        "Too few subjects were measured at two or more depths to test the slope across "
        f"subjects: at least {needed} are needed (one per species and {min_df} more), "
        "so that the spread between subjects rests on more than one or two differences.",
        rule,
    )


def _p_text(p_value):
    """A p-value as the test can resolve it: '< 0.001' below that, else three decimals."""
    return "< 0.001" if p_value < 0.001 else f"= {p_value:.3f}"
