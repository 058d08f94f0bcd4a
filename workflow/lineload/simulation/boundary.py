"""The boundary worlds: each claim's rule where it has the least power.

The reconstruction's own world tells how often a rule errs where the truth is far
from the claim's boundary.  A test's error rate is defined at the boundary: a
world that changes the true profiles along one direction (the effect ``t``) until
the claim just stops being true.  The boundary is found on the error-free
readings, by bisection between an effect where the claim holds and one where it
does not; the study then reads that world with fresh errors
(:func:`lineload.simulation.verdicts.verdict_study`) and counts how often the rule
still says "holds" (wrong: the claim is false there, if only just), and how often
"does not hold" where it just holds.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from lineload.claims import FAILS, HOLDS, IDENTITY, UNTESTABLE
from lineload.simulation.rates import binomial_interval
from lineload.simulation.subjects import shipped_subjects
from lineload.simulation.verdicts import reconstruction_claims, verdict_study

__all__ = [
    "BOUNDARY_COLUMNS",
    "BOUNDARY_SUMMARY_COLUMNS",
    "BOUNDARY_WORLDS",
    "SIDES",
    "boundary_effect",
    "boundary_study",
    "summarise_boundary",
]


def _changed(subjects, change):
    return [replace(s, **change(s)) if change(s) else s for s in subjects]


def _extents_scaled(t, chosen):
    """The shipped fingers, the deformed region of each ``chosen`` one ``t`` times as wide."""
    return _changed(
        shipped_subjects(),
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
        shipped_subjects(),
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
        shipped_subjects(),
        lambda s: {
            "near_fraction_shallow": s.near_fraction_shallow
            + t * (NEAR_WEIGHT_SHARP - s.near_fraction_shallow),
            "near_fraction_deep": s.near_fraction_deep
            + t * (NEAR_WEIGHT_SHARP - s.near_fraction_deep),
        },
    )


def _toward_circles(t):
    """C10: every profile ``t`` of the way to the circle through its depth and edge."""
    return _changed(shipped_subjects(), lambda s: {"circle_fraction": t})


def _toward_waterbed(t):
    """C8, C9: every profile ``t`` of the way (in its shape parameters) to the waterbed's.

    ``t = 0``: the shipped shapes; ``t = 1``: every trial is eq. 19 itself,
    ``W0 (1 - x / L)(1 - 3 x / L)`` with ``L = 3 e`` up to its zero at ``e``
    (exponent 2, near-field power 1 with weight 2/3, sides alike), which the
    paper's procedure fits without misfit at every depth.
    """
    return _changed(
        shipped_subjects(),
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
        shipped_subjects(),
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
