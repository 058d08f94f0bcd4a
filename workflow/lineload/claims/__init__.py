"""The claims table: each statement of the paper as a test on the fits, with its verdict.

Each claim (its text, kind and rule in :mod:`.registry`) has one function that
computes numbers from the fit table and the left/right mean profiles (C11 also
from the force readings, when there are any), then applies a rule stated in
words (with its thresholds) to reach a verdict.  No verdict is written in
advance.  Every row also carries one sentence of ``reason`` for a reader, and the
``rule`` in full.

Modules
-------
registry
    The one list of the claims: text, place in the paper, paper value, rule, what
    each needs, its boundary world, what the generator builds in, its function.
verdicts
    The verdicts, the kinds of row and the table's columns.
settings
    :class:`ClaimSettings`, the rules' thresholds.
statistics
    Shared statistics: deformed extent, asymmetry excess, chord curvature, slopes
    across subjects, how a fitted L moves with the readings.
trials, rows
    A trial's points and noise as the rules see them; one row of the table in words.
shape, fit_quality, halfwidth, forces, bending
    The claims' functions, one family per module.
table
    :func:`compute_claims` and the Markdown table.
summary
    The verdicts counted and said in a sentence.

Inputs
------
fits : pandas.DataFrame
    The fit table, one row per subject and depth (columns of
    :data:`lineload.fitting.batch.FIT_COLUMNS`; ``fit_window_mm`` says which points
    were fitted).
averaged : pandas.DataFrame
    The averaged profiles of every subject, stacked (columns of
    :data:`lineload.averaging.AVERAGED_COLUMNS`).
forces : pandas.DataFrame or None
    The optional force readings (``subject``, ``depth_mm``, ``force_N``); only the
    claims that need them (:data:`FORCE_CLAIMS`) take them.
"""

from lineload.claims.registry import (
    CLAIM_IDS,
    CLAIM_KINDS,
    CLAIM_TEXT,
    CLAIMS,
    FORCE_CLAIMS,
    claim_named,
    claims_using,
)
from lineload.claims.settings import ClaimSettings, judged_settings
from lineload.claims.statistics import (
    asymmetry_excess,
    chord_curvature,
    deformed_extent_mm,
    deformed_extent_se_mm,
    waterbed_zero_crossing_mm,
)
from lineload.claims.summary import summary_sentence, verdict_counts
from lineload.claims.table import CLAIM_FUNCTIONS, claims_markdown, compute_claims
from lineload.claims.trials import trial_key
from lineload.claims.verdicts import (
    CLAIM_COLUMNS,
    EVIDENCE_VERDICTS,
    FAILS,
    HOLDS,
    IDENTITY,
    LATER_WORK,
    MARGIN_GRID,
    PAPER_CLAIM,
    PAPER_SUGGESTION,
    UNTESTABLE,
    VERDICTS,
    InternalError,
)

__all__ = [
    "CLAIMS",
    "CLAIM_COLUMNS",
    "CLAIM_FUNCTIONS",
    "CLAIM_IDS",
    "CLAIM_KINDS",
    "CLAIM_TEXT",
    "EVIDENCE_VERDICTS",
    "FAILS",
    "FORCE_CLAIMS",
    "HOLDS",
    "IDENTITY",
    "LATER_WORK",
    "MARGIN_GRID",
    "PAPER_CLAIM",
    "PAPER_SUGGESTION",
    "UNTESTABLE",
    "VERDICTS",
    "ClaimSettings",
    "InternalError",
    "asymmetry_excess",
    "chord_curvature",
    "claim_named",
    "claims_markdown",
    "claims_using",
    "compute_claims",
    "deformed_extent_mm",
    "deformed_extent_se_mm",
    "judged_settings",
    "summary_sentence",
    "trial_key",
    "verdict_counts",
    "waterbed_zero_crossing_mm",
]
