"""The verdicts of a claims table counted, and said in one sentence.

Apart from :mod:`.table` (which imports every claim's rule, and scipy with them) so
that the article and the report pages, which only count verdicts, import it alone.
"""

from __future__ import annotations

from lineload.claims.verdicts import (
    EVIDENCE_VERDICTS,
    FAILS,
    HOLDS,
    IDENTITY,
    PAPER_CLAIM,
    UNTESTABLE,
    VERDICTS,
)
from lineload.publishing.tables import join_words

__all__ = ["summary_sentence", "verdict_counts"]


def verdict_counts(claims):
    """How many of the paper's claims got each verdict; only ``holds`` and ``does not
    hold`` are evidence.

    Parameters
    ----------
    claims : pandas.DataFrame
        A claims table (column ``verdict``; with a column ``kind``, only the rows of
        kind ``paper claim`` are counted, see :data:`lineload.claims.registry.CLAIM_KINDS`).

    Returns
    -------
    dict
        Verdict -> count for every verdict of :data:`VERDICTS`, ``evidence`` (the
        number of claims the data tested), ``paper_claims`` (the rows counted) and
        ``checks`` (the rows of other kinds, reported apart).
    """
    counted = claims[claims["kind"] == PAPER_CLAIM] if "kind" in claims else claims
    counts = {v: int((counted["verdict"] == v).sum()) for v in VERDICTS}
    counts["evidence"] = sum(counts[v] for v in EVIDENCE_VERDICTS)
    counts["paper_claims"] = len(counted)
    counts["checks"] = len(claims) - len(counted)
    return counts


def summary_sentence(claims):
    """One sentence counting the verdicts, evidence apart from identities.

    Parameters
    ----------
    claims : pandas.DataFrame
        A claims table (:func:`lineload.claims.table.compute_claims`).

    Returns
    -------
    str
    """
    counts = verdict_counts(claims)
    text = (
        f"Of the paper's {counts['paper_claims']} claims about fingers, the data tested "
        f"{counts['evidence']}: {counts[HOLDS]} {'holds' if counts[HOLDS] == 1 else 'hold'} "
        f"and {counts[FAILS]} {'does' if counts[FAILS] == 1 else 'do'} not"
    )
    extras = []
    if counts[UNTESTABLE]:
        extras.append(f"{counts[UNTESTABLE]} cannot be checked on these data")
    if counts[IDENTITY]:
        extras.append(
            f"{counts[IDENTITY]} {'is an identity' if counts[IDENTITY] == 1 else 'are identities'}"
            " of the model's equations and not evidence"
        )
    if "kind" in claims and counts["checks"]:
        others = claims[claims["kind"] != PAPER_CLAIM]
        extras.append(
            "checked and reported apart, not counted as evidence: "
            + join_words(f"{r['claim']} ({r['kind']})" for _, r in others.iterrows())
        )
    return text + ("; " + "; ".join(extras) if extras else "") + "."
