"""Later work (C12): a layered elastic finger describes the profiles better than a homogeneous
one, beyond the noise and beyond what a wrong geometry gives (:mod:`lineload.fitting.elastic`).

Dandekar, Raju and Srinivasan (2003) found that a finite-element fingertip needed a stiffer
outer layer over soft pulp to match the line-load surface deflections. The rule asks the same
of the fits by interpolation in the solution library, per trial and then per species:

- the layered fit's improvement ``D = SSE(homogeneous) - SSE(layered)`` (mm^2, never
  negative: the layered fit's search includes ratio 1) against the noise,
  ``D / s^2 > chi2_2(1 - significance)``: a likelihood ratio with the layer's two extra
  parameters (ratio and thickness), ``s^2`` the mean noise variance of the trial's averaged
  points under its noise model, as C13 takes it;
- the part of the misfit the layer removes, relative to the depth,
  ``g = sqrt(max(D - 2 s^2, 0) / n) / W0`` (the two extra parameters take ``2 s^2`` of pure
  noise on average), against the geometry margin (``claims: elastic_margin``): the largest
  ``g`` the study ``docs/calibration/scripts/elastic_layer_margin.py`` measured on
  noise-free homogeneous fingers whose sections the library does not hold. The fits
  already take the section as a nuisance over the library's; the margin is what that
  nuisance's coarseness still leaks into the layer.

A trial is *layered* when both pass, *homogeneous enough* when ``g`` is within the margin,
and *unresolved* otherwise (a gain above the margin that the noise could have made).
"""

from __future__ import annotations

import math

import numpy as np

from lineload.claims.rows import _n, _row
from lineload.claims.trials import _averaged_covariance_mm2, _trials, _window_points
from lineload.claims.verdicts import FAILS, HOLDS, UNTESTABLE
from lineload.distributions import chi2_quantile
from lineload.publishing.tables import format_fixed, span_text

__all__ = [
    "HOMOGENEOUS_ENOUGH",
    "LAYERED",
    "LAYER_PARAMETERS",
    "UNRESOLVED",
    "claim_c12",
    "layer_call",
    "species_verdict",
]

#: What the layered fit adds to the homogeneous one: the modulus ratio and the layer's
#: thickness (the section is a nuisance of both).
LAYER_PARAMETERS = 2
#: A trial's call.
LAYERED = "layered"
HOMOGENEOUS_ENOUGH = "homogeneous enough"
UNRESOLVED = "unresolved"


def layer_call(
    sse_homogeneous_mm2, sse_layered_mm2, n_points, noise_var_mm2, depth_mm, margin, significance
):
    """One trial's call: is its layer beyond the noise and beyond the geometry margin?

    Parameters
    ----------
    sse_homogeneous_mm2, sse_layered_mm2 : float
        The two fits' sums of squares on the same points (mm^2).
    n_points : int
        Points fitted.
    noise_var_mm2 : float
        Mean noise variance of those points (mm^2).
    depth_mm : float
        The indentation depth W0 (mm).
    margin : float
        The geometry margin, a fraction of W0.
    significance : float
        Error rate of the noise test.

    Returns
    -------
    dict
        ``statistic`` (``D / s^2``), ``threshold`` (the chi-square point), ``gain`` (``g``,
        a fraction of W0) and ``call`` (:data:`LAYERED`, :data:`HOMOGENEOUS_ENOUGH` or
        :data:`UNRESOLVED`).
    """
    improvement = max(float(sse_homogeneous_mm2) - float(sse_layered_mm2), 0.0)
    statistic = improvement / noise_var_mm2
    threshold = float(chi2_quantile(1 - significance, LAYER_PARAMETERS))
    excess = max(improvement - LAYER_PARAMETERS * noise_var_mm2, 0.0)
    gain = math.sqrt(excess / n_points) / depth_mm
    if gain <= margin:
        call = HOMOGENEOUS_ENOUGH
    elif statistic > threshold:
        call = LAYERED
    else:
        call = UNRESOLVED
    return {"statistic": statistic, "threshold": threshold, "gain": gain, "call": call}


def species_verdict(calls):
    """A species' verdict from its trials' calls: holds if more than half are layered, does
    not hold if more than half are homogeneous enough, cannot be checked otherwise."""
    calls = list(calls)
    if sum(c == LAYERED for c in calls) * 2 > len(calls):
        return HOLDS
    if sum(c == HOMOGENEOUS_ENOUGH for c in calls) * 2 > len(calls):
        return FAILS
    return UNTESTABLE


def claim_c12(fits, averaged, settings):
    """C12 (later work, Dandekar, Raju and Srinivasan 2003): a layered elastic finger describes
    the profiles better than a homogeneous one, beyond the noise and the geometry's margin.

    Reads the elastic fits' columns joined to the fit table
    (:func:`lineload.fitting.elastic.with_elastic`); without them, or with no trial fitted,
    the claim cannot be checked.
    """
    alpha, margin = settings.significance, settings.elastic_margin
    rule = (
        "Per trial, on the elastic fits' points (the fit window): D = SSE(homogeneous) − "
        "SSE(layered), the section a nuisance of both fits and the ratio and layer thickness "
        f"the layer's {LAYER_PARAMETERS} extra parameters. The layer is beyond the noise if "
        f"D/s² exceeds the {format_fixed(100 * (1 - alpha), 0)} % point of chi-square with "
        f"{LAYER_PARAMETERS} degrees of freedom (significance = {alpha:g}), s² the mean noise "
        "variance of the points under the trial's noise model; it is beyond the geometry if "
        f"g = √(max(D − {LAYER_PARAMETERS}s², 0)/n)/W₀ exceeds elastic_margin = "
        f"{format_fixed(100 * margin, 1)} % of the depth (config claims: elastic_margin; its "
        "default comes from g measured on noise-free homogeneous fingers whose sections the "
        "library does not hold, docs/calibration/elastic_layer_margin.md). A trial is "
        "layered if both, homogeneous enough if g is within the margin, unresolved "
        "otherwise. Per species: holds if more "
        "than half its fitted trials are layered, does not hold if more than half are "
        "homogeneous enough. Holds if it holds in every species with elastic fits; does not "
        "hold if it does not hold in at least one; cannot be checked otherwise or without "
        "elastic fits."
    )
    needed = ("elastic_homogeneous_sse_mm2", "elastic_layered_sse_mm2")
    if any(column not in fits for column in needed):
        return _row(
            "C12", "no elastic fits", UNTESTABLE, "The elastic finger was not fitted.", rule
        )
    calls, at_bound = {}, {}
    for fit, points in _trials(fits, averaged):
        homogeneous = float(fit["elastic_homogeneous_sse_mm2"])
        layered = float(fit["elastic_layered_sse_mm2"])
        depth_mm = float(fit["depth_mm"])
        if points.empty or not (math.isfinite(homogeneous) and math.isfinite(layered)):
            continue
        x, w, sides = _window_points(fit, points)
        if x.size < 2 or not depth_mm > 0:
            continue
        noise = float(np.mean(np.diag(_averaged_covariance_mm2(x, sides, w, fit, settings))))
        call = layer_call(homogeneous, layered, x.size, noise, depth_mm, margin, alpha)
        species = str(fit["species"])
        calls.setdefault(species, []).append(call)
        # at the library's largest ratio (the flag also marks an estimate of 1)
        bound = float(fit.get("elastic_layered_ratio_at_bound", 0.0)) == 1.0
        above_one = float(fit.get("elastic_layered_modulus_ratio", 1.0)) > 1.0
        at_bound[species] = at_bound.get(species, 0) + int(bound and above_one)
    if not calls:
        return _row(
            "C12",
            "no trial with elastic fits",
            UNTESTABLE,
            "No trial has elastic fits (the library lacks its species or depth, or its "
            "points reach past the library).",
            rule,
        )
    verdicts, parts = {}, []
    for species in sorted(calls):
        found = calls[species]
        verdicts[species] = species_verdict(c["call"] for c in found)
        counts = {
            name: sum(c["call"] == name for c in found)
            for name in (LAYERED, HOMOGENEOUS_ENOUGH, UNRESOLVED)
        }
        gains = [c["gain"] for c in found]
        parts.append(
            f"{species}: {_n(len(found), 'trial')}, {counts[LAYERED]} layered, "
            f"{counts[HOMOGENEOUS_ENOUGH]} homogeneous enough, {counts[UNRESOLVED]} "
            f"unresolved; "
            # g named with what it is where the text first uses it
            + (
                "g "
                if parts
                else "the layer's gain g (the RMS misfit it removes beyond "
                "the noise, as a share of the depth W₀) "
            )
            + f"{span_text([100 * g for g in gains], 1, ' %')}; "
            f"layered ratio at the library's largest in {at_bound[species]}"
        )
    our = "; ".join(parts)
    if any(v == FAILS for v in verdicts.values()):
        failing = ", ".join(s for s, v in verdicts.items() if v == FAILS)
        reason = (
            f"In {failing} the layer removes no more of the misfit than a wrong geometry "
            "gives a homogeneous finger, in more than half the trials."
        )
        return _row("C12", our, FAILS, reason, rule)
    if all(v == HOLDS for v in verdicts.values()):
        reason = (
            "In every species the layered finger describes more than half the trials better "
            "than the homogeneous one, beyond the noise and the geometry's margin"
        )
        if sum(at_bound.values()):
            reason += (
                f"; in {_n(sum(at_bound.values()), 'trial')} its ratio sits at the library's "
                "largest, so the ratio itself is not estimated there"
            )
        return _row("C12", our, HOLDS, reason + ".", rule)
    reason = (
        "Too few trials are resolved either way: the layer's gain is above the geometry's "
        "margin but within what the noise could make, or the calls are split."
    )
    return _row("C12", our, UNTESTABLE, reason, rule)
