"""Claims on the measured profile's own shape: how far it reaches (C1), whether its
sides agree (C2) and whether its free skin is one circle (C10)."""

from __future__ import annotations

import math

import numpy as np

from lineload import paper
from lineload.claims.rows import _every, _list, _n, _pct, _row, _smallest_margin
from lineload.claims.statistics import asymmetry_excess, chord_curvature, deformed_extent_se_mm
from lineload.claims.trials import _averaged_covariance_mm2, _label, _trials, _window_points
from lineload.claims.verdicts import FAILS, HOLDS, NO_MARGIN, UNTESTABLE
from lineload.distributions import normal_quantile
from lineload.publishing.tables import format_fixed
from lineload.publishing.tables import span_text as _span
from lineload.trials import DEPTH_DECIMALS

__all__ = [
    "claim_c1",
    "claim_c2",
    "claim_c10",
]


def claim_c1(fits, averaged, settings):
    """C1: wider deformed region in humans than in monkeys at the same depth, each extent
    with its standard error under the trial's noise."""
    fraction = settings.extent_fraction
    alpha = settings.significance
    extents = {}
    for fit, points in _trials(fits, averaged):
        if points.empty:
            continue
        keep = np.isfinite(points["deflection_mm"].to_numpy(float))
        x = points["distance_mm"].to_numpy(float)[keep]
        w = points["deflection_mm"].to_numpy(float)[keep]
        sides = points["n_sides"].to_numpy(float)[keep]
        covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
        threshold_mm = fraction * float(fit["depth_mm"])
        extent = deformed_extent_se_mm(x, w, threshold_mm, covariance)
        key = round(float(fit["depth_mm"]), DEPTH_DECIMALS)
        extents.setdefault(key, {}).setdefault(str(fit["species"]), []).append(extent)
    rule = (
        "Extent of a trial = distance at which the averaged deflection last falls through "
        f"{_pct(fraction, 0)} of the depth W₀ (config claims: extent_fraction; a property "
        "of the profile's shape, the same whatever the noise; linear interpolation "
        "between readings), with its standard error: the error of the interpolated "
        "deflection there (the trial's covariance from the noise table) over the profile's "
        "slope. At every depth measured in both species, every human trial is compared with "
        "every monkey trial: z = (human extent - monkey extent) / the root of the sum of "
        "their squared standard errors. Humans are wider at a depth if z exceeds "
        f"z(1 - {alpha:g}) in every pair (significance = {alpha:g}); a monkey is as wide if "
        "z is below minus the one-sided Bonferroni quantile over all pairs. Holds if humans "
        "are wider at every shared depth; does not hold if some monkey trial is wider than "
        "some human trial beyond the noise; cannot be checked otherwise."
    )
    by_species = {
        sp: [e for depth in extents.values() for e, _ in depth.get(sp, [])] for sp in paper.SPECIES
    }
    ranges = ", ".join(
        f"{sp}s {_span(by_species[sp])} ({_n(len(by_species[sp]), 'trial')})"
        if by_species[sp]
        else f"{sp}s: no trials"
        for sp in paper.SPECIES
    )
    shared = sorted(d for d, sp in extents.items() if "monkey" in sp and "human" in sp)
    if not shared:
        # the value lists what there is; the reason says once what is missing
        missing = [sp for sp in paper.SPECIES if not by_species[sp]]
        reason = (
            f"these data hold no {' and no '.join(missing)} trials"
            if missing
            else "no depth was measured in both species"
        )
        return _row("C1", ranges, UNTESTABLE, f"The species cannot be compared: {reason}.", rule)
    z_by_depth = {}
    for d in shared:
        z_by_depth[d] = np.array(
            [
                (h - m) / math.hypot(se_h, se_m)
                if math.hypot(se_h, se_m) > 0
                else (h - m) * math.inf
                for h, se_h in extents[d]["human"]
                for m, se_m in extents[d]["monkey"]
            ]
        )
    n_pairs = sum(z.size for z in z_by_depth.values())
    z_one = float(normal_quantile(1.0 - alpha))
    z_all = float(normal_quantile(1.0 - alpha / n_pairs))
    wider = [d for d in shared if (z_by_depth[d] > z_one).all()]
    reversed_ = [d for d in shared if (z_by_depth[d] < -z_all).any()]
    errors = [se for depth in extents.values() for group in depth.values() for _, se in group]
    per_depth = "; ".join(
        f"{d:g} mm: monkeys {_span([e for e, _ in extents[d]['monkey']])}, humans "
        f"{_span([e for e, _ in extents[d]['human']])}, smallest z "
        f"{format_fixed(float(z_by_depth[d].min()), 1)}"
        for d in shared
    )
    our = (
        f"{ranges}; standard error of an extent {_span(errors, 2)}; humans wider beyond the "
        f"noise at {len(wider)} of {len(shared)} shared depths"
    )
    narrow = [f"{d:g}" for d in shared if d not in wider]
    if narrow:
        our += f" (not at {', '.join(narrow)} mm)"
    our += f" ({per_depth})"
    if reversed_:
        reason = (
            f"At {', '.join(f'{d:g}' for d in reversed_)} mm some monkey trial is deformed "
            "farther from the wedge than some human trial, beyond the extents' uncertainty."
        )
        return _row("C1", our, FAILS, reason, rule)
    if len(wider) == len(shared):
        reason = (
            f"At {_every(len(shared), 'depth')} measured in both species, every human "
            "trial is deformed farther from the wedge than every monkey trial, beyond the "
            "extents' uncertainty."
        )
        return _row("C1", our, HOLDS, reason, rule)
    reason = (
        f"At {', '.join(narrow)} mm the extents' uncertainty leaves open whether every human "
        "trial is deformed farther from the wedge than every monkey trial."
    )
    return _row("C1", our, UNTESTABLE, reason, rule)


def _difference_covariance_mm2(x_mm, settings):
    """Covariance of left minus right at distances both sides read, from noise alone.

    The two sides' own errors are independent, so the difference has twice one
    side's covariance (reading and tracing: the side offsets are not measured, so an
    offset between the two traces counts as a difference between the sides, which
    makes "nearly the same" harder to show, not easier); without a noise model, twice
    ``noise_mm**2`` on the diagonal.
    """
    if settings.noise_model is not None and settings.noise_mm is None:
        return 2.0 * settings.noise_model.side_covariance_mm2(x_mm)
    return 2.0 * settings.reading_noise_mm**2 * np.eye(x_mm.size)


def claim_c2(fits, averaged, settings):
    """C2: left and right profiles nearly the same, an equivalence test against the noise."""
    alpha = settings.significance
    margin = settings.symmetry_margin
    rule = (
        "An equivalence test, the noise removed, with the workflow's margin (config "
        f"claims: symmetry_margin = {_pct(margin, 0)}, reasons in the config schema; the "
        "paper gives no number for symmetry). Per "
        "trial, over the distances read on both sides (left_source and right_source both "
        "'measured'): the mean square of left - right beyond what the noise gives, D = "
        "mean(d²) − trace(C)/n, with C the covariance of the difference under noise alone "
        "(twice one side's: reading and tracing, the noise table; an offset of one side's "
        "trace is not measured and counts in D), and its "
        "standard error SE. The sides are nearly the same if their true RMS difference is "
        f"below {_pct(margin, 0)} of the depth W₀. Equivalent if D + z(1 - {alpha:g}) SE < "
        f"({margin:g} W₀)²; different if D - z(1 - {alpha:g}/(2 x trials)) SE > ({margin:g} "
        "W₀)² (Bonferroni). Holds if every trial is equivalent; does not hold if any is "
        "different; cannot be checked otherwise. Beside it: the smallest margin of 1-20 % at "
        "which the claim holds."
    )
    values = []
    for fit, points in _trials(fits, averaged):
        if points.empty:
            continue
        both = (points["left_source"] == "measured") & (points["right_source"] == "measured")
        both &= points["distance_mm"].to_numpy(float) > 0
        x = points.loc[both, "distance_mm"].to_numpy(float)
        difference = (points.loc[both, "left_mm"] - points.loc[both, "right_mm"]).to_numpy(float)
        if difference.size >= 2:
            excess, se = asymmetry_excess(difference, _difference_covariance_mm2(x, settings))
            values.append((_label(fit), excess, se, float(fit["depth_mm"])))
    if not values:
        return _row(
            "C2",
            "no trial read on both sides at two or more distances",
            UNTESTABLE,
            "No trial was read on both sides at the same distances.",
            rule,
            NO_MARGIN,
        )
    depths = np.array([v[3] for v in values])
    z_one = float(normal_quantile(1.0 - alpha))
    z_all = float(normal_quantile(1.0 - alpha / (2.0 * len(values))))
    excess = np.array([v[1] for v in values])
    se = np.array([v[2] for v in values])

    def tests(margin):
        bound = (margin * depths) ** 2
        return excess + z_one * se < bound, excess - z_all * se > bound

    def decide(margin):
        equivalent, different = tests(margin)
        return FAILS if different.any() else HOLDS if equivalent.all() else UNTESTABLE

    smallest = _smallest_margin(decide)
    equivalent, different = tests(margin)
    fraction = np.sqrt(np.clip(excess, 0.0, None)) / depths
    # the bound the equivalence test compares with the margin, in the same units
    upper = np.sqrt(np.clip(excess + z_one * se, 0.0, None)) / depths
    worst, widest = values[int(np.argmax(fraction))][0], values[int(np.argmax(upper))][0]
    if fraction.max() > 0:
        estimate = (
            f"median {_pct(np.median(fraction), 2)}, largest {_pct(fraction.max(), 2)} ({worst})"
        )
    else:
        # an estimate clipped at zero in every trial: the sides differ by no more than
        # the noise alone makes them; '0 %' alone would read as a rounding
        estimate = f"0 in {_every(len(values), 'trial')} (no more than the noise alone gives)"
    level = f"{format_fixed(100 * (1 - alpha), 0)} %"
    bounded = f"at most {_pct(upper.max(), 2)} ({widest})" if upper.max() > 0 else "0 in each too"
    our = (
        f"true RMS left-right difference (noise removed) / depth: {estimate}; its upper "
        f"{level} bound {bounded}; equivalent within {_pct(margin, 0)} in "
        f"{int(equivalent.sum())} of {_n(len(values), 'trial')}, different in "
        f"{int(different.sum())}"
    )
    if different.any():
        labels = [v[0] for v, d in zip(values, different, strict=True) if d]
        reason = (
            f"In {_n(len(labels), 'trial')} ({_list(labels)}) the sides differ by more than "
            f"{_pct(margin, 0)} of the depth, beyond what the noise explains."
        )
        return _row("C2", our, FAILS, reason, rule, smallest)
    if equivalent.all():
        reason = (
            "In every trial the two sides differ, once the noise is removed, by less than "
            f"{_pct(margin, 0)} of the depth."
        )
        return _row("C2", our, HOLDS, reason, rule, smallest)
    reason = (
        f"In {_n(int((~equivalent).sum()), 'trial')} the noise leaves it open whether the sides "
        f"differ by more or less than {_pct(margin, 0)} of the depth."
    )
    return _row("C2", our, UNTESTABLE, reason, rule, smallest)


def claim_c10(fits, averaged, settings):
    """C10: constant curvature, an equivalence test of the two halves of the window."""
    alpha = settings.significance
    margin = settings.circularity_margin
    rule = (
        "An equivalence test with the workflow's margin (config claims: circularity_margin "
        f"= {_pct(margin, 0)}, reasons in the config schema; the paper says 'approximately "
        "circular' and gives no number). Per trial: the fitted points (the fit "
        "window) are split at half the largest fitted distance; the whole window and each half "
        "with at least 5 points get the curvature of their best-fitting circle, with standard "
        "errors from the noise table's covariance (correlated errors included; "
        "lineload.claims.chord_curvature). The statistic is the relative change r = (inner - "
        "outer) / whole, zero for a circle; its standard error by first order. Pooled over "
        "trials (inverse-variance weights): the skin is circular to the margin if the "
        f"{format_fixed(100 * (1 - 2 * alpha), 0)} % interval of the pooled r lies inside "
        f"±{_pct(margin, 0)} and no trial's r lies significantly outside it (Bonferroni over "
        f"the trials; significance = {alpha:g}); it is not if the pooled interval lies "
        "outside, or any trial's r lies significantly outside the margin. Cannot be checked "
        "otherwise: the noise hides a change as large as the margin. Beside it: the smallest "
        "margin of 1-20 % at which the claim holds."
    )
    tested = []
    for fit, points in _trials(fits, averaged):
        if points.empty:
            continue
        x, w, sides = _window_points(fit, points)
        if x.size == 0:
            continue
        inner = x <= x.max() / 2.0
        if inner.sum() < 5 or (~inner).sum() < 5:
            continue
        covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
        whole, se_whole = chord_curvature(x, w, covariance)
        k_in, se_in = chord_curvature(x[inner], w[inner], covariance[np.ix_(inner, inner)])
        k_out, se_out = chord_curvature(x[~inner], w[~inner], covariance[np.ix_(~inner, ~inner)])
        if whole == 0.0:
            continue
        r = (k_in - k_out) / whole
        se = math.sqrt((se_in**2 + se_out**2) / whole**2 + (r * se_whole / whole) ** 2)
        tested.append((_label(fit), r, se))
    if not tested:
        return _row(
            "C10",
            "no trial with 5 or more points in each half of the fit window",
            UNTESTABLE,
            "No trial has enough points in both halves of the window to compare curvatures.",
            rule,
            NO_MARGIN,
        )
    r = np.array([t[1] for t in tested])
    se = np.array([t[2] for t in tested])
    weights = se**-2
    pooled = float(np.sum(weights * r) / np.sum(weights))
    pooled_se = float(np.sum(weights) ** -0.5)
    z_one = float(normal_quantile(1.0 - alpha))
    z_all = float(normal_quantile(1.0 - alpha / (2.0 * len(tested))))

    def tests(margin):
        inside = (pooled - z_one * pooled_se > -margin) and (pooled + z_one * pooled_se < margin)
        outside = (pooled - z_one * pooled_se > margin) or (pooled + z_one * pooled_se < -margin)
        return inside, outside, (np.abs(r) - margin) / se > z_all

    def decide(margin):
        inside, outside, beyond = tests(margin)
        return FAILS if outside or beyond.any() else HOLDS if inside else UNTESTABLE

    smallest = _smallest_margin(decide)
    inside, outside, beyond = tests(margin)
    our = (
        f"relative change of curvature, inner minus outer half over the whole window: pooled "
        f"{_pct(pooled)} ± {_pct(pooled_se)} (SE) over {_n(len(tested), 'trial')}; per trial "
        f"{_span(100 * r, 1, ' %')}; significantly beyond ±{_pct(margin, 0)} in "
        f"{int(beyond.sum())}"
    )
    if outside or beyond.any():
        labels = [t[0] for t, b in zip(tested, beyond, strict=True) if b]
        where = f" ({_list(labels)})" if labels else ""
        direction = "inner" if (pooled > 0 if outside else np.mean(r[beyond]) > 0) else "outer"
        reason = (
            f"The curvature changes along the window by more than the {_pct(margin, 0)} "
            f"margin{where}, the {direction} half bending more: the free skin is not one "
            "circle there."
        )
        return _row("C10", our, FAILS, reason, rule, smallest)
    if inside:
        reason = (
            "Pooled over the trials, the two halves of the window bend alike to within "
            f"the {_pct(margin, 0)} margin, and no trial departs from it significantly."
        )
        return _row("C10", our, HOLDS, reason, rule, smallest)
    reason = (
        f"The noise leaves the change of curvature ({_pct(pooled)} ± {_pct(pooled_se)}) "
        f"undecided against the {_pct(margin, 0)} margin."
    )
    return _row("C10", our, UNTESTABLE, reason, rule, smallest)
