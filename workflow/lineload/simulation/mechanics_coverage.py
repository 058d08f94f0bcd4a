"""Coverage of the membrane's intervals on reconstructions with fresh errors.

The forces of the reconstruction come from a membrane under tension at rest, N0 and E
known for each finger.  Each dataset of the verdict study (the same seeds) goes through
the mechanics as rule ``mechanics`` runs it: its fitted arc L with their intervals, the
forces with their noise, the stated error of one force reading.  The interval
estimate +- 1.96 standard errors should hold the truth in 95 % of subjects.

A recovery check, not evidence about fingers: the forces are made by the very law the
fit inverts (:func:`lineload.simulation.readings.trial_forces`), so coverage here shows
that the arithmetic and its intervals return the constants they were made with; forces
from another law are not simulated.
"""

from __future__ import annotations

import math
import statistics

from lineload.mechanics import mechanics_tables
from lineload.simulation.rates import binomial_interval
from lineload.simulation.readings import force_table
from lineload.simulation.subjects import shipped_subjects
from lineload.simulation.verdicts import reconstruction_fits

__all__ = [
    "MECHANICS_COLUMNS",
    "MECHANICS_SUMMARY_COLUMNS",
    "RECOVERY_COLUMNS",
    "RECOVERY_SUMMARY_COLUMNS",
    "RECOVERY_WORLDS",
    "STIFFENING",
    "mechanics_study",
    "recovery_study",
    "summarise_mechanics",
    "summarise_recovery",
]

#: Strain-stiffening of the membrane in the world whose forces come from a law other
#: than the one inverted: ``N = N0 + E (exp(b eps) - 1) / b`` with this ``b``, so the
#: tangent stiffness doubles at a strain of ln 2 / b = 3.5 %, about the strain of the
#: arc at 2 mm (skin stiffens as it stretches; a stated size, not a measurement).
STIFFENING = 20.0
#: The worlds of the recovery check: (name, stiffening).
RECOVERY_WORLDS = (
    ("linear membrane (the law the fit inverts)", 0.0),
    ("strain-stiffening membrane (another law)", STIFFENING),
)

#: Per subject and parameter: the estimate, its standard error, the truth, covered or not.
MECHANICS_COLUMNS = [
    "dataset",
    "subject",
    "n_depths",
    "parameter",
    "estimate",
    "se",
    "truth",
    "covered",
]
#: Per parameter and kind of fit: how often the 95 % interval held the truth.
MECHANICS_SUMMARY_COLUMNS = ["parameter", "fit", "n", "n_covered", "coverage", "ci_low", "ci_high"]
#: Columns of the recovery check's rows (the world, then :data:`MECHANICS_COLUMNS`) and
#: summary (per world and parameter, with the median of estimate / truth).
RECOVERY_COLUMNS = ["world", "stiffening", *MECHANICS_COLUMNS]
RECOVERY_SUMMARY_COLUMNS = [
    "world",
    "stiffening",
    "parameter",
    "n",
    "n_covered",
    "coverage",
    "ci_low",
    "ci_high",
    "median_ratio",
]

#: Each parameter's columns in the mechanics table and its true value on a finger.
_MEMBRANE = {
    "pretension_N_per_mm": ("pretension_se_N_per_mm", lambda s: s.pretension_N_per_mm),
    "stiffness_N_per_mm": ("stiffness_se_N_per_mm", lambda s: s.stiffness_N_per_mm),
    "prestrain": ("prestrain_se", lambda s: s.prestrain),
}


def mechanics_study(
    seed, datasets, window_mm, priors, max_trials, force_sd_N, first=0, stiffening=0.0
):
    """Coverage of the membrane's N0, E and pre-strain on reconstructions with fresh errors.

    Parameters
    ----------
    seed, datasets, window_mm, priors, max_trials, first
        As for :func:`lineload.simulation.verdicts.verdict_study` (dataset ``k`` has
        the errors of its dataset ``k``).
    force_sd_N : float
        Config ``mechanics: force_sd_N``, the stated error of one force reading.
    stiffening : float, optional
        0: forces from the linear law the fit inverts; otherwise from a strain-stiffening
        membrane (:func:`lineload.simulation.readings.trial_forces`), whose truth is its
        tension and tangent stiffness at rest.

    Returns
    -------
    list of dict
        Columns :data:`MECHANICS_COLUMNS`.
    """
    subjects = shipped_subjects()
    by_id = {s.subject: s for s in subjects}
    lengths = {s.subject: s.contact_length_mm for s in subjects}
    rows = []
    for k in range(first, first + datasets):
        fits, *_ = reconstruction_fits(subjects, (seed, k), window_mm, priors, max_trials)
        forces = force_table(subjects, (seed, k), stiffening=stiffening)
        table, _ = mechanics_tables(fits, forces, lengths, force_sd_N)
        for _, row in table.iterrows():
            subject = by_id[str(row["subject"])]
            for parameter, (se_column, truth_of) in _MEMBRANE.items():
                estimate, se, truth = (
                    float(row[parameter]),
                    float(row[se_column]),
                    truth_of(subject),
                )
                rows.append(
                    {
                        "dataset": k,
                        "subject": subject.subject,
                        "n_depths": int(row["n_depths"]),
                        "parameter": parameter,
                        "estimate": estimate,
                        "se": se,
                        "truth": truth,
                        "covered": bool(abs(estimate - truth) <= 1.96 * se),
                    }
                )
    return rows


def summarise_mechanics(rows):
    """Coverage per parameter: over every subject, over-determined fits, exact ones."""
    rows = list(rows)
    summary = []
    for parameter in _MEMBRANE:
        for fit, keep in (
            ("all", lambda r: True),
            ("three or more depths", lambda r: r["n_depths"] > 2),
            ("two depths (exact)", lambda r: r["n_depths"] == 2),
        ):
            group = [r for r in rows if r["parameter"] == parameter and keep(r)]
            if not group:
                continue
            n, covered = len(group), sum(bool(r["covered"]) for r in group)
            low, high = binomial_interval(covered, n)
            summary.append(
                {
                    "parameter": parameter,
                    "fit": fit,
                    "n": n,
                    "n_covered": covered,
                    "coverage": covered / n,
                    "ci_low": low,
                    "ci_high": high,
                }
            )
    return summary


def recovery_study(seed, datasets, window_mm, priors, max_trials, force_sd_N):
    """N0, E and pre-strain recovered from forces of each world of :data:`RECOVERY_WORLDS`.

    The same datasets (seeds ``(seed, k)``) in every world; only the force law differs.
    The truth is the membrane's tension and tangent stiffness at rest.

    Returns
    -------
    list of dict
        Columns :data:`RECOVERY_COLUMNS`.
    """
    rows = []
    for world, stiffening in RECOVERY_WORLDS:
        for row in mechanics_study(
            seed, datasets, window_mm, priors, max_trials, force_sd_N, stiffening=stiffening
        ):
            rows.append({"world": world, "stiffening": stiffening, **row})
    return rows


def summarise_recovery(rows):
    """Per world and parameter: how often the interval held the truth, and the median of
    estimate / truth over the subjects.

    Returns
    -------
    list of dict
        Columns :data:`RECOVERY_SUMMARY_COLUMNS`.
    """
    rows = list(rows)
    summary = []
    for world, stiffening in dict.fromkeys((r["world"], r["stiffening"]) for r in rows):
        for parameter in _MEMBRANE:
            group = [r for r in rows if r["world"] == world and r["parameter"] == parameter]
            if not group:
                continue
            n, covered = len(group), sum(bool(r["covered"]) for r in group)
            low, high = binomial_interval(covered, n)
            ratios = [r["estimate"] / r["truth"] for r in group if r["truth"]]
            summary.append(
                {
                    "world": world,
                    "stiffening": stiffening,
                    "parameter": parameter,
                    "n": n,
                    "n_covered": covered,
                    "coverage": covered / n,
                    "ci_low": low,
                    "ci_high": high,
                    "median_ratio": statistics.median(ratios) if ratios else math.nan,
                }
            )
    return summary
