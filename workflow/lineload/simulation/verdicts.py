"""Verdict calibration: how often each claim's rule reaches the right verdict.

The claims table (:mod:`lineload.claims`) gives each statement of the paper a
verdict.  A verdict is only worth as much as the rate at which its rule reaches
the right one, so this module measures that rate on datasets whose truth is
known: the seven fingers of the shipped reconstruction (:mod:`lineload.simulation.synthetic`)
with their true profiles unchanged, each dataset read with a fresh draw of every
digitising error (reading and tracing errors, side and shared offsets, shared
tilt, rotation, depth error, misplaced wedge, force noise).  Every dataset goes
through the workflow's own steps, in memory: readings to tissue mm, the left-right
mean, the noise measured from the left-right differences, the fits of every
model with that noise, and the claims with their rules.

The truth of each claim in each dataset is the verdict the same rules reach on
the same design without any error: the true profiles read on the dataset's own
reading grid (which decides, for instance, how well a logarithm fits next to the
wedge), the true forces, and every uncertainty shrunk a thousandfold
(:data:`TRUTH_SCALE`), so that the intervals close on the true values.  For
each claim the study counts how often the workflow says ``holds``,
``does not hold`` and ``cannot be checked``: a verdict opposite to the truth is
wrong; "cannot be checked" is not wrong but is counted, since a rule that never
commits is no test.  A last row counts the datasets with at least one wrong
verdict, the rate a reader faces when reading the whole table.

Dataset ``k`` of a study seeded ``seed`` is drawn from the generator seed
``(seed, k)``, so any slice reruns alone with the same numbers.
"""

from __future__ import annotations

import numpy as np

from lineload.averaging import tissue_columns
from lineload.claims import (
    CLAIM_KINDS,
    CLAIMS,
    FAILS,
    HOLDS,
    IDENTITY,
    PAPER_CLAIM,
    UNTESTABLE,
)
from lineload.fitting.bending import fit_bending_trials, with_bending
from lineload.simulation.analysis import TRUTH_SCALE, analyse, judged_claims
from lineload.simulation.errors import AS_ASSUMED
from lineload.simulation.rates import binomial_interval
from lineload.simulation.readings import force_table, profile_table
from lineload.simulation.subjects import MAGNIFICATION, shipped_subjects

__all__ = [
    "BENDING_CLAIMS",
    "DATASET_COLUMNS",
    "SCENARIO_DATASET_COLUMNS",
    "SCENARIO_SUMMARY_COLUMNS",
    "SUMMARY_COLUMNS",
    "TRUTH_SCALE",
    "UNCALIBRATED_CLAIMS",
    "reconstruction_claims",
    "reconstruction_fits",
    "summarise_scenario_verdicts",
    "summarise_verdicts",
    "verdict_study",
]


#: Columns of the per-dataset table: one row per dataset and claim.
DATASET_COLUMNS = ["dataset", "claim", "truth", "verdict", "wrong"]

#: Columns of the summary: one row per claim, then ``any`` (a dataset with a wrong verdict).
SUMMARY_COLUMNS = [
    "claim",
    "truth",
    "n_datasets",
    "n_holds",
    "n_fails",
    "n_untestable",
    "n_wrong",
    "wrong_rate",
    "wrong_ci_low",
    "wrong_ci_high",
]

#: Columns of the verdicts in worlds whose errors are not as stated: the world's name,
#: then those of :data:`DATASET_COLUMNS` / :data:`SUMMARY_COLUMNS`; the summary names
#: what the world makes differently and the true/stated size of the priors.
SCENARIO_DATASET_COLUMNS = ["scenario", *DATASET_COLUMNS]
SCENARIO_SUMMARY_COLUMNS = ["scenario", "misspecified", "prior_ratio", *SUMMARY_COLUMNS]

#: The opposite of each evidence verdict: saying it when the other is true is wrong.
_OPPOSITE = {HOLDS: FAILS, FAILS: HOLDS}

#: Claims that need the bending skin's fits (C13): judged when a reconstruction fits the
#: bending skin too (``wall`` given, as the verdict calibration does), left out when it
#: does not (the boundary worlds, none of which is such a claim's, skip its fits: they
#: would double each analysis's time).
BENDING_CLAIMS = tuple(claim.id for claim in CLAIMS if "bending" in claim.needs)
#: Claims the verdict calibration does not judge: those that need the elastic finger's
#: fits, which the reconstructions analysed in memory here do not make (the claims table
#: and the article say "not calibrated"; C12's rates come from its own study,
#: docs/calibration/elastic_layer_margin.md).
UNCALIBRATED_CLAIMS = tuple(claim.id for claim in CLAIMS if "elastic" in claim.needs)


def reconstruction_fits(
    subjects, seed, window_mm, priors, max_trials, errors=True, wall=None, scenario=AS_ASSUMED
):
    """One dataset of ``subjects`` read, averaged, its noise measured and fitted.

    Each step calls what its rule's script calls: ``prepare_profiles``
    (:func:`lineload.averaging.tissue_columns`, :func:`lineload.averaging.average_subjects`),
    ``noise`` (:func:`lineload.noise.measure_noise_table`), ``fit_models``
    (:func:`lineload.noise.trial_models`, :func:`lineload.fitting.batch.fit_trials`) and,
    with ``wall``, ``fit_bending`` (:func:`lineload.fitting.bending.fit_bending_trials`,
    joined as rule ``claims_table`` joins it), in memory: nothing is written or read back.

    ``wall`` is the bending skin's wall condition (config ``bending: wall``); None: the
    bending skin is not fitted (its claims cannot be judged).  ``scenario`` is the world
    the readings' errors are made in (:class:`lineload.simulation.errors.Scenario`); the
    noise is measured and the priors stated (``priors``) as ever, so a scenario whose
    true sizes differ from ``priors`` is a world where the stated priors are wrong.

    Returns
    -------
    tuple
        ``(fits, averaged, noise, trial_noise)``: the fit table (a DataFrame, as rule
        ``fit_models`` writes it), the averaged columns, the dataset's noise model
        (the generator's times :data:`TRUTH_SCALE` without errors) and each trial's
        (list, in the fit table's order).
    """
    converted = [
        tissue_columns(
            profile_table(subject, seed, errors=errors, scenario=scenario),
            subject.subject,
            MAGNIFICATION,
        )
        for subject in subjects
    ]
    species = {subject.subject: subject.species for subject in subjects}
    analysis = analyse(converted, species, window_mm, priors, max_trials, errors)
    fits = analysis.fits
    if wall is not None:
        bending = fit_bending_trials(
            analysis.per_trial("distance_mm"),
            analysis.per_trial("deflection_mm"),
            analysis.depths_mm,
            window_mm,
            noise=analysis.trial_noise,
            n_sides=analysis.per_trial("n_sides"),
            wall=wall,
        )
        fits = with_bending(fits, analysis.labelled(bending))
    return fits, analysis.averaged, analysis.noise, analysis.trial_noise


def reconstruction_claims(
    seed,
    window_mm,
    priors,
    max_trials,
    claims=None,
    errors=True,
    subjects=None,
    wall=None,
    scenario=AS_ASSUMED,
):
    """One dataset of the reconstruction with its own errors, analysed as the workflow does.

    Parameters
    ----------
    seed : int or tuple of int
        Generator seed of the dataset (1989 gives the shipped data).
    window_mm : float
        Fit window (config ``fit_window_mm``).
    priors : dict
        The noise priors (config ``noise``: ``shared_offset_sd_mm``,
        ``shared_tilt_sd``, ``depth_sd_mm``, ``wedge_position_sd_mm``).
    max_trials : int
        Config ``noise: max_trials``.
    claims : dict, optional
        Settings of the claims (config ``claims``); schema defaults if None.
    errors : bool, optional
        False: the true readings on the same grid and the true forces, judged
        with the generator's noise times :data:`TRUTH_SCALE` (nothing measured).
    subjects : list of SubjectParameters, optional
        The fingers' true profiles; the shipped reconstruction's if None (a
        boundary world of :data:`BOUNDARY_WORLDS` changes some of them).
    wall : {"clamped", "pinned"} or None, optional
        The bending skin's walls (config ``bending: wall``): its fits are made and
        its claims (:data:`BENDING_CLAIMS`) judged; None: neither.
    scenario : Scenario, optional
        The world the readings' errors are made in (as for :func:`reconstruction_fits`).

    Returns
    -------
    pandas.DataFrame
        The claims table (columns of :data:`lineload.claims.CLAIM_COLUMNS`).
    """
    subjects = shipped_subjects() if subjects is None else subjects
    fits, averaged, noise, trial_noise = reconstruction_fits(
        subjects, seed, window_mm, priors, max_trials, errors, wall, scenario
    )
    forces = force_table(subjects, seed, errors=errors)
    # as rule claims_table judges them: the dataset's noise and each trial's
    claims = judged_claims(fits, averaged, noise, trial_noise, claims, errors, forces)
    if wall is None:  # the bending skin not fitted: its claims are not judged
        claims = claims[~claims["claim"].isin(BENDING_CLAIMS)]
    # nor those of the elastic finger, whose fits are not made here
    claims = claims[~claims["claim"].isin(UNCALIBRATED_CLAIMS)]
    return claims.reset_index(drop=True)


def verdict_study(
    seed,
    datasets,
    window_mm,
    priors,
    max_trials,
    claims=None,
    first=0,
    subjects=None,
    truth_claims=None,
    wall=None,
    scenario=AS_ASSUMED,
):
    """The verdict of every claim on ``datasets`` reconstructions with fresh errors.

    Parameters
    ----------
    seed : int
        Seed of the study; dataset ``k`` is generated with seed ``(seed, k)``.
    datasets : int
        How many datasets.
    window_mm, priors, max_trials, claims
        As for :func:`reconstruction_claims`.
    first : int, optional
        Number of the first dataset (a slice of a larger study).
    subjects : list of SubjectParameters, optional
        As for :func:`reconstruction_claims`.
    truth_claims : dict, optional
        Settings of the claims for the error-free truth (``claims`` if None): a
        boundary world judges its truth as its boundary was placed.
    wall : {"clamped", "pinned"} or None, optional
        As for :func:`reconstruction_claims`: with it, the bending skin's claims too.
    scenario : Scenario, optional
        The world the readings' errors are made in; the truth is error-free in every one.

    Returns
    -------
    list of dict
        Columns :data:`DATASET_COLUMNS`.
    """
    rows = []
    for k in range(first, first + datasets):
        read = reconstruction_claims(
            (seed, k),
            window_mm,
            priors,
            max_trials,
            claims,
            subjects=subjects,
            wall=wall,
            scenario=scenario,
        )
        true = reconstruction_claims(
            (seed, k),
            window_mm,
            priors,
            max_trials,
            claims if truth_claims is None else truth_claims,
            False,
            subjects,
            wall,
        )
        for claim, verdict, truth in zip(
            read["claim"], read["verdict"], true["verdict"], strict=True
        ):
            rows.append(
                {
                    "dataset": k,
                    "claim": claim,
                    "truth": truth,
                    "verdict": verdict,
                    "wrong": verdict == _OPPOSITE.get(truth),
                }
            )
    return rows


def summarise_verdicts(rows):
    """Counts of each verdict per claim, the wrong-verdict rate and its 95 % interval.

    Parameters
    ----------
    rows : iterable of dict
        As :func:`verdict_study` gives them.

    Returns
    -------
    list of dict
        Columns :data:`SUMMARY_COLUMNS`; one row per claim and true verdict (the
        truth can differ between datasets: it depends on each dataset's reading
        grid), claims in table order, then ``any``: datasets with at least one
        wrong verdict among the paper's claims (kind ``paper claim``; the checks of
        method and model, :data:`lineload.claims.CLAIM_KINDS`, apart).
    """
    by_claim, wrong_in = {}, {}
    for row in rows:
        by_claim.setdefault((row["claim"], row["truth"]), []).append(row)
        counted = CLAIM_KINDS.get(row["claim"], PAPER_CLAIM) == PAPER_CLAIM and bool(row["wrong"])
        wrong_in[row["dataset"]] = wrong_in.get(row["dataset"], False) or counted
    order = {verdict: i for i, verdict in enumerate((HOLDS, FAILS, UNTESTABLE, IDENTITY))}
    claims = list(dict.fromkeys(claim for claim, _ in by_claim))
    keys = sorted(by_claim, key=lambda key: (claims.index(key[0]), order.get(key[1], 9)))
    summary = []
    for claim, truth in keys:
        group = by_claim[(claim, truth)]
        verdicts = [r["verdict"] for r in group]
        n, wrong = len(group), sum(bool(r["wrong"]) for r in group)
        low, high = binomial_interval(wrong, n)
        summary.append(
            {
                "claim": claim,
                "truth": truth,
                "n_datasets": n,
                "n_holds": verdicts.count(HOLDS),
                "n_fails": verdicts.count(FAILS),
                "n_untestable": verdicts.count(UNTESTABLE),
                "n_wrong": wrong,
                "wrong_rate": wrong / n,
                "wrong_ci_low": low,
                "wrong_ci_high": high,
            }
        )
    n, wrong = len(wrong_in), sum(wrong_in.values())
    low, high = binomial_interval(wrong, n)
    summary.append(
        {
            "claim": "any",
            "truth": "",
            "n_datasets": n,
            "n_holds": np.nan,
            "n_fails": np.nan,
            "n_untestable": np.nan,
            "n_wrong": wrong,
            "wrong_rate": wrong / n if n else np.nan,
            "wrong_ci_low": low,
            "wrong_ci_high": high,
        }
    )
    return summary


def summarise_scenario_verdicts(rows, scenarios):
    """:func:`summarise_verdicts` per world whose errors are not as stated.

    Parameters
    ----------
    rows : iterable of dict
        As :func:`verdict_study` gives them, each with its ``scenario``'s name.
    scenarios : sequence of Scenario
        The worlds, in the order of the summary.

    Returns
    -------
    list of dict
        Columns :data:`SCENARIO_SUMMARY_COLUMNS`.
    """
    by_name = {}
    for row in rows:
        by_name.setdefault(row["scenario"], []).append(row)
    summary = []
    for scenario in scenarios:
        if scenario.name not in by_name:
            continue
        for row in summarise_verdicts(by_name[scenario.name]):
            summary.append(
                {
                    "scenario": scenario.name,
                    "misspecified": scenario.misspecified,
                    "prior_ratio": scenario.prior_ratio,
                    **row,
                }
            )
    return summary
