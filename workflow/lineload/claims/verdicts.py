"""The words of the claims table: its verdicts, the kinds of row and its columns.

Standard library only: the registry (:mod:`lineload.claims.registry`) and every
claim's family read these names.

``holds`` / ``does not hold``
    The data were tested, and the rule could have come out either way (the tests
    build a violating and a satisfying dataset for every claim).
``cannot be checked on these data``
    The data hold nothing the rule can test; ``our_value`` says why.
``identity``
    The statement follows from the model's equations alone (C7).  The rule
    checks that the fitted curves obey it, which tests the code, not the
    fingertip; it is not counted as evidence
    (:func:`lineload.claims.summary.verdict_counts`).
"""

from __future__ import annotations

__all__ = [
    "CLAIM_COLUMNS",
    "EVIDENCE_VERDICTS",
    "FAILS",
    "HOLDS",
    "IDENTITY",
    "KINDS",
    "LATER_WORK",
    "MARGIN_GRID",
    "METHOD_IDENTITY",
    "METHOD_PROPERTY",
    "MODEL_CHECK",
    "NO_MARGIN",
    "PAPER_CLAIM",
    "PAPER_SUGGESTION",
    "UNTESTABLE",
    "VERDICTS",
    "InternalError",
]


class InternalError(RuntimeError):
    """A check that can only fail through a bug in this code (never evidence)."""


HOLDS = "holds"
FAILS = "does not hold"
UNTESTABLE = "cannot be checked on these data"
IDENTITY = "identity"
#: The only verdicts a claim can get.
VERDICTS = (HOLDS, FAILS, UNTESTABLE, IDENTITY)
#: The verdicts that are evidence about the data (the others are not counted).
EVIDENCE_VERDICTS = (HOLDS, FAILS)

PAPER_CLAIM = "paper claim"
METHOD_PROPERTY = "property of the method"
METHOD_IDENTITY = "identity of the method"
MODEL_CHECK = "model-consistency check"
PAPER_SUGGESTION = "the paper's closing suggestion"
#: A finding of later work by others, tested on these data (not the paper's).
LATER_WORK = "later work"
#: What a row of the claims table can be.  Only the paper's claims about fingers are
#: counted as evidence (:func:`lineload.claims.summary.verdict_counts`); the others are
#: checked and reported apart.  Each claim's kind, and why, is in its registry entry.
KINDS = (
    PAPER_CLAIM,
    METHOD_PROPERTY,
    METHOD_IDENTITY,
    MODEL_CHECK,
    PAPER_SUGGESTION,
    LATER_WORK,
)

#: The margins searched for the smallest at which an equivalence test holds.
MARGIN_GRID = tuple(k / 100 for k in range(1, 21))
#: ``smallest_margin`` where no margin of the grid makes the claim hold.
NO_MARGIN = "none"

#: Columns of the claims table, in order.
CLAIM_COLUMNS = [
    "claim",
    "kind",
    "statement",
    "paper_location",
    "paper_value",
    "our_value",
    "verdict",
    "smallest_margin",
    "reason",
    "rule",
]
