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

from dataclasses import replace

import numpy as np
import pandas as pd

from lineload.averaging import average_subjects, tissue_columns
from lineload.claims import (
    CLAIM_KINDS,
    CLAIMS,
    EVIDENCE_VERDICTS,
    FAILS,
    HOLDS,
    IDENTITY,
    PAPER_CLAIM,
    UNTESTABLE,
    ClaimSettings,
    compute_claims,
)
from lineload.fitting.batch import fit_trials
from lineload.mechanics import mechanics_tables
from lineload.noise import estimate_noise, model_from_rows, noise_rows, trial_differences
from lineload.simulation import synthetic
from lineload.simulation.coverage import TRUE_NOISE, binomial_interval, percent_interval

__all__ = [
    "BOUNDARY_COLUMNS",
    "BOUNDARY_SUMMARY_COLUMNS",
    "BOUNDARY_WORLDS",
    "DATASET_COLUMNS",
    "MECHANICS_COLUMNS",
    "MECHANICS_SUMMARY_COLUMNS",
    "SUMMARY_COLUMNS",
    "TRUTH_SCALE",
    "UNCALIBRATED_CLAIMS",
    "boundary_effect",
    "boundary_markdown",
    "boundary_study",
    "claim_error_rates",
    "mechanics_markdown",
    "mechanics_study",
    "reconstruction_claims",
    "summarise_boundary",
    "summarise_mechanics",
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

#: Claims the calibration does not judge: those that need the bending skin's fits (C13),
#: which the reconstructions analysed in memory here do not make (their error rates are
#: not yet measured; the claims table and the article say "not calibrated").
UNCALIBRATED_CLAIMS = tuple(claim.id for claim in CLAIMS if "bending" in claim.needs)


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


def _reconstruction_fits(subjects, seed, window_mm, priors, max_trials, errors=True):
    """One dataset of ``subjects`` read, averaged, its noise measured and fitted.

    Returns
    -------
    tuple
        ``(fits, averaged, noise)``: the fit table (a DataFrame, as rule
        ``fit_models`` writes it), the averaged columns and the noise model
        (the generator's times :data:`TRUTH_SCALE` without errors).
    """
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
    return fits, averaged, noise


def reconstruction_claims(
    seed, window_mm, priors, max_trials, claims=None, errors=True, subjects=None
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

    Returns
    -------
    pandas.DataFrame
        The claims table (columns of :data:`lineload.claims.CLAIM_COLUMNS`).
    """
    subjects = synthetic.shipped_subjects() if subjects is None else subjects
    settings = dict(claims or {})
    if not errors:
        settings["noise_mm"] = None
        settings["force_sd_N"] = TRUTH_SCALE * ClaimSettings(**settings).force_sd_N
    fits, averaged, noise = _reconstruction_fits(
        subjects, seed, window_mm, priors, max_trials, errors
    )
    forces = synthetic.force_table(subjects, seed, errors=errors)
    claims = compute_claims(
        fits, pd.DataFrame(averaged), ClaimSettings(**settings, noise_model=noise), forces=forces
    )
    # the reconstructions do not fit the bending skin: its claim is not calibrated here
    return claims[~claims["claim"].isin(UNCALIBRATED_CLAIMS)].reset_index(drop=True)


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

    Returns
    -------
    list of dict
        Columns :data:`DATASET_COLUMNS`.
    """
    rows = []
    for k in range(first, first + datasets):
        read = reconstruction_claims(
            (seed, k), window_mm, priors, max_trials, claims, subjects=subjects
        )
        true = reconstruction_claims(
            (seed, k),
            window_mm,
            priors,
            max_trials,
            claims if truth_claims is None else truth_claims,
            False,
            subjects,
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


#: The columns both calibration tables give each claim and truth.
_COUNT_HEADER = [
    "true verdict",
    "datasets",
    "holds",
    "does not hold",
    "cannot be checked",
    "wrong (95 % CI)",
]


def _percent_interval(row):
    return percent_interval(row["wrong_rate"], row["wrong_ci_low"], row["wrong_ci_high"])


def verdict_markdown(summary, command, notice=""):
    """The verdict calibration as a Markdown table with the command that made it."""
    from lineload.publishing.tables import markdown_table

    header = ["claim", *_COUNT_HEADER]
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
    evidence = len(
        {
            r["claim"]
            for r in summary[:-1]
            if r["truth"] in EVIDENCE_VERDICTS
            and CLAIM_KINDS.get(r["claim"], PAPER_CLAIM) == PAPER_CLAIM
        }
    )
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
        + f"\n\nAcross the paper's {evidence} claims that are evidence about fingers (the "
        "checks of the method and the model apart), "
        f"{every['n_wrong']} of "
        f"{every['n_datasets']} datasets had at least one wrong verdict "
        f"({_percent_interval(every)}): each rule keeps its own error rate, none is "
        "corrected for the others.\n\n"
        "Only the reconstruction's own world is simulated. Where its truth is always "
        f"'holds' ({', '.join(never_fails) or 'none'}), the table measures false 'does not "
        "hold' verdicts only; where always 'does not hold' "
        f"({', '.join(never_holds) or 'none'}), false 'holds' only. Where a rule's power is "
        "least, at its claim's boundary, boundary.md measures it in worlds built for the "
        "purpose.\n\n"
        f"Made by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text


# --- Boundary worlds: each claim where its rule has the least power ------------------
#
# The reconstruction's own world tells how often a rule errs where the truth is far
# from the claim's boundary.  A test's error rate is defined at the boundary: a
# world that changes the true profiles along one direction (the effect ``t``) until
# the claim just stops being true.  The boundary is found on the error-free
# readings, by bisection between an effect where the claim holds and one where it
# does not; the study then reads that world with fresh errors and counts how often
# the rule still says "holds" (wrong: the claim is false there, if only just).


def _changed(subjects, change):
    return [replace(s, **change(s)) if change(s) else s for s in subjects]


def _extents_scaled(t, chosen):
    """The shipped fingers, the deformed region of each ``chosen`` one ``t`` times as wide."""
    return _changed(
        synthetic.shipped_subjects(),
        lambda s: (
            {"extent_shallow_mm": t * s.extent_shallow_mm, "extent_deep_mm": t * s.extent_deep_mm}
            if chosen(s)
            else None
        ),
    )


def _human_extents(t):
    """C1: every human's deformed region ``t`` times as wide (1: the shipped humans)."""
    return _extents_scaled(t, lambda s: s.species == "human")


def _side_asymmetry(t):
    """C2: the second monkey's sides unequal, its left edge ``1 + t`` times the mean."""
    return _changed(
        synthetic.shipped_subjects(),
        lambda s: {"side_asymmetry": t} if s.subject == "M2" else None,
    )


def _wider_h3(t):
    """C5: the third human's deformed region ``t`` times as wide (its L grows with it)."""
    return _extents_scaled(t, lambda s: s.subject == "H3")


def _all_narrower(t):
    """C6: every finger's deformed region ``t`` times as wide (deeper for its width)."""
    return _extents_scaled(t, lambda s: True)


#: Weight of the near-field term towards which the C3 world moves every profile: most
#: of the drop right at the wedge, as the logarithm of the Boussinesq form has it.
NEAR_WEIGHT_SHARP = 0.9


def _sharper_near_wedge(t):
    """C3: every profile's near-field weight ``t`` of the way to :data:`NEAR_WEIGHT_SHARP`."""
    return _changed(
        synthetic.shipped_subjects(),
        lambda s: {
            "near_fraction_shallow": s.near_fraction_shallow
            + t * (NEAR_WEIGHT_SHARP - s.near_fraction_shallow),
            "near_fraction_deep": s.near_fraction_deep
            + t * (NEAR_WEIGHT_SHARP - s.near_fraction_deep),
        },
    )


def _toward_circles(t):
    """C10: every profile ``t`` of the way to the circle through its depth and edge."""
    return _changed(synthetic.shipped_subjects(), lambda s: {"circle_fraction": t})


def _toward_waterbed(t):
    """C8, C9: every profile ``t`` of the way (in its shape parameters) to the waterbed's.

    ``t = 0``: the shipped shapes; ``t = 1``: every trial is eq. 19 itself,
    ``W0 (1 - x / L)(1 - 3 x / L)`` with ``L = 3 e`` up to its zero at ``e``
    (exponent 2, near-field power 1 with weight 2/3, sides alike), which the
    paper's procedure fits without misfit at every depth.
    """
    return _changed(
        synthetic.shipped_subjects(),
        lambda s: {
            "exponent_shallow": s.exponent_shallow + t * (2.0 - s.exponent_shallow),
            "exponent_deep": s.exponent_deep + t * (2.0 - s.exponent_deep),
            "near_fraction_shallow": t * 2.0 / 3.0,
            "near_fraction_deep": s.near_fraction_deep + t * (2.0 / 3.0 - s.near_fraction_deep),
            "near_exponent": s.near_exponent + t * (1.0 - s.near_exponent),
            "side_asymmetry": (1.0 - t) * s.side_asymmetry,
        },
    )


def _one_shape(t):
    """C8: every finger's deep profile ``t`` of the way to its shallow one's shape.

    ``t = 1``: one shape at every depth (``w = W0 f(x / e)``, the edge ``e`` still
    widening with depth): the waterbed's misfit then grows as W0 and its misfit
    relative to the depth stays, but for what the fixed fit window sees of the wider
    deep profiles.
    """
    return _changed(
        synthetic.shipped_subjects(),
        lambda s: {
            "exponent_deep": s.exponent_deep + t * (s.exponent_shallow - s.exponent_deep),
            "near_fraction_deep": s.near_fraction_deep
            + t * (s.near_fraction_shallow - s.near_fraction_deep),
        },
    )


#: World name -> (claim, what changes, family of subjects, (effect where the claim
#: holds, effect where it does not), claim settings of the error-free verdicts that
#: place the boundary).  C8's world moves every finger towards one shape at every depth,
#: where the waterbed's misfit grows as W0 but not relative to it.  C8's rule tests a
#: mean over seven subjects against their own spread, which remains without
#: digitising errors: its boundary is where that mean slope is zero, the error-free
#: verdict at significance 0.5 (holds exactly when the estimate is above zero), not
#: where the seven subjects' t-test stops rejecting.
#: C10's world starts where the claim fails (the shipped shapes) and moves towards
#: circles, where it holds; its effect runs from 1 (circles) down.  Claims without a
#: world: C4 (no shape of the generator's family bulges above the resting surface),
#: C7 (an identity) and C11 (the forces come from a membrane under tension at rest,
#: which the force part of the rule rejects as stress-free whatever the shapes).
BOUNDARY_WORLDS = {
    "humans-narrower": (
        "C1",
        "every human's deformed region narrowed by the factor t",
        _human_extents,
        (1.0, 0.5),
        {},
    ),
    "sides-unequal": (
        "C2",
        "the second monkey's left edge (1 + t) and right edge (1 - t) times their mean",
        _side_asymmetry,
        (-0.03, -0.4),
        {},
    ),
    "boussinesq-nearer": (
        "C3",
        "every profile's near-wedge term t of the way to 90 % of the depth",
        _sharper_near_wedge,
        (0.0, 0.5),
        {},
    ),
    "h3-wider": (
        "C5",
        "the third human's deformed region widened by the factor t",
        _wider_h3,
        (1.0, 1.6),
        {},
    ),
    "deeper-for-width": (
        "C6",
        "every finger's deformed region narrowed by the factor t",
        _all_narrower,
        (1.0, 0.4),
        {},
    ),
    "one-shape-at-every-depth": (
        "C8",
        "every finger's deep profile t of the way to its shallow profile's shape",
        _one_shape,
        (0.0, 1.0),
        {"significance": 0.5},
    ),
    "readings-on-the-curve": (
        "C9",
        "every profile's shape parameters t of the way to the waterbed's eq. 19",
        _toward_waterbed,
        (0.0, 1.0),
        {},
    ),
    "nearly-circles": (
        "C10",
        "every profile t of the way to the circle through its depth meeting its edge flat",
        _toward_circles,
        (1.0, 0.0),
        {},
    ),
}

#: The two planned worlds of each boundary: the ends of the last bisection bracket,
#: where the claim just holds and where it just fails on dataset 0's reading grid.
SIDES = ("holding", "failing")

#: Columns of the boundary study: one row per world, side and dataset.  ``wrong_holds``:
#: the rule says "holds" where the claim is not true; ``wrong_fails``: it says "does not
#: hold" where the claim is not false.
BOUNDARY_COLUMNS = [
    "world",
    "side",
    "effect",
    "dataset",
    "claim",
    "truth",
    "verdict",
    "wrong_holds",
    "wrong_fails",
]
#: Columns of its summary: one row per world, side and true verdict, both errors with
#: their Clopper-Pearson 95 % intervals.
BOUNDARY_SUMMARY_COLUMNS = [
    "world",
    "side",
    "effect",
    "claim",
    "truth",
    "n_datasets",
    "n_holds",
    "n_fails",
    "n_untestable",
    "n_wrong_holds",
    "wrong_holds_rate",
    "wrong_holds_ci_low",
    "wrong_holds_ci_high",
    "n_wrong_fails",
    "wrong_fails_rate",
    "wrong_fails_ci_low",
    "wrong_fails_ci_high",
]


def _true_verdict(claim, effect, family, seed, window_mm, priors, max_trials, claims):
    table = reconstruction_claims(
        seed, window_mm, priors, max_trials, claims, errors=False, subjects=family(effect)
    )
    return dict(zip(table["claim"], table["verdict"], strict=True))[claim]


def boundary_effect(world, seed, window_mm, priors, max_trials, claims=None, steps=12):
    """The effects either side of where a world's claim stops being true, on error-free
    readings.

    Parameters
    ----------
    world : str
        A key of :data:`BOUNDARY_WORLDS`.
    seed : int or tuple of int
        Generator seed whose reading grid the error-free readings use.
    window_mm, priors, max_trials, claims
        As for :func:`reconstruction_claims`.
    steps : int, optional
        Bisection steps: the effect is found to ``2**-steps`` of the bracket.

    Returns
    -------
    tuple of float
        ``(holding, failing)``: the ends of the last bisection bracket, the effect
        nearest the boundary at which the claim's true verdict is "holds" and the one
        at which it is not.

    Raises
    ------
    ValueError
        If the world's two ends do not bracket the boundary (the claim holds at
        the first and does not at the second).
    """
    claim, _, family, (holds_at, fails_at), placing = BOUNDARY_WORLDS[world]
    settings = {**(claims or {}), **placing}

    def truth(effect):
        return _true_verdict(claim, effect, family, seed, window_mm, priors, max_trials, settings)

    ends = truth(holds_at), truth(fails_at)
    if ends[0] != HOLDS or ends[1] == HOLDS:
        raise ValueError(
            f"world {world}: {claim} should hold at t = {holds_at} and not at t = "
            f"{fails_at}; error-free verdicts were {ends[0]!r} and {ends[1]!r}"
        )
    for _ in range(steps):
        middle = 0.5 * (holds_at + fails_at)
        if truth(middle) == HOLDS:
            holds_at = middle
        else:
            fails_at = middle
    return holds_at, fails_at


def boundary_study(
    world, seed, datasets, window_mm, priors, max_trials, claims=None, first=0, sides=SIDES
):
    """The verdicts of a world's claim either side of its boundary, on datasets with
    fresh errors.

    The boundary is found on dataset 0's reading grid (:func:`boundary_effect`); each
    side's world is then read ``datasets`` times, dataset ``k`` with the errors of
    dataset ``k`` of :func:`verdict_study` (seed ``(seed, k)``) and its own error-free
    verdict as ``truth``.  Both errors are scored: "holds" where the truth is not
    "holds" (mostly on the failing side), "does not hold" where the truth is not "does
    not hold" (mostly on the holding side).

    Returns
    -------
    list of dict
        Columns :data:`BOUNDARY_COLUMNS`.
    """
    claim, _, family, _, placing = BOUNDARY_WORLDS[world]
    effects = dict(
        zip(
            SIDES,
            boundary_effect(world, (seed, 0), window_mm, priors, max_trials, claims),
            strict=True,
        )
    )
    out = []
    for side in sides:
        # each dataset's truth judged as the boundary was placed (C8: the sign of the mean
        # slope), its readings as the workflow judges them
        rows = verdict_study(
            seed,
            datasets,
            window_mm,
            priors,
            max_trials,
            claims,
            first,
            family(effects[side]),
            truth_claims={**(claims or {}), **placing},
        )
        out.extend(
            {
                "world": world,
                "side": side,
                "effect": effects[side],
                "dataset": row["dataset"],
                "claim": row["claim"],
                "truth": row["truth"],
                "verdict": row["verdict"],
                "wrong_holds": row["verdict"] == HOLDS and row["truth"] != HOLDS,
                "wrong_fails": row["verdict"] == FAILS and row["truth"] != FAILS,
            }
            for row in rows
            if row["claim"] == claim
        )
    return out


def _rate(wrong, n, prefix):
    low, high = binomial_interval(wrong, n)
    return {
        f"n_{prefix}": wrong,
        f"{prefix}_rate": wrong / n if n else np.nan,
        f"{prefix}_ci_low": low,
        f"{prefix}_ci_high": high,
    }


def summarise_boundary(rows):
    """Counts of each verdict per world, side and truth, with both wrong-verdict rates.

    Parameters
    ----------
    rows : iterable of dict
        As :func:`boundary_study` gives them, any number of worlds.

    Returns
    -------
    list of dict
        Columns :data:`BOUNDARY_SUMMARY_COLUMNS`, worlds in the order of
        :data:`BOUNDARY_WORLDS`, the holding side first.
    """
    groups = {}
    for row in rows:
        groups.setdefault((row["world"], row["side"], row["truth"]), []).append(row)
    order = {verdict: i for i, verdict in enumerate((HOLDS, FAILS, UNTESTABLE, IDENTITY))}
    worlds = list(BOUNDARY_WORLDS)
    summary = []
    for world, side, truth in sorted(
        groups, key=lambda k: (worlds.index(k[0]), SIDES.index(k[1]), order.get(k[2], 9))
    ):
        group = groups[(world, side, truth)]
        verdicts = [r["verdict"] for r in group]
        n = len(group)
        summary.append(
            {
                "world": world,
                "side": side,
                "effect": group[0]["effect"],
                "claim": group[0]["claim"],
                "truth": truth,
                "n_datasets": n,
                "n_holds": verdicts.count(HOLDS),
                "n_fails": verdicts.count(FAILS),
                "n_untestable": verdicts.count(UNTESTABLE),
                **_rate(sum(bool(r["wrong_holds"]) for r in group), n, "wrong_holds"),
                **_rate(sum(bool(r["wrong_fails"]) for r in group), n, "wrong_fails"),
            }
        )
    return summary


def _wrong_cell(row, prefix):
    """'2: 1.0 % (0.1-3.6 %)': the count of wrong verdicts, their rate and its interval."""
    rate = percent_interval(
        row[f"{prefix}_rate"], row[f"{prefix}_ci_low"], row[f"{prefix}_ci_high"]
    )
    return f"{int(row[f'n_{prefix}'])}: {rate}"


def boundary_markdown(summary, command, notice=""):
    """The boundary study's summary as a Markdown table with the command that made it."""
    from lineload.publishing.tables import markdown_table

    header = [
        "claim",
        "world (effect t)",
        "side",
        "true verdict",
        "datasets",
        "holds",
        "does not hold",
        "cannot be checked",
        "wrong 'holds' (95 % CI)",
        "wrong 'does not hold' (95 % CI)",
    ]
    cells = [
        [
            row["claim"],
            f"{BOUNDARY_WORLDS[row['world']][1]}: t = {row['effect']:.4g}",
            row["side"],
            row["truth"],
            str(row["n_datasets"]),
            str(row["n_holds"]),
            str(row["n_fails"]),
            str(row["n_untestable"]),
            _wrong_cell(row, "wrong_holds"),
            _wrong_cell(row, "wrong_fails"),
        ]
        for row in summary
    ]
    text = (
        "# Verdicts either side of each claim's boundary\n\n"
        "Worlds that change the reconstruction's true profiles along one direction, the "
        "effect t, to the point where a claim just stops being true on error-free "
        "readings (found by bisection on one dataset's reading grid). Two worlds are "
        "planned for each boundary, the two ends of the last bisection step: on the "
        "holding side the claim just holds, on the failing side it just fails. Each is "
        "read the same planned number of times with the fresh errors of the main "
        "calibration's datasets and analysed as the workflow does; each dataset's truth is "
        "the error-free verdict on its own reading grid (a row per truth). Both errors are "
        "counted, with Clopper-Pearson 95 % intervals: 'holds' where the truth is not "
        "'holds', and 'does not hold' where the truth is not 'does not hold'. At the "
        "boundary, where a test's power is least, an honest test at significance 0.05 "
        "makes either error in at most about 5 % of datasets; 'cannot be checked' is not "
        "an error but is counted.\n\n"
        + markdown_table(header, cells, "llllrrrrrr")
        + "\n\nNo world is built for C4 and C11: the generator's family of shapes (a power "
        "of the distance to the edge, a near-field term and a circle) cannot make the skin "
        "bulge above its resting surface, and its forces come from a membrane under "
        "tension at rest, which C11's force test rejects as stress-free whatever the "
        "shapes. C7 is an identity. C6 is a property of the paper's method, reported "
        "apart from the paper's claims.\n\n"
        f"Made by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text


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


# --- Coverage of the membrane's intervals ---------------------------------------------
#
# The forces of the reconstruction come from a membrane under tension at rest, N0 and E
# known for each finger.  Each dataset of the verdict study (the same seeds) goes through
# the mechanics as rule ``mechanics`` runs it: its fitted arc L with their intervals, the
# forces with their noise, the stated error of one force reading.  The interval
# estimate +- 1.96 standard errors should hold the truth in 95 % of subjects.

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

#: Each parameter's columns in the mechanics table and its true value on a finger.
_MEMBRANE = {
    "pretension_N_per_mm": ("pretension_se_N_per_mm", lambda s: s.pretension_N_per_mm),
    "stiffness_N_per_mm": ("stiffness_se_N_per_mm", lambda s: s.stiffness_N_per_mm),
    "prestrain": ("prestrain_se", lambda s: s.prestrain),
}


def mechanics_study(seed, datasets, window_mm, priors, max_trials, force_sd_N, first=0):
    """Coverage of the membrane's N0, E and pre-strain on reconstructions with fresh errors.

    Parameters
    ----------
    seed, datasets, window_mm, priors, max_trials, first
        As for :func:`verdict_study` (dataset ``k`` has the errors of its
        dataset ``k``).
    force_sd_N : float
        Config ``mechanics: force_sd_N``, the stated error of one force reading.

    Returns
    -------
    list of dict
        Columns :data:`MECHANICS_COLUMNS`.
    """
    subjects = synthetic.shipped_subjects()
    by_id = {s.subject: s for s in subjects}
    lengths = {s.subject: s.contact_length_mm for s in subjects}
    rows = []
    for k in range(first, first + datasets):
        fits, _, _ = _reconstruction_fits(subjects, (seed, k), window_mm, priors, max_trials)
        forces = synthetic.force_table(subjects, (seed, k))
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


def mechanics_markdown(summary, command, notice=""):
    """The membrane's coverage as a Markdown table with the command that made it."""
    from lineload.publishing.tables import markdown_table

    cells = [
        [
            row["parameter"],
            row["fit"],
            str(row["n"]),
            str(row["n_covered"]),
            percent_interval(row["coverage"], row["ci_low"], row["ci_high"]),
        ]
        for row in summary
    ]
    header = ["parameter", "fit", "subjects", "covered", "coverage (95 % CI)"]
    text = (
        "# Coverage of the membrane's intervals\n\n"
        "The reconstruction's forces come from a membrane under tension at rest whose N0, E "
        "and pre-strain are known for each finger. Each dataset of the verdict calibration "
        "(the same seeds: fresh digitising errors and force noise) goes through the mechanics "
        "as the workflow runs it: the exact arc's L with its interval, the forces, the stated "
        "error of one force reading (a prior: there are no replicate forces). The interval "
        "estimate ± 1.96 standard errors should hold the truth in 95 % of subjects; "
        "aim 93-97 %.\n\n" + markdown_table(header, cells, "llrrr") + f"\n\nMade by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text
