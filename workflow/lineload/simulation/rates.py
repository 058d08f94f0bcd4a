"""Rates from the calibration: binomial intervals and the sentences the claims table prints.

Light on purpose: the claims table and the article read the committed calibration's
numbers through :func:`claim_error_rates` without running (or depending on) the
generator or the studies.
"""

from __future__ import annotations

import math

from lineload.claims import FAILS, HOLDS, IDENTITY, UNTESTABLE

__all__ = ["binomial_interval", "claim_error_rates", "percent_interval"]


def percent_interval(rate, low, high):
    """A rate with its interval, in percent: ``97.1 % (95.9-98.0 %)``."""
    return f"{100 * rate:.1f} % ({100 * low:.1f}-{100 * high:.1f} %)"


def binomial_interval(successes, n, level=0.95):
    """Clopper-Pearson interval of a binomial proportion.

    Parameters
    ----------
    successes, n : int
    level : float, optional

    Returns
    -------
    tuple of float
        ``(low, high)``; ``(nan, nan)`` when ``n`` is 0.
    """
    from scipy.stats import binomtest

    if n == 0:
        return math.nan, math.nan
    interval = binomtest(int(successes), int(n)).proportion_ci(level, method="exact")
    return float(interval.low), float(interval.high)


def claim_error_rates(verdicts, boundary=None):
    """One sentence per claim: how often its rule was wrong in the calibration.

    Parameters
    ----------
    verdicts : pandas.DataFrame
        The verdict calibration's summary (``verdicts.csv``, columns
        :data:`SUMMARY_COLUMNS`).
    boundary : pandas.DataFrame, optional
        The boundary study's summary (``boundary.csv``, columns
        :data:`BOUNDARY_SUMMARY_COLUMNS`).

    Returns
    -------
    dict
        Claim -> sentence, for the claims that are evidence (identities left out).
    """
    rates = {}
    for claim, group in verdicts[verdicts["claim"] != "any"].groupby("claim", sort=False):
        if (group["truth"] == IDENTITY).all():
            continue
        n, wrong = int(group["n_datasets"].sum()), int(group["n_wrong"].sum())
        undecided = int(group["n_untestable"].sum())
        high = binomial_interval(wrong, n)[1]
        if (group["truth"] == UNTESTABLE).all():
            # nothing built in decides the claim (e.g. C13: no bending skin in the
            # reconstruction): no verdict is opposite to the truth, so none is counted
            # wrong; a decided one claims more than the error-free data support
            decided = n - undecided
            rates[str(claim)] = (
                f"its error-free truth is undecided in all {n} reconstructions, so no "
                f"verdict can be counted wrong; with fresh errors the rule decided in "
                f"{decided} of them (95 % upper bound "
                f"{100 * binomial_interval(decided, n)[1]:.1f} %)"
            )
            continue
        if undecided == n:  # no decided verdict: no rate of wrong ones to give
            rates[str(claim)] = (
                f"undecided in every one of {n} reconstructions with fresh errors, so no "
                "error rate can be given"
            )
            continue
        rates[str(claim)] = (
            f"wrong in {wrong} of {n} reconstructions with fresh errors (95 % upper bound "
            f"{100 * high:.1f} %), undecided in {undecided}"
        )
    if boundary is not None:
        for claim, group in boundary.groupby("claim", sort=False):
            parts = []
            for prefix, words, side in (
                ("wrong_holds", "'holds'", "fails"),
                ("wrong_fails", "'does not hold'", "holds"),
            ):
                # the datasets where that verdict is wrong: the truth is not that verdict
                truth = HOLDS if prefix == "wrong_holds" else FAILS
                counted = group[group["truth"] != truth]
                n, wrong = int(counted["n_datasets"].sum()), int(counted[f"n_{prefix}"].sum())
                if n:
                    high = binomial_interval(wrong, n)[1]
                    parts.append(
                        f"where the claim only just {side}, {words} in {wrong} of {n} (95 % "
                        f"upper bound {100 * high:.1f} %)"
                    )
            rates[str(claim)] = "; ".join([rates[str(claim)]] if str(claim) in rates else [])
            rates[str(claim)] = "; ".join(p for p in (rates[str(claim)], *parts) if p)
    return rates
