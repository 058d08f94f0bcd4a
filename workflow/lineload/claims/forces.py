"""The forces on the wedge against the membrane's shapes (C11, a check of the model's
consistency the paper never makes): through F = 2lN sin θ₀ (eq. 3) with N = Eε (eq. 7)."""

from __future__ import annotations

import math

import numpy as np

from lineload import mechanics, paper
from lineload.claims.rows import _every, _list, _n, _row
from lineload.claims.verdicts import FAILS, HOLDS, UNTESTABLE
from lineload.publishing.tables import format_fixed
from lineload.publishing.tables import span_text as _span

__all__ = [
    "claim_c11",
]


def _shape_checks(fits, allowed):
    """Per subject with two or more depths of finite arc L: :func:`mechanics.ratio_check`
    between its smallest and largest depth, with those depths."""
    variant = mechanics.WATERBED_VARIANT
    checks = {}
    for subject, rows in fits.groupby("subject", sort=False):
        rows = rows[np.isfinite(rows[f"{variant}_L_mm"].to_numpy(float))]
        rows = rows.sort_values("depth_mm", kind="stable")
        if rows["depth_mm"].nunique() < 2:
            continue
        small, large = rows.iloc[0], rows.iloc[-1]

        def L_of(row):
            return tuple(
                float(row[f"{variant}_L{suffix}_mm"]) for suffix in ("", "_ci_low", "_ci_high")
            )

        check = mechanics.ratio_check(
            float(small["depth_mm"]), L_of(small), float(large["depth_mm"]), L_of(large), allowed
        )
        check["depths_mm"] = (float(small["depth_mm"]), float(large["depth_mm"]))
        checks[str(subject)] = check
    return checks


def _force_checks(fits, forces, prior_sd_N):
    """Per subject with forces at two or more depths: the stress-free and the full fit.

    Each force's SD is the mechanics table's: the pooled chi-square of the full fits,
    with the config's ``prior_sd_N`` a floor and the fallback
    (:func:`lineload.mechanics.pooled_force_sd`).  Returns ``(checks, sd_N, source)``.
    """
    groups = mechanics.force_groups(fits, forces)
    sd_N, _, source = mechanics.pooled_force_sd(list(groups.values()), prior_sd_N)
    checks = {}
    for subject, (depth, L_mm, force, L_sd) in groups.items():
        args = (depth, L_mm, force, sd_N, L_sd)
        checks[subject] = {
            "stress_free": mechanics.fit_membrane(*args, stress_free=True),
            "tensioned": mechanics.fit_membrane(*args),
            "ratio": float(force[-1] / force[0]),
        }
    return checks, sd_N, source


def claim_c11(fits, averaged, settings, forces=None):
    """C11: the forces on the wedge go with the paper's stress-free membrane (eqs 3 and 7)."""
    low_N, high_N = paper.FORCE_RANGE_N
    allowed = mechanics.allowed_force_ratio()
    alpha = settings.significance
    rule = (
        "Through F = 2lN sin θ₀ (eq. 3) with N = Eε (eq. 7), the exact arc fitted "
        "at each depth (arc_L_mm: its load angle and Green strain, lineload.mechanics) fixes "
        "the ratio of the forces of a stress-free membrane at two depths, whatever E and the "
        "contact length l. (a) Shapes: per subject, that ratio between its largest and "
        "smallest depth, at the fitted L and at the ends of the two L's 95 % intervals; every "
        f"force inside the paper's {low_N:g}-{high_N:g} N allows at most {high_N:g}/{low_N:g} "
        f"= {allowed:.2f}. (b) Forces, where forces.csv has two or more depths of a subject: "
        "the stress-free membrane fitted to them (one constant) by weighted least squares, "
        "each force with variance s² plus the part from L's uncertainty, s the force SD of "
        "the mechanics table (from the pooled chi-square of the membrane fits with a tension "
        f"at rest; the config's force_sd_N = {settings.force_sd_N:g} N its floor and "
        "fallback), and its chi-square against the chi-square distribution "
        f"(significance = {alpha:g} divided by the number of subjects tested, Bonferroni). "
        "Does not hold if in some subject even the most favourable ends of the intervals "
        "give a ratio above the allowed one, or the forces reject the stress-free membrane; "
        "holds if in every subject the least favourable ends stay within it and no subject's "
        "forces reject it; cannot be checked otherwise. Beside it: the ratio of a membrane "
        "held by its tension alone (the limit of a large pre-strain) and the smallest "
        "pre-strain N₀/E that would bring the ratio within the allowed one (none if even "
        "tension alone exceeds it)."
    )
    shapes = _shape_checks(fits, allowed)
    measured, force_sd_N, sd_source = {}, settings.force_sd_N, ""
    if forces is not None:
        measured, force_sd_N, sd_source = _force_checks(fits, forces, settings.force_sd_N)
    if not shapes and not measured:
        return _row(
            "C11",
            "no subject with a finite exact-arc L at two or more depths",
            UNTESTABLE,
            "No subject was fitted at two depths, so no force ratio follows from the shapes.",
            rule,
        )
    parts, too_steep, all_within = [], [], True
    if shapes:
        tension = [c["tension_only"] for c in shapes.values()]
        too_steep = [s for s, c in shapes.items() if c["stress_free_low"] > allowed]
        all_within = all(c["stress_free_high"] <= allowed for c in shapes.values())
        prestrains = {s: c["prestrain"] for s, c in shapes.items()}
        finite = {s: p for s, p in prestrains.items() if math.isfinite(p)}
        none = [s for s, p in prestrains.items() if p == math.inf]
        spans = sorted({c["depths_mm"] for c in shapes.values()})
        if len(shapes) <= 8:
            reconcile = "per subject, stress-free ratio / pre-strain that reconciles: " + ", ".join(
                f"{s} {format_fixed(c['stress_free'], 1)} / "
                + ("none" if c["prestrain"] == math.inf else format_fixed(c["prestrain"], 2))
                for s, c in shapes.items()
            )
        else:
            reconcile = "pre-strain that reconciles " + (
                f"{_span(list(finite.values()), 2, '')} in {len(finite)}" if finite else "none"
            )
            reconcile += f", none can in {len(none)} ({_list(none)})" if none else ""
        by_pair = []
        for pair in spans:
            members = [c for c in shapes.values() if c["depths_mm"] == pair]
            by_pair.append(
                f"{pair[0]:g} to {pair[1]:g} mm ({_n(len(members), 'subject')}): "
                f"{_span([c['stress_free'] for c in members], 1, '')}, lowest within the L "
                f"intervals {_span([c['stress_free_low'] for c in members], 1, '')}"
            )
        parts.append(
            f"shapes: stress-free force ratio, largest over smallest depth, "
            f"{'; '.join(by_pair)}; allowed by {low_N:g}-{high_N:g} N at most "
            f"{allowed:.2f}; tension alone {_span(tension, 2, '')}; {reconcile}"
        )
    rejected = []
    if measured:
        critical = alpha / len(measured)
        p_values = {s: c["stress_free"].p_value for s, c in measured.items()}
        rejected = [s for s, pv in p_values.items() if math.isfinite(pv) and pv < critical]
        fitted_prestrain = [c["tensioned"].prestrain for c in measured.values()]
        parts.append(
            f"forces of forces.csv, {_n(len(measured), 'subject')} (force SD "
            f"{force_sd_N:.3g} N, {sd_source}): ratio "
            f"{_span([c['ratio'] for c in measured.values()], 2, '')}; stress-free rejected in "
            f"{len(rejected)} of {len(measured)} (p < {critical:.2g}); fitted pre-strain "
            f"{_span(fitted_prestrain, 2, '')}"
        )
    our = "; ".join(parts)
    if too_steep or rejected:
        reasons = []
        if too_steep:
            for pair in sorted({shapes[s]["depths_mm"] for s in too_steep}):
                members = [s for s in too_steep if shapes[s]["depths_mm"] == pair]
                steep = [shapes[s]["stress_free"] for s in members]
                steep_low = [shapes[s]["stress_free_low"] for s in members]
                reasons.append(
                    f"from {pair[0]:g} to {pair[1]:g} mm the fitted shapes need a stress-free "
                    f"membrane to push {_span(steep, 0, '')} times harder (at least "
                    f"{_span(steep_low, 0, '')} anywhere in the L intervals) in "
                    f"{_list(members, limit=len(members))}"
                )
            reasons[-1] += f", where the paper's {low_N:g}-{high_N:g} N allows {allowed:.1f}"
        if rejected:
            reasons.append(
                f"the forces in forces.csv reject it in {_list(rejected, limit=len(rejected))}, "
                "which they fit with a tension at rest"
            )
        tension_over = [s for s, c in shapes.items() if c["prestrain"] == math.inf]
        text = "; ".join(reasons)
        if tension_over:
            text += (
                f". Even a membrane held by its tension alone gives more than {allowed:.1f} "
                f"in {_list(tension_over)}: for them no pre-strain at all reconciles the "
                "shapes with the paper's range"
            )
        return _row("C11", our, FAILS, text[0].upper() + text[1:] + ".", rule)
    if shapes and all_within:
        reason = (
            f"In {_every(len(shapes), 'subject')} the fitted shapes give a stress-free membrane "
            f"a force ratio within the {allowed:.1f} the paper's range allows, even at the "
            "least favourable ends of the L intervals"
        )
        reason += "; the forces in forces.csv do not reject it." if measured else "."
        return _row("C11", our, HOLDS, reason, rule)
    reason = (
        "The fitted shapes neither rule out a stress-free membrane nor confirm it: the L "
        f"intervals straddle the ratio of {allowed:.1f} the paper's range allows"
        if shapes
        else "Only the forces of forces.csv were tested and they do not reject it, but no "
        "subject's shapes span two depths"
    )
    return _row("C11", our, UNTESTABLE, reason + ".", rule)
