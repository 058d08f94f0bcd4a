"""The claims table: every claim of the registry judged on one dataset, the verdicts
counted, and the table as Markdown."""

from __future__ import annotations

import pandas as pd

from lineload.claims.registry import CLAIMS, check_claims, claim_function
from lineload.claims.settings import ClaimSettings
from lineload.claims.summary import summary_sentence, verdict_counts
from lineload.claims.verdicts import (
    CLAIM_COLUMNS,
    NO_MARGIN,
    PAPER_CLAIM,
)
from lineload.publishing.tables import markdown_table, notice_footer

__all__ = [
    "CLAIM_FUNCTIONS",
    "claims_markdown",
    "compute_claims",
    "summary_sentence",
    "verdict_counts",
]


#: Claim id -> its function, from the registry; importing this module refuses a
#: registry whose entries do not all have one (:func:`check_claims`).
check_claims(CLAIMS)
CLAIM_FUNCTIONS = {claim.id: claim_function(claim) for claim in CLAIMS}


def compute_claims(fits, averaged, settings=None, forces=None):
    """The claims table: one row per claim of the registry, each verdict from its stated rule.

    Parameters
    ----------
    fits : pandas.DataFrame
        Fit table (one row per subject and depth).
    averaged : pandas.DataFrame
        Averaged profiles of the subjects in ``fits``, stacked.
    settings : ClaimSettings, optional
        Thresholds of the rules; defaults as in the config schema.
    forces : pandas.DataFrame, optional
        Force readings (``subject``, ``depth_mm``, ``force_N``) for the claims that
        need them (C11); None when the dataset has none (C11 then uses the shapes
        alone).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`CLAIM_COLUMNS`, one row per claim in the registry's order.
    """
    settings = settings or ClaimSettings()
    rows = [
        CLAIM_FUNCTIONS[claim.id](
            fits, averaged, settings, **({"forces": forces} if "forces" in claim.needs else {})
        )
        for claim in CLAIMS
    ]
    return pd.DataFrame(rows, columns=CLAIM_COLUMNS)


def claims_markdown(claims, notice="", error_rates=None):
    """The claims table as Markdown: a table of verdicts, the rule of each claim, and
    how often each rule was wrong in the calibration.

    Parameters
    ----------
    claims : pandas.DataFrame
        Output of :func:`compute_claims`.
    notice : str, optional
        Data notice; when non-empty it is added as a footer line.
    error_rates : dict, optional
        Claim -> sentence, from :func:`lineload.simulation.calibration.claim_error_rates`
        (the calibration kept in ``docs/calibration/``); no section if None.

    Returns
    -------
    str
    """
    headers = [
        "Claim",
        "Kind",
        "Statement",
        "Where in the paper",
        "Paper",
        "Ours",
        "Verdict",
        "Reason",
    ]
    rows = [
        [
            r["claim"],
            r.get("kind", PAPER_CLAIM),
            r["statement"],
            r["paper_location"],
            r["paper_value"],
            r["our_value"],
            f"**{r['verdict']}**"
            + (
                f" (holds from a margin of {r['smallest_margin']})"
                if r.get("smallest_margin") not in (None, "", NO_MARGIN)
                else " (at no margin up to 20 %)"
                if r.get("smallest_margin") == NO_MARGIN
                else ""
            ),
            r["reason"],
        ]
        for _, r in claims.iterrows()
    ]
    text = (
        "# Claims of Srinivasan (1989), recomputed\n\n"
        "Each verdict comes from applying the rule below to numbers computed from the data "
        "this table was built from; it describes those data, not the paper's fingertips. "
        "Only the paper's claims about fingers (kind 'paper claim') are counted as evidence; "
        "a property or identity of the paper's method, and a check of the model's "
        "consistency, are checked and reported apart. The equivalence margins are the "
        "workflow's own (config claims: symmetry_margin, shift_margin, circularity_margin); "
        "beside each such verdict, the smallest margin of 1-20 % at which the claim holds. "
        f"{summary_sentence(claims)}\n\n"
    )
    text += markdown_table(headers, rows, "llllllll")
    text += "\n## Rules\n\n"
    text += "".join(
        f"- **{r['claim']}**: {' '.join(r['rule'].split())}\n" for _, r in claims.iterrows()
    )
    if error_rates:
        text += (
            "\n## How often each rule is wrong\n\n"
            "Measured by `snakemake calibration` (kept in `docs/calibration/`) on the "
            "synthetic reconstruction's design: its seven fingers and reading grids, read "
            "again and again with fresh digitising errors, in its own world and in worlds "
            "either side of a claim's boundary, where it just holds and where it just "
            "fails. The rates hold for other data as far as their "
            "design and noise resemble it.\n\n"
        )
        text += "".join(
            f"- **{claim}**: {error_rates[claim]}.\n"
            for claim in claims["claim"]
            if claim in error_rates
        )
    return text + notice_footer(notice)
