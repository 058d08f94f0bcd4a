"""The calibration's tables as Markdown, each with the command that made it.

One function per study: :func:`coverage_markdown` and :func:`bootstrap_markdown`
(:mod:`lineload.simulation.coverage`), :func:`verdict_markdown` and
:func:`mechanics_markdown` (:mod:`lineload.simulation.verdicts`,
:mod:`lineload.simulation.mechanics_coverage`), :func:`boundary_markdown`
(:mod:`lineload.simulation.boundary`).
"""

from __future__ import annotations

import math

from lineload.claims import (
    CLAIM_KINDS,
    EVIDENCE_VERDICTS,
    FAILS,
    HOLDS,
    IDENTITY,
    PAPER_CLAIM,
)
from lineload.publishing.tables import markdown_table
from lineload.simulation.boundary import BOUNDARY_WORLDS
from lineload.simulation.rates import percent_interval

__all__ = [
    "bootstrap_markdown",
    "boundary_markdown",
    "calibration_command",
    "coverage_markdown",
    "mechanics_markdown",
    "verdict_markdown",
]


def calibration_command(seed, **counts):
    """The command that remakes a calibration table with these settings (for its footer).

    ``calibration_command(2026, datasets=40)`` ->
    ``snakemake --cores 2 calibration --config calibration='{seed: 2026, datasets: 40}'``.
    """
    settings = ", ".join(f"{key}: {value}" for key, value in {"seed": seed, **counts}.items())
    return f"snakemake --cores 2 calibration --config calibration='{{{settings}}}'"


def coverage_markdown(summary, command, notice=""):
    """The pooled coverage rows as a Markdown table with the command that made them."""
    pooled = [r for r in summary if r["species"] == "all"]
    header = ["errors simulated", "model", "parameter", "trials", "covered", "coverage (95 % CI)"]
    cells = [
        [
            r["scenario"],
            r["model"],
            r["parameter"],
            str(r["n_trials"]),
            str(r["n_covered"]),
            percent_interval(r["coverage"], r["ci_low"], r["ci_high"]),
        ]
        for r in pooled
    ]
    text = (
        "# Coverage of the nominal 95 % intervals\n\n"
        "Simulated datasets of the shipped design, each trial made by the model named, read "
        "with every digitising error of the reconstruction; the noise measured from each "
        "dataset's left-right differences and the model fitted as the workflow fits it. "
        "Aim: 93-97 %. In the worlds after the first three the errors the differences "
        "cannot measure are made at other sizes than the fit states (the fit keeps its "
        "stated priors), or an error the fit has no room for is made: there the table "
        "shows how far the intervals can be trusted when the priors are wrong.\n\n"
        + markdown_table(header, cells, "lllrrr")
        + f"\n\nMade by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text


def bootstrap_markdown(summary, command, n_trials, notice=""):
    """The parametric bootstrap's pooled coverage as Markdown, with the command."""
    pooled = [r for r in summary if r["species"] == "all"]
    header = ["model", "parameter", "trials x replicates", "covered", "coverage (95 % CI)"]
    cells = [
        [
            r["model"],
            r["parameter"],
            str(r["n_trials"]),
            str(r["n_covered"]),
            percent_interval(r["coverage"], r["ci_low"], r["ci_high"]),
        ]
        for r in pooled
    ]
    text = (
        "# A parametric bootstrap of the data's own fits\n\n"
        f"Each of the {n_trials} trials made again, many times, from the model as fitted to "
        "it, on its own reading grid, read with every error of the measured noise table; in "
        "each replicate the noise measured again from the left-right differences and the "
        "model fitted as the workflow fits it. An interval covers when it holds the fitted "
        "value its replicate was made from. Aim: 93-97 %.\n\n"
        "What it does not show: the replicates are made from the fitted curves, so each "
        "model is exactly right in them, while on the data every model leaves a misfit "
        "larger than the noise (the fit table's RMSE); and they are read with the priors' "
        "errors at their stated sizes, the sizes the fits assume. It checks the intervals "
        "at this design and these parameters, not in a world with the data's own misfit "
        "or with wrong priors (for those, docs/calibration/coverage.md).\n\n"
        + markdown_table(header, cells, "llrrr")
        + f"\n\nMade by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text


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


def _wrong_cell(row, prefix):
    """'2: 1.0 % (0.1-3.6 %)': the count of wrong verdicts, their rate and its interval."""
    rate = percent_interval(
        row[f"{prefix}_rate"], row[f"{prefix}_ci_low"], row[f"{prefix}_ci_high"]
    )
    return f"{int(row[f'n_{prefix}'])}: {rate}"


def boundary_markdown(summary, command, notice=""):
    """The boundary study's summary as a Markdown table with the command that made it."""
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


def mechanics_markdown(summary, command, notice=""):
    """The membrane's coverage as a Markdown table with the command that made it."""
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
        "# Recovery of the membrane's N0, E and pre-strain\n\n"
        "A recovery check, not evidence about fingers: the reconstruction's forces are made "
        "by the very law the fit inverts (a membrane under tension at rest, F = 2 l (N0 + E "
        "eps) sin(theta0), on the exact arc fitted to the noise-free profile), so the table "
        "shows that the arithmetic and its intervals return the constants they were made "
        "with, not that a finger follows that law; forces from another law are not "
        "simulated here. "
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


def verdict_scenarios_markdown(summary, command, notice=""):
    """The verdicts in worlds whose errors are not as stated, as Markdown with the command."""
    header = ["world", "claim", *_COUNT_HEADER]
    cells = []
    for row in summary:
        if row["claim"] == "any":
            cells.append(
                [
                    row["scenario"],
                    "any wrong",
                    "",
                    str(row["n_datasets"]),
                    "",
                    "",
                    "",
                    _percent_interval(row),
                ]
            )
            continue
        if row["truth"] == IDENTITY:
            continue
        cells.append(
            [
                row["scenario"],
                row["claim"],
                row["truth"],
                str(row["n_datasets"]),
                str(row["n_holds"]),
                str(row["n_fails"]),
                str(row["n_untestable"]),
                _percent_interval(row),
            ]
        )
    text = (
        "# The verdicts when the stated priors are wrong\n\n"
        "The datasets of the verdict calibration (the same seeds, so the same draws), read "
        "with errors made in the coverage study's worlds whose errors are not as stated "
        "(docs/calibration/coverage.md): the errors the left-right differences cannot "
        "measure at other sizes than the priors state, a resting curvature error, misreads, "
        "a tracing correlation or reading tails the noise estimate does not assume. Each is "
        "analysed as the workflow analyses the shipped data, with the priors as stated. "
        "The truth is the error-free verdict, as in the verdict calibration; the bending "
        "skin is not fitted here, so C13 is left out. 'any wrong' counts the datasets with "
        "a wrong verdict among the paper's claims.\n\n"
        + markdown_table(header, cells, "lllrrrrr")
        + f"\n\nMade by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text


def recovery_markdown(summary, command, notice=""):
    """The membrane's recovery check in each force world, as Markdown with the command."""
    cells = [
        [
            row["world"],
            row["parameter"],
            str(row["n"]),
            str(row["n_covered"]),
            percent_interval(row["coverage"], row["ci_low"], row["ci_high"]),
            f"{row['median_ratio']:.3f}",
        ]
        for row in summary
    ]
    header = ["forces from", "parameter", "subjects", "covered", "coverage (95 % CI)",
              "median estimate / truth"]  # fmt: skip
    b = max((float(row["stiffening"]) for row in summary), default=0.0)
    doubling = (
        f" (b = {b:g}: the tangent stiffness doubles at a strain of {100 * math.log(2) / b:.1f} %)"
        if b
        else ""
    )
    text = (
        "# Recovery of N0, E and pre-strain when the forces follow another law\n\n"
        "The datasets of the verdict calibration (the same seeds), their forces made twice: "
        "by the linear membrane the fit inverts, and by a strain-stiffening membrane, "
        f"N = N0 + E (exp(b eps) - 1) / b{doubling}, on the same arcs. The mechanics run as "
        "rule mechanics does. The truth is "
        "the membrane's tension N0 and tangent stiffness E at rest (pre-strain N0 / E). "
        "Where the forces follow another law the linear fit returns a secant stiffness "
        "over the strains reached, not the stiffness at rest: the intervals cannot be read "
        "as the finger's constants unless its law is the one inverted.\n\n"
        + markdown_table(header, cells, "llrrrr")
        + f"\n\nMade by `{command}`.\n"
    )
    if notice:
        text += f"\n{notice}\n"
    return text
