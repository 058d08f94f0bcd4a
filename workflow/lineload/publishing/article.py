"""What the reproduction article says, computed from the results tables.

The article (``workflow/article/reproduction.typ``, typeset with Typst) holds no
number of its own: every number and every data-dependent phrase in its text comes
from the facts built here out of the workflow's tables, written to
``results/article/facts.json`` beside it.  Numbers arrive as finished text
(fixed decimals, ranges, counts in words where a sentence needs them), so the
article reads the same whatever the dataset, and a reviewer can open the JSON to
see each value the text uses.
"""

from __future__ import annotations

import math

import numpy as np

from lineload import paper
from lineload.claims import EVIDENCE_VERDICTS, PAPER_CLAIM, summary_sentence, verdict_counts
from lineload.claims.registry import NEEDS, SETTINGS, claims_needing, claims_using
from lineload.claims.rows import NAMED_FIGURES
from lineload.priors import changed_claims
from lineload.publishing.formulas import segments
from lineload.publishing.tables import (
    AT_BOUND_MARK,
    at_bound,
    counted,
    every,
    format_fixed,
    join_words,
    percent_text,
    span_text,
)
from lineload.simulation.rates import claim_error_rates

__all__ = [
    "article_facts",
    "bending_facts",
    "calibration_design",
    "counted",
    "counted_words",
    "dataset_design",
    "design_text",
    "elastic_facts",
    "every",
    "group_depths_text",
    "join_words",
    "number_words",
    "percent_text",
    "photograph_facts",
    "shown",
    "span_text",
]

#: Small counts in words, as a sentence would write them.
_WORDS = ("no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten")


def number_words(count):
    """``3`` -> ``"three"`` up to ten, digits beyond."""
    count = int(count)
    return _WORDS[count] if 0 <= count < len(_WORDS) else str(count)


def shown(value):
    """A setting as the text shows it: numbers short (``3``, ``0.01``), lists joined, null
    as ``none``; dicts shown key by key."""
    if isinstance(value, dict):
        return {key: shown(item) for key, item in value.items()}
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return f"{value:g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(shown(item) for item in value)
    return str(value)


def _depths_text(depths_mm):
    return join_words(f"{d:g}" for d in sorted(set(depths_mm))) + " mm"


def group_depths_text(members, depths_mm):
    """The depths most of ``members`` have, then each other set with its subjects.

    ``0.5, 1, 1.5 and 2 mm (H3: 1 and 2 mm)``: a subject measured at fewer depths
    than the rest of its species is named, never folded into the others' depths.
    """
    sets = {}
    for subject in members:
        sets.setdefault(tuple(sorted(set(depths_mm[subject]))), []).append(subject)
    common = max(sets, key=lambda key: len(sets[key]))
    others = [
        f"{join_words(subjects)}: {_depths_text(key)}"
        for key, subjects in sets.items()
        if key != common
    ]
    return _depths_text(common) + (f" ({'; '.join(others)})" if others else "")


def counted_words(count, noun, plural=None):
    """:func:`~lineload.publishing.tables.counted` with a small count in words, as a
    sentence writes it: ``"one subject"``, ``"three monkeys"``, ``"12 trials"``."""
    count = int(count)
    return f"{number_words(count)} {counted(count, noun, plural).split(' ', 1)[1]}"


#: How many photographed subjects' quality figures the article prints (the report has all).
PHOTOGRAPH_FIGURES = 4


def _batch_label(batch, subjects):
    """How a figure's caption names a digitise batch: its subject's label, or its size."""
    members = [r["subject"] for r in batch["subjects"]]
    if len(members) == 1:
        return subjects[members[0]]["label"]
    if len(members) == 2:
        return f"the batch of {members[0]} and {members[1]}"
    return f"the batch of {len(members)} subjects from {members[0]} to {members[-1]}"


def photograph_facts(batches, subjects, figures):
    """What the article says of the subjects read from photographs (None if there are none).

    Parameters
    ----------
    batches : list of dict
        The digitise jobs' quality records (``digitised/<batch>.json``: ``batch`` and
        its ``subjects``, each with its ``trials``), sheet order.
    subjects : dict
        Subject id -> ``{"label", ...}`` (the subject sheet).
    figures : list of str
        Each batch's quality figure, as the article names it (relative to the results).

    Returns
    -------
    dict or None
        ``subjects`` (named), ``all`` (every subject photographed), ``n_trials``, the
        ranges of the reading uncertainty and registration residual (um) and of the first
        distance read (mm), the figures to print (a batch's id, ``subject``, names it),
        and one row per trial.
    """
    records = [record for batch in batches for record in batch["subjects"]]
    if not records:
        return None
    trials = [(r["subject"], t) for r in records for t in r["trials"]]
    first = [d for _, t in trials for d in t["first_read_mm"].values() if d is not None]
    rows = [
        {
            "subject": subject,
            "depth": f"{t['depth_mm']:g}",
            "tip": f"{t['tip_x_mm']:.3f}",
            "shift": f"{1000 * t['shift_x_mm']:.1f}, {1000 * t['shift_z_mm']:.1f}",
            "registration": f"{t['registration_rms_um']:.1f}",
            "reading_sd": f"{t['reading_sd_um']:.1f}",
            "first": ", ".join("-" if d is None else f"{d:g}" for d in t["first_read_mm"].values()),
            "readings": f"{sum(t['readings'].values())}",
            "error": "-" if t.get("error_rms_um") is None else f"{t['error_rms_um']:.1f}",
        }
        for subject, t in trials
    ]
    return {
        "subjects": join_words(r["subject"] for r in records),
        "all": {r["subject"] for r in records} == set(subjects),
        "n_trials": len(trials),
        "reading_sd": span_text([t["reading_sd_um"] for _, t in trials], 1, " µm"),
        "registration": span_text([t["registration_rms_um"] for _, t in trials], 1, " µm"),
        "first_read": span_text(first, 2, " mm"),
        "with_truth": any(t.get("error_rms_um") is not None for _, t in trials),
        "error": span_text(
            [t["error_rms_um"] for _, t in trials if t.get("error_rms_um") is not None], 1, " µm"
        ),
        "figures": [
            {"file": f, "subject": b["batch"], "label": _batch_label(b, subjects)}
            for f, b in list(zip(figures, batches, strict=True))[:PHOTOGRAPH_FIGURES]
        ],
        "n_figures": len(batches),
        # the verb after the list of figures printed: "Figure C1 shows", "C1 and C2 show"
        "figures_show": "shows" if min(len(batches), PHOTOGRAPH_FIGURES) == 1 else "show",
        "rows": rows,
    }


def _data_facts(subjects, depths_mm, notice):
    """Who was measured, at which depths, and how the data describe themselves."""
    by_species = {}
    for subject, about in subjects.items():
        by_species.setdefault(about["species"], []).append(subject)
    order = [s for s in paper.SPECIES if s in by_species] + sorted(
        s for s in by_species if s not in paper.SPECIES
    )
    groups = []
    for species in order:
        members = by_species[species]
        groups.append(
            {
                "species": species,
                "count": len(members),
                "count_words": counted_words(len(members), species),
                "subjects": join_words(members),
                "depths": group_depths_text(members, depths_mm),
                "n_trials": sum(len(depths_mm[s]) for s in members),
            }
        )
    magnifications = sorted({about["magnification"] for about in subjects.values()})
    all_depths = sorted({d for s in subjects for d in depths_mm[s]})
    n_trials = sum(len(d) for d in depths_mm.values())
    return {
        "synthetic": bool(notice),
        "notice": notice,
        "has": {species: species in by_species for species in paper.SPECIES},
        "subjects_text": counted(len(subjects), "subject"),
        "trials_text": counted(n_trials, "trial"),
        "every_trial": every(n_trials, "trial"),
        "n_subjects": len(subjects),
        "n_trials": n_trials,
        "groups": groups,
        "who": join_words(g["count_words"] for g in groups),
        "depths": _depths_text(all_depths),
        "n_depths": len(all_depths),
        "magnification": (
            f"{magnifications[0]:g}"
            if len(magnifications) == 1
            else f"{magnifications[0]:g} to {magnifications[-1]:g}"
        ),
        "paper_depths": _depths_text(paper.DEPTHS_MM),
    }


def _fit_facts(fits, checks, noise_mm):
    """L per species and procedure, the model comparison and what the coordinates change."""
    species = [s for s in paper.SPECIES if (fits["species"] == s).any()]
    species += sorted(set(fits["species"]) - set(species))
    L = {
        model: {s: span_text(fits.loc[fits["species"] == s, f"{model}_L_mm"]) for s in species}
        for model in ("waterbed", "shifted", "arc")
    }
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = (fits["boussinesq_rmse_mm"] / fits["waterbed_rmse_mm"]).to_numpy(float)
    finite = np.isfinite(ratio)
    change = (fits["shifted_L_mm"] - fits["waterbed_L_mm"]).to_numpy(float)
    deepest = float(fits["depth_mm"].max()) if len(fits) else math.nan
    at_deepest = (fits["depth_mm"] == deepest).to_numpy()
    gaps = checks["gap_shifted_mm"].to_numpy(float) if len(checks) else np.array([])
    n_compared, n_better = int(finite.sum()), int((ratio[finite] > 1).sum())
    n_gaps, n_above = int(gaps.size), int((gaps > noise_mm).sum())
    return {
        "comparison": _comparison_text(n_better, n_compared),
        "comparison_short": _comparison_short(n_better, n_compared),
        "n_compared": n_compared,
        "n_waterbed_better": n_better,
        "coordinates": _coordinates_text(n_above, n_gaps),
        "n_gaps": n_gaps,
        "n_gaps_above_noise": n_above,
        "species": species,
        "L_paper": L["waterbed"],
        "L_shifted": L["shifted"],
        "L_arc": L["arc"],
        "L_paper_all": span_text(fits["waterbed_L_mm"]),
        "rmse_waterbed": span_text(fits["waterbed_rmse_mm"], 3),
        "rmse_boussinesq": span_text(fits["boussinesq_rmse_mm"], 3),
        "ratio_median": (
            format_fixed(np.median(ratio[finite]), _ratio_decimals(ratio[finite]))
            if finite.any()
            else "–"
        ),
        "ratio_range": span_text(ratio[finite], _ratio_decimals(ratio[finite]), ""),
        "waterbed_better": f"{int((ratio[finite] > 1).sum())} of {int(finite.sum())}",
        "L_change": span_text(change, 2),
        "L_change_deepest": span_text(change[at_deepest], 2),
        "deepest_mm": f"{deepest:g}",
        "gap_range": span_text(gaps, 4),
        "gap_above_noise": f"{int((gaps > noise_mm).sum())} of {gaps.size}",
        "noise_mm": f"{noise_mm:g}",
        "prior_share_L": _share_span(fits, "waterbed_L_prior_share"),
        "prior_share_A": _share_span(fits, "boussinesq_A_prior_share"),
        "wedge_share_A": _share_span(fits, "boussinesq_A_wedge_share"),
    }


def _ratio_decimals(ratios, least=1):
    """Decimals that show the smallest ratio to two significant digits (``least`` at
    least, three at most): a ratio of 0.02 is not printed as 0.0, nor one of 20.58 as
    20.582 with ``least=0``."""
    ratios = np.abs(np.asarray(ratios, float))
    ratios = ratios[np.isfinite(ratios) & (ratios > 0)]
    if not ratios.size:
        return least
    return int(min(3, max(least, 1 - math.floor(math.log10(ratios.min())))))


def _comparison_text(n_better, n_compared):
    """Which model leaves the smaller residuals, as the counts say it."""
    if n_compared == 0:
        return "No trial has both fits, so the two forms cannot be compared by their residuals"
    if n_better == n_compared:
        return (
            "Near the wedge the waterbed leaves smaller residuals than the half-space form in "
            + every(n_compared, "trial")
        )
    if n_better == 0:
        return (
            "Near the wedge the half-space form leaves smaller residuals than the waterbed in "
            + every(n_compared, "trial")
        )
    return (
        "Near the wedge neither form leaves the smaller residuals in every trial: the waterbed "
        f"does in {n_better} of {counted(n_compared, 'trial')}, the half-space form in the "
        + ("other one" if n_compared - n_better == 1 else f"other {n_compared - n_better}")
    )


def _comparison_short(n_better, n_compared):
    """The abstract's half-sentence on the residuals: which model leaves the smaller ones
    in how many trials, naming the other model only where it wins any."""
    if n_compared == 0:
        return "no trial has both fits to compare their residuals"
    if n_better == 0:
        return (
            "the half-space form leaves the smaller residuals in "
            + every(n_compared, "trial")
            + " with both fits"
        )
    text = (
        "the waterbed leaves the smaller residuals in "
        + (
            every(n_compared, "trial")
            if n_better == n_compared
            else f"{n_better} of {counted(n_compared, 'trial')}"
        )
        + " with both fits"
    )
    others = n_compared - n_better
    if others:
        text += ", the half-space form in the " + (
            "other one" if others == 1 else f"other {others}"
        )
    return text


def _coordinates_text(n_above, n_gaps):
    """Whether reading the photographs in measured coordinates moves a fit by more than the
    noise, in how many trials."""
    if n_gaps == 0:
        return "no trial has both fits to compare"
    if n_above == 0:
        return "less than one reading's noise in " + every(n_gaps, "trial")
    if n_above == n_gaps:
        return "more than one reading's noise in " + every(n_gaps, "trial")
    return f"more than one reading's noise in {n_above} of {counted(n_gaps, 'trial')}"


def dataset_design(fits):
    """The trials of a dataset by species and depth: ``{(species, depth_mm): count}``."""
    return {
        (str(species), float(depth)): int(n)
        for (species, depth), n in fits.groupby(["species", "depth_mm"]).size().items()
    }


def calibration_design(bootstrap_trials):
    """The design the committed calibration was computed for, from the parametric
    bootstrap's per-trial table (``docs/calibration/bootstrap_trials.csv``): the trials
    of its first replicate by species and depth, as :func:`dataset_design` gives them."""
    first = bootstrap_trials[
        (bootstrap_trials["dataset"] == bootstrap_trials["dataset"].min())
        & (bootstrap_trials["model"] == bootstrap_trials["model"].iloc[0])
        & (bootstrap_trials["parameter"] == bootstrap_trials["parameter"].iloc[0])
    ]
    return dataset_design(first)


def design_text(design):
    """``"26 trials (16 monkey, 10 human) at 0.5, 1, 1.5 and 2 mm"``."""
    per_species = {}
    for (species, _), n in design.items():
        per_species[species] = per_species.get(species, 0) + n
    depths = sorted({depth for _, depth in design})
    order = [s for s in paper.SPECIES if s in per_species]
    order += sorted(set(per_species) - set(paper.SPECIES))
    parts = ", ".join(f"{per_species[species]} {species}" for species in order)
    return f"{counted(sum(design.values()), 'trial')} ({parts}) at {_depths_text(depths)}"


def _prior_facts(claims):
    """Which verdicts change with the noise priors scaled (the claims table's
    ``verdict_prior_x*`` columns): by multiple, and below twice the stated sizes."""
    columns = [c for c in claims.columns if c.startswith("verdict_prior_x")]
    multiples = [float(c.removeprefix("verdict_prior_x")) for c in columns]
    by_multiple = [
        {
            "multiple": f"{m:g}",
            "changed": join_words(claims.loc[claims[c] != claims["verdict"], "claim"]) or "none",
        }
        for m, c in zip(multiples, columns, strict=True)
    ]
    below = changed_claims(claims, below=2.0)
    return {
        "checked": bool(columns),
        "multiples": join_words(f"{m:g}" for m in multiples),
        "by_multiple": by_multiple,
        "changed_below_2": join_words(below) if below else "none",
    }


def _share_span(fits, column):
    """The range of a ``*_prior_share`` or ``*_wedge_share`` column in per cent ('–'
    without one)."""
    if column not in fits:
        return "–"
    return span_text(100 * fits[column].to_numpy(float), 0, " %")


def article_facts(
    fits,
    claims,
    checks,
    subjects,
    depths_mm,
    settings,
    notice,
    software,
    mechanics=None,
    calibration=None,
    built_in=None,
    results_name="results",
):
    """Every number and data-dependent phrase of the article.

    Parameters
    ----------
    fits, claims, checks : pandas.DataFrame
        The fit table, the claims table and the per-trial checks.
    subjects : dict
        Subject id -> ``{"species", "magnification", "label"}``, in sheet order.
    depths_mm : dict
        Subject id -> list of measured depths (mm).
    settings : dict
        The analysis settings the article names, each under its config key
        (``fit_window_mm``, ``claims``, ``sensitivity``, ``figures``).
    notice : str
        The data notice (empty for data that carry none).
    software : dict
        ``python``, ``packages`` (name -> version) and ``git`` (``commit``, ``dirty``)
        from the provenance record; optionally ``name``, ``version`` and ``released``
        (the workflow's own, from ``CITATION.cff``).
    mechanics : pandas.DataFrame, optional
        The per-subject membrane mechanics, when the workflow made them.
    built_in : list of dict, optional
        ``data/built_in_verdicts.json`` of the generator (``claim`` and ``how``:
        ``tuned``, ``follows`` or ``identity``), for its reconstruction.
    calibration : dict of pandas.DataFrame, optional
        ``verdicts``, ``coverage`` and optionally ``boundary``: the calibration
        tables (``docs/calibration/verdicts.csv``, ``coverage.csv``, ``boundary.csv``),
        and ``design``: ``{(species, depth_mm): trials}`` of the data they were computed
        for. Their rates are printed only for data of that design.
    results_name : str, optional
        The name of the build's results folder, where the text sends the reader.

    Returns
    -------
    dict
        JSON-ready: ``data``, ``fits``, ``verdicts``, ``claims`` (one dict per claim,
        in table order), ``settings`` (as given), ``figures`` (the data-dependent
        parts of the captions), ``mechanics`` (or None), ``calibration`` (or None)
        and ``software``.
    """
    counts = verdict_counts(claims)
    noise_mm = float(settings["claims"]["noise_mm"])
    figures = settings["figures"]
    facts = {
        "data": _data_facts(subjects, depths_mm, notice),
        "fits": _fit_facts(fits, checks, noise_mm),
        "verdicts": {
            **{key.replace(" ", "_"): value for key, value in counts.items()},
            "sentence": summary_sentence(claims),
            # the paper's claims about fingers; the checks of method and model apart
            "n_claims": counts["paper_claims"],
            "evidence_words": number_words(counts["evidence"]),
            "holds_words": number_words(counts["holds"]),
            "fails_words": number_words(counts["does not hold"]),
        },
        "claims": [
            {
                "claim": row["claim"],
                "statement": row["statement"],
                "paper_location": row["paper_location"],
                "paper_value": row["paper_value"],
                "our_value": row["our_value"],
                "verdict": row["verdict"],
                "kind": row.get("kind", PAPER_CLAIM),
                "evidence": row["verdict"] in EVIDENCE_VERDICTS
                and row.get("kind", PAPER_CLAIM) == PAPER_CLAIM,
                "reason": row["reason"],
            }
            for _, row in claims.iterrows()
        ],
        "priors": _prior_facts(claims),
        "settings": shown(settings),
        "figures": {
            "example_depth": f"{figures['example_depth_mm']:g} mm",
            "example_subjects": join_words(figures["example_subjects"]),
            "outline_subjects": join_words(figures["outline_subjects"]),
            "outline_depth": (
                "" if figures["outline_depth_mm"] is None else f"{figures['outline_depth_mm']:g} mm"
            ),
            "has_outlines": bool(figures["outline_subjects"]),
        },
        "mechanics": None,
        "calibration": None,
        "trials": _trial_facts(fits),
        "built_in": None
        if built_in is None
        else {
            **{
                how.replace(" ", "_"): join_words(r["claim"] for r in built_in if r["how"] == how)
                for how in ("tuned", "by construction", "follows")
            },
            # claims the generator's list is silent on (added after it was written)
            "not_listed": join_words(
                c for c in claims["claim"] if c not in {r["claim"] for r in built_in}
            ),
        },
        "claim_verdicts": {row["claim"]: row["verdict"] for _, row in claims.iterrows()},
        # each claim's rule cut into plain text and formulas, which the article typesets
        "rules": {row["claim"]: segments(str(row["rule"])) for _, row in claims.iterrows()},
        # a figure named in the claims' text -> its label: the article cites it by number
        "named_figures": dict(NAMED_FIGURES),
        # which claims' rules read each setting, from the claims registry
        "claims_using": {setting: join_words(claims_using(setting)) for setting in SETTINGS},
        "claims_needing": {need: join_words(claims_needing(need)) for need in NEEDS},
        "software": {
            "record": f"{results_name}/provenance.json",
            # name, version and release date: the citation file's (absent in older callers)
            **{
                key: str(software[key])
                for key in ("name", "version", "released", "authors")
                if software.get(key)
            },
            "authors_placeholder": bool(software.get("authors_placeholder", True)),
            "python": str(software["python"]),
            "packages": {name: str(v) for name, v in software["packages"].items() if v},
            "git": {
                "commit": software["git"]["commit"] or "unknown",
                "dirty": bool(software["git"]["dirty"]),
            },
        },
    }
    if mechanics is not None and len(mechanics):
        facts["mechanics"] = _mechanics_facts(mechanics)
    if calibration is not None:
        facts["calibration"] = _calibration_facts(
            calibration["verdicts"],
            calibration["coverage"],
            calibration.get("boundary"),
            calibration.get("mechanics"),
            calibration.get("bootstrap"),
        )
        ours = dataset_design(fits)
        theirs = calibration.get("design")
        facts["calibration"]["same_design"] = theirs is None or theirs == ours
        facts["calibration"]["design"] = "" if theirs is None else design_text(theirs)
        facts["calibration"]["our_design"] = design_text(ours)
    return facts


#: The models as the text names them (the tables' column prefixes are lower case).
_MODEL_NAMES = {
    "waterbed": "waterbed",
    "shifted": "shifted",
    "arc": "exact arc",
    "boussinesq": "Boussinesq",
}


def _symbol(parameter):
    """A parameter as the text writes it: ``x0_mm`` -> ``x₀``, ``L_mm`` -> ``L``."""
    name = str(parameter).removesuffix("_mm")
    return {"x0": "x₀", "W0": "W₀"}.get(name, name)


def _percent(rate, low, high):
    """``"4.0 (1.6-8.2)"``: a rate and its interval, in percent."""
    return f"{100 * rate:.1f} ({100 * low:.1f}-{100 * high:.1f})"


def _calibration_facts(verdicts, coverage, boundary=None, mechanics=None, bootstrap=None):
    """The verdict calibration per claim and truth, the verdicts at each claim's boundary
    (where a boundary table is given), the pooled coverage per parameter, that of the
    membrane's parameters and that of the parametric bootstrap (where given)."""
    rows = []
    for _, row in verdicts[verdicts["claim"] != "any"].iterrows():
        identity = row["truth"] == "identity"
        rows.append(
            {
                "claim": str(row["claim"]),
                "truth": str(row["truth"]),
                "n": str(int(row["n_datasets"])),
                "holds": "–" if identity else str(int(row["n_holds"])),
                "fails": "–" if identity else str(int(row["n_fails"])),
                "untestable": "–" if identity else str(int(row["n_untestable"])),
                "wrong": "not evidence"
                if identity
                else "undecided"
                if int(row["n_holds"]) + int(row["n_fails"]) == 0
                else _percent(row["wrong_rate"], row["wrong_ci_low"], row["wrong_ci_high"]),
            }
        )
    every = verdicts[verdicts["claim"] == "any"].iloc[0]
    pooled = coverage[coverage["species"] == "all"]
    at_boundary = []
    if boundary is not None:
        # every world, side and truth: wrong 'holds' and wrong 'does not hold'
        for _, row in boundary.iterrows():
            at_boundary.append(
                {
                    "claim": str(row["claim"]),
                    "side": str(row["side"]),
                    "truth": str(row["truth"]),
                    "n": str(int(row["n_datasets"])),
                    "holds": str(int(row["n_holds"])),
                    "fails": str(int(row["n_fails"])),
                    "untestable": str(int(row["n_untestable"])),
                    "wrong_holds": _percent(
                        row["wrong_holds_rate"],
                        row["wrong_holds_ci_low"],
                        row["wrong_holds_ci_high"],
                    ),
                    "wrong_fails": _percent(
                        row["wrong_fails_rate"],
                        row["wrong_fails_ci_low"],
                        row["wrong_fails_ci_high"],
                    ),
                }
            )
    by_claim = claim_error_rates(verdicts, boundary)
    membrane = {}
    if mechanics is not None:
        for _, row in mechanics[mechanics["fit"] == "all"].iterrows():
            membrane[str(row["parameter"])] = _percent(
                row["coverage"], row["ci_low"], row["ci_high"]
            )
            membrane["n"] = str(int(row["n"]))
    resampled = None
    if bootstrap is not None:
        replicated = bootstrap[bootstrap["species"] == "all"]
        resampled = {
            # what the bootstrap is not: the data's world (its models exact, priors as stated)
            "limits": (
                "the replicates are made by the fitted models themselves, so each model is "
                "exactly right in them, and with the priors' errors at their stated sizes: "
                "the check is of the intervals at this design and these fitted values, not "
                "in a world with the data's own misfit or with wrong priors"
            ),
            "n": str(int(replicated["n_trials"].iloc[0])),
            "rows": [
                {
                    "what": f"{_MODEL_NAMES.get(row['model'], row['model'])} "
                    + _symbol(row["parameter"]),
                    "coverage": _percent(row["coverage"], row["ci_low"], row["ci_high"]),
                }
                for _, row in replicated.iterrows()
            ],
        }
    return {
        "by_claim": by_claim,
        "rows": rows,
        "boundary": at_boundary,
        "boundary_claims": str(len({row["claim"] for row in at_boundary})),
        "membrane": membrane or None,
        "bootstrap": resampled,
        # the coverage study's worlds whose errors are not as stated (Figure
        # supplement_coverage): each world, interval and its coverage
        "misspecified": [
            {
                "scenario": str(row["scenario"]),
                "ratio": f"{float(row['prior_ratio']):g}",
                "model": _MODEL_NAMES.get(str(row["model"]), str(row["model"])),
                "parameter": _symbol(row["parameter"]),
                "coverage": _percent(row["coverage"], row["ci_low"], row["ci_high"]),
            }
            for _, row in pooled.iterrows()
            if str(row.get("misspecified", "none")) != "none"
        ],
        "n_datasets": str(int(every["n_datasets"])),
        "any_wrong": str(int(every["n_wrong"])),
        "any_rate": (
            f"{percent_text(every['wrong_rate'])}, 95 % CI {100 * every['wrong_ci_low']:.1f}-"
            f"{100 * every['wrong_ci_high']:.1f} %"
        ),
        "coverage": [
            {
                "scenario": str(row["scenario"]),
                "model": _MODEL_NAMES.get(str(row["model"]), str(row["model"])),
                "parameter": _symbol(row["parameter"]),
                "n": str(int(row["n_trials"])),
                "coverage": _percent(row["coverage"], row["ci_low"], row["ci_high"]),
            }
            for _, row in pooled.iterrows()
        ],
    }


#: Trials printed in the article's appendix; a larger dataset's others are in fits.csv.
APPENDIX_TRIALS = 60


def _interval_text(value, low, high, decimals=2):
    """``12.34 [11.90, 12.80]``; ``-`` for a value not fitted, ``open`` for an open end."""
    if not math.isfinite(value):
        return "–"
    ends = [format_fixed(v, decimals) if math.isfinite(v) else "open" for v in (low, high)]
    return f"{format_fixed(value, decimals)} [{ends[0]}, {ends[1]}]"


def _trial_facts(fits):
    """Every trial's L of each waterbed fit with its 95 % interval, and both models' RMSE.

    A reviewer finds in print each number a figure shows; beyond
    :data:`APPENDIX_TRIALS` trials the rest are left to ``tables/fits.csv``.
    """
    rows = []
    for _, row in fits.head(APPENDIX_TRIALS).iterrows():
        rows.append(
            {
                "subject": str(row["subject"]),
                "depth": f"{float(row['depth_mm']):g}",
                **{
                    model: _interval_text(
                        float(row[f"{model}_L_mm"]),
                        float(row[f"{model}_L_ci_low_mm"]),
                        float(row[f"{model}_L_ci_high_mm"]),
                    )
                    + (AT_BOUND_MARK if at_bound(row, model) else "")
                    for model in ("waterbed", "arc")
                },
                "rmse_waterbed": format_fixed(1000 * float(row["waterbed_rmse_mm"]), 1),
                "rmse_boussinesq": format_fixed(1000 * float(row["boussinesq_rmse_mm"]), 1),
            }
        )
    bounded = sum(
        at_bound(row, model) for _, row in fits.iterrows() for model in ("waterbed", "arc")
    )
    return {
        "rows": rows,
        "n": len(fits),
        "shown": len(rows),
        "bounded": int(bounded),
        "bound_mark": AT_BOUND_MARK,
    }


def _with_error(value, error, decimals):
    """``"0.083 ± 0.002"``; the value alone without an error; ``"–"`` if missing."""
    if value is None or not math.isfinite(float(value)):
        return "–"
    text = format_fixed(value, decimals)
    if error is not None and math.isfinite(float(error)):
        text += f" ± {format_fixed(error, decimals)}"
    return text


def _mechanics_facts(mechanics):
    """The membrane per subject, as the article's table shows it."""
    rows = [
        {
            "subject": str(row["subject"]),
            "species": str(row["species"]),
            # as many forces as constants: the fit passes through them, no scatter left
            "n_depths": str(int(row["n_depths"])) + (" (exact)" if int(row["dof"]) == 0 else ""),
            "pretension": _with_error(row["pretension_N_per_mm"], row["pretension_se_N_per_mm"], 3),
            "stiffness": _with_error(row["stiffness_N_per_mm"], row["stiffness_se_N_per_mm"], 2),
            "prestrain": _with_error(row["prestrain"], row["prestrain_se"], 2),
        }
        for _, row in mechanics.iterrows()
    ]
    with_lengths = int(np.isfinite(mechanics["pretension_N_per_mm"].to_numpy(float)).sum())
    return {
        "n_subjects": len(rows),
        "n_words": number_words(len(rows)),
        "subjects_text": counted_words(len(rows), "subject"),
        "with_contact_lengths": with_lengths,
        "any_exact": bool((mechanics["dof"].to_numpy(int) == 0).any()),
        "rows": rows,
    }


def bending_facts(bending, fits, claims):
    """What the article says of the bending skin (issue: the paper's closing suggestion).

    Parameters
    ----------
    bending : pandas.DataFrame or None
        The bending table (``tables/bending.csv``); None or empty without one.
    fits : pandas.DataFrame
        The fit table (the waterbed's AICc, for the comparison on the same points).
    claims : pandas.DataFrame
        The claims table (C13's verdict).

    Returns
    -------
    dict or None
        Counts and ranges as text: trials fitted, how many bending lengths lie at the
        range's end (not told from the membrane), the range of the others, how many
        trials the bending skin wins by AICc on the same points, C13's verdict.
    """
    if bending is None or not len(bending):
        return None
    fitted = bending[np.isfinite(bending["bending_length_mm"].astype(float))]
    at_end = fitted["bending_length_at_bound"].astype(float) > 0
    free = fitted[~at_end]
    merged = fitted.merge(
        fits[["subject", "depth_mm", "waterbed_aicc"]], on=["subject", "depth_mm"], how="left"
    )
    better = int((merged["bending_aicc"] < merged["waterbed_aicc"]).sum())
    c13 = claims.loc[claims["claim"] == "C13", "verdict"]
    return {
        "n": counted(len(fitted), "trial"),
        "every": every(len(fitted), "trial"),
        "at_end": counted(int(at_end.sum()), "trial"),
        "all_at_end": bool(at_end.all()),
        "none_at_end": not bool(at_end.any()),
        "free": counted(len(free), "trial"),
        "free_range": span_text(free["bending_length_mm"].to_numpy(float), 3),
        "better_aicc": f"{better} of {counted(len(fitted), 'trial')}",
        "wall": str(fitted["wall"].iloc[0]) if "wall" in fitted and len(fitted) else "clamped",
        "c13": str(c13.iloc[0]) if len(c13) else "",
    }


def elastic_facts(elastic, fits):
    """What the article says of the elastic finger (issue: the later literature's model).

    Parameters
    ----------
    elastic : pandas.DataFrame or None
        The elastic fits (``tables/elastic_fits.csv``); None or empty without one.
    fits : pandas.DataFrame
        The fit table (the waterbed's RMSE, the yardstick on the same points).

    Returns
    -------
    dict or None
        Counts and ranges as text: trials fitted and not, how many layered ratios lie at
        the library's largest ratio, the range of the others, the RMSE of each elastic
        fit and of the waterbed over the same trials, how many trials the layered finger
        wins over the homogeneous one by AICc and how many it fits better than the
        waterbed. None when no trial has an elastic fit.
    """
    if elastic is None or not len(elastic):
        return None
    fitted = elastic[np.isfinite(elastic["elastic_layered_modulus_ratio"].astype(float))]
    if not len(fitted):
        return None
    at_end = fitted["elastic_layered_ratio_at_bound"].astype(float) > 0
    free = fitted[~at_end]
    merged = fitted.merge(
        fits[["subject", "depth_mm", "waterbed_rmse_mm"]], on=["subject", "depth_mm"], how="left"
    )
    layered = merged["elastic_layered_rmse_mm"].to_numpy(float)
    homogeneous = merged["elastic_homogeneous_rmse_mm"].to_numpy(float)
    waterbed = merged["waterbed_rmse_mm"].to_numpy(float)
    layered_wins = int((merged["elastic_layered_aicc"] < merged["elastic_homogeneous_aicc"]).sum())
    return {
        "n": counted(len(fitted), "trial"),
        "every": every(len(fitted), "trial"),
        "not_fitted": counted(len(elastic) - len(fitted), "trial"),
        "all_fitted": len(fitted) == len(elastic),
        "at_end": counted(int(at_end.sum()), "trial"),
        "all_at_end": bool(at_end.all()),
        "none_at_end": not bool(at_end.any()),
        "free": counted(len(free), "trial"),
        "free_range": span_text(
            free["elastic_layered_modulus_ratio"].to_numpy(float),
            _ratio_decimals(free["elastic_layered_modulus_ratio"].to_numpy(float), least=0),
            "",
        ),
        "largest_ratio": f"{float(fitted['elastic_layered_ratio_ci_high'].max()):g}",
        "rmse_layered": span_text(layered, 3),
        "rmse_homogeneous": span_text(homogeneous, 3),
        "rmse_waterbed": span_text(waterbed, 3),
        "layered_wins": f"{layered_wins} of {counted(len(fitted), 'trial')}",
        "waterbed_sentence": (
            "the layered finger fits no trial better than the waterbed"
            if not (layered < waterbed).any()
            else f"the layered finger fits {int((layered < waterbed).sum())} of "
            f"{counted(len(fitted), 'trial')} better than the waterbed"
        ),
    }
