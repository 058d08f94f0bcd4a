"""Claims on the fitted half-width L: its range (C5), the shift U the paper's procedure
neglects (C6, a property of the method) and the curve's zero at L/3 (C7, an identity)."""

from __future__ import annotations

import math

import numpy as np

from lineload import paper
from lineload.claims.rows import COORDINATES_FIGURE, _every, _list, _n, _pct, _row, _smallest_margin
from lineload.claims.statistics import _L_sensitivity, waterbed_zero_crossing_mm
from lineload.claims.trials import (
    PAPER_FIT,
    _averaged_covariance_mm2,
    _finite_L,
    _label,
    _trials,
    _window_points,
)
from lineload.claims.verdicts import FAILS, HOLDS, IDENTITY, NO_MARGIN, UNTESTABLE, InternalError
from lineload.distributions import normal_quantile
from lineload.fitting.sensitivity import curve_gap_mm
from lineload.models import arc_deflection_mm, waterbed_deflection_mm, waterbed_shift_mm
from lineload.publishing.tables import at_bound, format_fixed
from lineload.publishing.tables import span_text as _span

__all__ = [
    "claim_c5",
    "claim_c6",
    "claim_c7",
]


def _scaled_interval(fit, model, z):
    """A trial's interval on L at another level: each side of the fit's 95 % profile
    interval scaled by ``z / z_0.975`` (the profile is close to quadratic at these
    widths; :mod:`lineload.simulation.coverage` measures the 95 % interval's coverage)."""
    L_mm = float(fit[f"{model}_L_mm"])
    scale = z / normal_quantile(0.975)
    low = float(fit.get(f"{model}_L_ci_low_mm", math.nan))
    high = float(fit.get(f"{model}_L_ci_high_mm", math.nan))
    return L_mm - scale * (L_mm - low), L_mm + scale * (high - L_mm)


def _crosses_between_windows(fit, model, low_mm, high_mm):
    """Whether the fit's L, found again in the other configured windows, lies on both
    sides of an end of the range (False where the table has no such columns)."""
    smallest = float(fit.get(f"{model}_L_window_min_mm", math.nan))
    largest = float(fit.get(f"{model}_L_window_max_mm", math.nan))
    if not (math.isfinite(smallest) and math.isfinite(largest)):
        return False
    return any(smallest < end < largest for end in (low_mm, high_mm))


def claim_c5(fits, averaged, settings):
    """C5: the true L between 10 and 15 mm, under the paper's procedure: a range test
    with each trial's interval (shifted fit beside)."""
    low, high = paper.L_RANGE_MM
    alpha = settings.significance
    rule = (
        f"A test of the range [{low:g}, {high:g}] mm (the paper's) on each trial's L fitted "
        "by the paper's procedure, with its interval (GLS with the measured noise; other "
        "levels scaled from the 95 % profile interval). A trial is inside if its "
        f"{format_fixed(100 * (1 - 2 * alpha), 0)} % interval lies within the range (two "
        f"one-sided tests at significance = {alpha:g}), outside if its interval at "
        f"{format_fixed(100 * (1 - alpha), 0)} %, Bonferroni over the trials, lies wholly "
        "above or below it. Holds if every trial is inside; does not hold if some trial is "
        "outside; cannot be checked otherwise (the readings cannot place L relative to the "
        "range's ends). A trial whose fit ended on a bound of its search is undecided: its L "
        "is a bound, not a measurement. L is the half-width for the fit window: a trial whose "
        "L crosses an end of the range between the configured windows (the fit table's "
        "L_window_min_mm and L_window_max_mm) is undecided too. The same for the shifted "
        "parabola (the small-slope solution in measured coordinates) is given beside it, "
        "not deciding."
    )
    z_inside = normal_quantile(1.0 - alpha)
    outcomes = {}
    for model in (PAPER_FIT, "shifted"):
        rows = [f for f in fits.to_dict("records") if _finite_L(f, model)]
        z_outside = normal_quantile(1.0 - alpha / (2 * max(len(rows), 1)))
        inside, outside, unsure, L_mm, bounded, windowed = [], [], [], [], [], []
        for fit in rows:
            L_mm.append(float(fit[f"{model}_L_mm"]))
            if at_bound(fit, model):
                # a bound of the search, not a measurement: no side of the range is shown
                bounded.append(_label(fit))
                unsure.append(_label(fit))
                continue
            if _crosses_between_windows(fit, model, low, high):
                # L is the half-width for a window; another window puts it across an end
                windowed.append(_label(fit))
                unsure.append(_label(fit))
                continue
            in_low, in_high = _scaled_interval(fit, model, z_inside)
            out_low, out_high = _scaled_interval(fit, model, z_outside)
            if in_low >= low and in_high <= high:
                inside.append(_label(fit))
            elif out_low > high or out_high < low:
                outside.append(_label(fit))
            else:
                unsure.append(_label(fit))
        outcomes[model] = (np.array(L_mm), inside, outside, unsure, bounded, windowed)
    L_paper, inside, outside, unsure, bounded, windowed = outcomes[PAPER_FIT]
    L_shift, inside_s, outside_s, unsure_s, _, _ = outcomes["shifted"]
    if L_paper.size == 0:
        return _row("C5", "no waterbed fit", UNTESTABLE, "No trial has a waterbed fit.", rule)
    our = (
        f"paper's procedure: L = {_span(L_paper)}; of {_n(L_paper.size, 'trial')} "
        f"{len(inside)} inside, {len(outside)} outside, {len(unsure)} undecided"
        + (f" ({len(bounded)} of them with L on a bound of its search)" if bounded else "")
        + (
            f" ({len(windowed)} of them with L across an end of the range in another window)"
            if windowed
            else ""
        )
        + "; "
        f"shifted parabola: L = {_span(L_shift)}, {len(inside_s)} inside, "
        f"{len(outside_s)} outside, {len(unsure_s)} undecided"
    )
    if outside:
        verdict = FAILS
        reason = (
            f"Fitted the paper's way, L lies outside {low:g}-{high:g} mm beyond its "
            f"uncertainty in {_list(outside)}"
        )
    elif not unsure:
        verdict = HOLDS
        reason = (
            f"Fitted the paper's way, L lies within {low:g}-{high:g} mm in "
            f"{_every(len(inside), 'trial')}, interval included"
        )
    else:
        verdict = UNTESTABLE
        reason = f"No trial's L is outside {low:g}-{high:g} mm beyond its uncertainty, but"
        reaching = [label for label in unsure if label not in bounded and label not in windowed]
        if reaching:
            reason += f" in {_list(reaching)} the interval reaches past an end of the range"
        if bounded:
            reason += (
                f"{' and' if reaching else ''} in {_list(bounded)} the fit ended on a bound of "
                "its search (the readings want a membrane the model does not allow), so L "
                "there is not a measurement"
            )
        if windowed:
            reason += (
                f"{' and' if reaching or bounded else ''} in {_list(windowed)} L, the "
                "half-width for the fit window, falls on the other side of an end of the "
                "range in another of the configured windows"
            )
    if L_shift.size == 0:
        reason += "; there is no fit in measured coordinates to compare."
    elif outside_s == outside and unsure_s == unsure:
        reason += "; the shifted parabola agrees, trial for trial."
    else:
        reason += (
            f"; in measured coordinates (shifted parabola) {len(outside_s)} "
            f"{'is' if len(outside_s) == 1 else 'are'} outside and {len(unsure_s)} undecided "
            f"instead ({COORDINATES_FIGURE})."
        )
    return _row("C5", our, verdict, reason, rule)


def claim_c6(fits, averaged, settings):
    """C6: the paper's small-slope procedure against the exact arc, an equivalence test.

    A property of the paper's method at the data's W0/L, not evidence about fingers
    (its kind in :mod:`lineload.claims.registry`): reported, not counted.
    """
    margin = settings.shift_margin
    alpha = settings.significance
    z_equivalence = normal_quantile(1.0 - alpha)
    rule = (
        "A property of the paper's method at the data's W₀/L, not counted as evidence about "
        "fingers: both fits are one-parameter curves of the same membrane, so the gap "
        "between their L is fixed by W₀/L up to a standard error of hundredths of a percent. "
        "An equivalence test with the workflow's margin (config claims: shift_margin = "
        f"{_pct(margin, 0)}, reasons in the config schema; not the paper's 8 %, a bound on "
        "|U|/X). Neglecting U (eq. 19 read at the deformed position) is negligible if it "
        f"changes the fitted L by less than {_pct(margin, 0)}. The reference is the exact arc, the "
        "finite-deformation solution of the same membrane (consistent in both coordinates). "
        "Per trial with both fits: the paired relative difference d = (L of the paper's "
        "procedure − L of the arc) / L of the arc, both from the same readings, with its "
        "standard error from the fits' "
        "first-order sensitivities to the readings (misfit included) and the measured noise "
        "(the noise table: reading and tracing errors, and the priors for what the "
        "left-right differences cannot see or measure, the side offsets in the shared "
        "offset's). "
        f"Equivalent if the {format_fixed(100 * (1 - 2 * alpha), 0)} % interval of "
        f"d lies inside ±{_pct(margin, 0)} (two one-sided tests at significance = "
        f"{alpha:g}); different if its {format_fixed(100 * (1 - 2 * alpha / 2), 0)} % "
        "interval, Bonferroni over the trials, lies outside. Holds if every trial is "
        "equivalent; does not hold if some trial is different; cannot be checked otherwise "
        "(so also where a trial's paper or arc fit ended on a bound of its search: there L is "
        "a bound, not a measurement, and the trial is left out, counted). Beside it, not "
        "deciding: the largest gap between the two fitted curves against the reading noise, "
        "the paper's own bound |U(L/3)| / (L/3) from eq. 20, the shifted "
        "parabola (eq. 19 placed at x = X + U) as a sensitivity, and the smallest margin of "
        "1-20 % at which the claim holds."
    )
    rows, bounded = [], []
    for fit, points in _trials(fits, averaged):
        if not (_finite_L(fit) and _finite_L(fit, "arc")) or points.empty:
            continue
        if at_bound(fit, PAPER_FIT) or at_bound(fit, "arc"):
            # a bound's L does not move with the readings as a minimum's does: no error
            bounded.append(_label(fit))
            continue
        x, y, sides = _window_points(fit, points)
        if x.size < 2:
            continue
        depth_mm = float(fit["depth_mm"])
        L_paper, L_arc = float(fit["waterbed_L_mm"]), float(fit["arc_L_mm"])
        # d = L_paper / L_arc - 1 moves with the readings as J . noise
        J = _L_sensitivity(waterbed_deflection_mm, x, depth_mm, L_paper, y) / L_arc
        J = J - _L_sensitivity(arc_deflection_mm, x, depth_mm, L_arc, y) * L_paper / L_arc**2
        covariance = _averaged_covariance_mm2(x, sides, y, fit, settings)
        sd = math.sqrt(max(float(J @ covariance @ J), 0.0))
        shift_mm = float(waterbed_shift_mm(L_paper / 3.0, depth_mm, L_paper))
        rows.append(
            {
                "label": _label(fit),
                "d": L_paper / L_arc - 1.0,
                "sd": sd,
                "gap_mm": curve_gap_mm(
                    depth_mm, L_paper, L_arc, float(fit["max_distance_mm"]), "arc"
                ),
                "fraction": abs(shift_mm) / (L_paper / 3.0),
                "shifted": float(fit["shifted_L_mm"]) / L_arc - 1.0
                if _finite_L(fit, "shifted")
                else math.nan,
            }
        )
    bounded_text = (
        f"; left out: {_list(bounded)}, where the paper's or the arc's L ended on a bound "
        "of its search (a bound, not a measurement)"
        if bounded
        else ""
    )
    if not rows:
        return _row(
            "C6",
            "no trial with both the paper's and the exact-arc fit" + bounded_text,
            UNTESTABLE,
            "No trial has both the paper's fit and the exact arc's off the bounds of their search.",
            rule,
            NO_MARGIN,
        )
    d = np.array([r["d"] for r in rows])
    sd = np.array([r["sd"] for r in rows])
    z_difference = normal_quantile(1.0 - alpha / (2 * len(rows)))

    def tests(margin):
        equivalent = (d - z_equivalence * sd > -margin) & (d + z_equivalence * sd < margin)
        return equivalent, (np.abs(d) - z_difference * sd) > margin

    def decide(margin):
        equivalent, different = tests(margin)
        return FAILS if different.any() else HOLDS if equivalent.all() else UNTESTABLE

    smallest = _smallest_margin(decide)
    equivalent, different = tests(margin)
    gaps = np.array([r["gap_mm"] for r in rows])
    fractions = np.array([r["fraction"] for r in rows])
    shifted = np.array([r["shifted"] for r in rows])
    our = (
        f"L of the paper's procedure differs from the arc's by {_span(100 * d, 1, ' %')}, standard "
        f"error {_span(100 * sd, 3, ' %')}; equivalent within ±{_pct(margin, 0)} in "
        f"{int(equivalent.sum())} of {_n(d.size, 'trial')}, different in "
        f"{int(different.sum())}; largest gap between the curves {_span(gaps, 3, ' mm')} "
        f"(reading noise {format_fixed(settings.reading_noise_mm, 3)} mm); "
        "paper's bound |U(L/3)| / (L/3) "
        f"{_span(100 * fractions, 1, ' %')}; shifted parabola against the arc "
        f"{_span(100 * shifted[np.isfinite(shifted)], 1, ' %')}" + bounded_text
    )
    labels = [r["label"] for r in rows]
    if different.any():
        failing = [lab for lab, f in zip(labels, different, strict=True) if f]
        reason = (
            f"In {_list(failing)} the paper's procedure puts L further than "
            f"{_pct(margin, 0)} from the exact arc's, beyond the uncertainty: neglecting U "
            "is not negligible there."
        )
        return _row("C6", our, FAILS, reason, rule, smallest)
    if equivalent.all() and not bounded:
        reason = (
            f"In {_every(d.size, 'trial')} the paper's L is within {_pct(margin, 0)} of the "
            f"exact arc's ({_span(100 * d, 1, ' %')}), interval included: neglecting U costs "
            "less than the margin."
        )
        return _row("C6", our, HOLDS, reason, rule, smallest)
    if equivalent.all():
        reason = (
            f"In {_every(d.size, 'trial')} with both fits off their bounds the paper's L is "
            f"within {_pct(margin, 0)} of the exact arc's, interval included, but in "
            f"{_list(bounded)} a fit ended on a bound of its search: there the difference "
            "is not measured."
        )
        return _row("C6", our, UNTESTABLE, reason, rule, smallest)
    open_ = [lab for lab, e in zip(labels, equivalent, strict=True) if not e]
    reason = (
        f"In {_list(open_)} the interval of the difference reaches past {_pct(margin, 0)}: "
        "these data cannot tell whether neglecting U stays within the margin."
    )
    return _row("C6", our, UNTESTABLE, reason, rule, smallest)


def claim_c7(fits, averaged, settings, deflection=None):
    """C7: the fitted curve crosses zero at L/3 (an identity of eq. 19, checked numerically).

    ``deflection`` replaces eq. 19 (tests use it to show the check can fail).
    """
    rtol = settings.zero_crossing_rtol
    rule = (
        "An identity of eq. 19, not evidence: per trial with a finite fitted L, the zero of "
        "the fitted waterbed curve found by Brent's method on [0, 2L/3] (not from the "
        f"formula) must equal L/3 within a relative {rtol:.0e} (floating-point accuracy); "
        "that checks the implementation. 'identity' if it does in every trial; if not, the "
        "build stops with an internal error naming the trial (a bug is never evidence)."
    )
    deviations, labels = [], []
    for _, fit in fits.iterrows():
        if not _finite_L(fit) or not float(fit["depth_mm"]) > 0:
            continue
        L_mm = float(fit["waterbed_L_mm"])
        root_mm = waterbed_zero_crossing_mm(float(fit["depth_mm"]), L_mm, deflection)
        deviations.append(abs(root_mm / (L_mm / 3.0) - 1.0))
        labels.append(_label(fit))
    if not deviations:
        return _row(
            "C7",
            "no trial with a finite fitted L",
            UNTESTABLE,
            "No trial has a finite fitted L whose curve could be checked.",
            rule,
        )
    deviations = np.array(deviations)
    worst = int(np.argmax(deviations))
    if deviations[worst] > rtol:
        raise InternalError(
            f"internal error: the fitted waterbed curve of {labels[worst]} crosses zero at "
            f"{1 + deviations[worst]:.9g} x L/3, not at L/3 as eq. 19 requires of any L; the "
            "curve code is wrong (this is a bug, not a property of the data)"
        )
    our = (
        f"numerical zero / (L/3) - 1: largest |deviation| {deviations.max():.1e} over "
        f"{_n(deviations.size, 'trial')}"
    )
    reason = (
        "Every fitted curve crosses zero at L/3, as eq. 19 requires of any L; this says "
        "nothing about the fingertip."
    )
    return _row("C7", our, IDENTITY, reason, rule)
