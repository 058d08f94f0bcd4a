"""Verdict calibration: how often each claim's rule reaches the right verdict.

The claims table (:mod:`lineload.claims`) gives each statement of the paper a
verdict.  A verdict is only worth as much as the rate at which its rule reaches
the right one, so this module measures that rate on datasets whose truth is
known: the seven fingers of the shipped reconstruction (:mod:`lineload.synthetic`)
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
import pandas as pd

from . import synthetic
from .averaging import average_subjects, tissue_columns
from .claims import (
    EVIDENCE_VERDICTS,
    FAILS,
    HOLDS,
    IDENTITY,
    UNTESTABLE,
    ClaimSettings,
    compute_claims,
)
from .coverage import TRUE_NOISE, binomial_interval
from .fitting import fit_trials
from .noise import estimate_noise, model_from_rows, noise_rows, trial_differences

__all__ = [
    "DATASET_COLUMNS",
    "SUMMARY_COLUMNS",
    "TRUTH_SCALE",
    "reconstruction_claims",
    "summarise_verdicts",
    "verdict_markdown",
    "verdict_study",
]

#: Every standard deviation of the noise, and of a force reading, times this when
#: the rules judge the error-free readings: intervals a thousandth of their size.
TRUTH_SCALE = 1e-3

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

#: The opposite of each evidence verdict: saying it when the other is true is wrong.
_OPPOSITE = {HOLDS: FAILS, FAILS: HOLDS}


def _trials_of(averaged):
    """Each trial's rows of the averaged columns, in table order: (subject, depth, slice)."""
    subject = np.asarray(averaged["subject"])
    depth = np.asarray(averaged["depth_mm"], dtype=float)
    new = np.r_[True, (subject[1:] != subject[:-1]) | (depth[1:] != depth[:-1])]
    starts = np.flatnonzero(new)
    ends = np.r_[starts[1:], subject.size]
    return [(subject[a], float(depth[a]), slice(a, b)) for a, b in zip(starts, ends, strict=True)]


def _scaled_noise(scale):
    """The generator's noise with every standard deviation times ``scale``."""
    values = TRUE_NOISE.as_dict()
    return type(TRUE_NOISE)(
        **{k: v if k == "tracing_length_mm" else v * scale for k, v in values.items()}
    )


def reconstruction_claims(seed, window_mm, priors, max_trials, claims=None, errors=True):
    """One dataset of the reconstruction with its own errors, analysed as the workflow does.

    Parameters
    ----------
    seed : int or tuple of int
        Generator seed of the dataset (1989 gives the shipped data).
    window_mm : float
        Fit window (config ``fit_window_mm``).
    priors : dict
        The noise priors (config ``noise``: ``shared_offset_sd_mm``,
        ``shared_tilt_sd``, ``depth_sd_mm``).
    max_trials : int
        Config ``noise: max_trials``.
    claims : dict, optional
        Settings of the claims (config ``claims``); schema defaults if None.
    errors : bool, optional
        False: the true readings on the same grid and the true forces, judged
        with the generator's noise times :data:`TRUTH_SCALE` (nothing measured).

    Returns
    -------
    pandas.DataFrame
        The claims table (columns of :data:`lineload.claims.CLAIM_COLUMNS`).
    """
    subjects = synthetic.shipped_subjects()
    converted = [
        tissue_columns(
            synthetic.profile_table(subject, seed, errors=errors),
            subject.subject,
            synthetic.MAGNIFICATION,
        )
        for subject in subjects
    ]
    averaged = average_subjects(converted)
    trials = _trials_of(averaged)
    columns = {
        name: np.asarray(averaged[name], dtype=float)
        for name in ("distance_mm", "deflection_mm", "left_mm", "right_mm", "n_sides")
    }
    settings = dict(claims or {})
    if errors:
        differences = [
            trial_differences(
                columns["distance_mm"][rows],
                columns["left_mm"][rows],
                columns["right_mm"][rows],
                window_mm,
            )
            for _, _, rows in trials
        ]
        rows = noise_rows(estimate_noise(differences, max_trials=max_trials), priors)
        noise = model_from_rows(rows)
    else:
        noise = _scaled_noise(TRUTH_SCALE)
        settings["noise_mm"] = None
        settings["force_sd_N"] = TRUTH_SCALE * ClaimSettings(**settings).force_sd_N
    fitted = fit_trials(
        [columns["distance_mm"][r] for *_, r in trials],
        [columns["deflection_mm"][r] for *_, r in trials],
        [depth for _, depth, _ in trials],
        window_mm,
        noise=noise,
        n_sides=[columns["n_sides"][r] for *_, r in trials],
    )
    species = {subject.subject: subject.species for subject in subjects}
    fits = pd.DataFrame(
        [
            {"subject": name, "species": species[name], **row}
            for (name, _, _), row in zip(trials, fitted, strict=True)
        ]
    )
    forces = synthetic.force_table(subjects, seed, errors=errors)
    return compute_claims(
        fits, pd.DataFrame(averaged), ClaimSettings(**settings, noise_model=noise), forces=forces
    )


def verdict_study(seed, datasets, window_mm, priors, max_trials, claims=None, first=0):
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

    Returns
    -------
    list of dict
        Columns :data:`DATASET_COLUMNS`.
    """
    rows = []
    for k in range(first, first + datasets):
        read = reconstruction_claims((seed, k), window_mm, priors, max_trials, claims)
        true = reconstruction_claims((seed, k), window_mm, priors, max_trials, claims, False)
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
        wrong verdict among the evidence claims.
    """
    by_claim, wrong_in = {}, {}
    for row in rows:
        by_claim.setdefault((row["claim"], row["truth"]), []).append(row)
        wrong_in[row["dataset"]] = wrong_in.get(row["dataset"], False) or bool(row["wrong"])
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


def _percent_interval(row):
    return (
        f"{100 * row['wrong_rate']:.1f} % "
        f"({100 * row['wrong_ci_low']:.1f}-{100 * row['wrong_ci_high']:.1f} %)"
    )


def verdict_markdown(summary, command, notice=""):
    """The verdict calibration as a Markdown table with the command that made it."""
    from .tables import markdown_table

    header = [
        "claim",
        "true verdict",
        "datasets",
        "holds",
        "does not hold",
        "cannot be checked",
        "wrong (95 % CI)",
    ]
    cells = []
    for row in summary:
        if row["claim"] == "any":
            continue
        if row["truth"] == IDENTITY:
            counts = ["-", "-", "-", "not evidence"]
        else:
            counts = [
                str(row["n_holds"]),
                str(row["n_fails"]),
                str(row["n_untestable"]),
                _percent_interval(row),
            ]
        cells.append([row["claim"], row["truth"], str(row["n_datasets"]), *counts])
    every = summary[-1]
    evidence = len({r["claim"] for r in summary[:-1] if r["truth"] in EVIDENCE_VERDICTS})
    truths = {}
    for r in summary[:-1]:
        truths.setdefault(r["claim"], set()).add(r["truth"])
    never_fails = [claim for claim, found in truths.items() if found == {HOLDS}]
    never_holds = [claim for claim, found in truths.items() if found == {FAILS}]
    text = (
        "# Calibration of the verdicts\n\n"
        "Datasets of the reconstruction: its seven fingers and their true profiles, each "
        "dataset read with a fresh draw of every digitising error and force noise, analysed "
        "as the workflow analyses the shipped data (noise measured, models fitted, claims "
        "judged). The true verdict is what the same rules conclude from the dataset's true "
        "profiles on its own reading grid, without any error and with intervals shrunk to "
        "points; it can differ between datasets, so a claim can have a row for each truth. "
        "A verdict opposite to the truth is wrong; 'cannot be checked' is not wrong, but "
        "counted. Aim: at most 5 % wrong per claim.\n\n"
        + markdown_table(header, cells, "llrrrrr")
        + f"\n\nAcross the {evidence} claims that are evidence, {every['n_wrong']} of "
        f"{every['n_datasets']} datasets had at least one wrong verdict "
        f"({_percent_interval(every)}): each rule keeps its own error rate, none is "
        "corrected for the others.\n\n"
        "Only the reconstruction's own world is simulated. Where its truth is always "
        f"'holds' ({', '.join(never_fails) or 'none'}), the table measures false 'does not "
        "hold' verdicts only; where always 'does not hold' "
        f"({', '.join(never_holds) or 'none'}), false 'holds' only. Datasets built at each "
        "claim's boundary, where a rule's power is least, are not simulated here.\n\n"
        f"Made by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text
