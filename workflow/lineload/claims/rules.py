"""The paper's quantitative claims, recomputed from the fits and the averaged profiles.

Each claim C1-C11 of the paper (text in :data:`CLAIM_TEXT`) has one function that
computes numbers from the fit table and the left/right mean profiles (C11 also
from the force readings, when there are any), then applies a rule stated in
words (with its thresholds) to reach a verdict.  No verdict is
written in advance.  The verdicts (:data:`VERDICTS`) separate evidence from
algebra:

``holds`` / ``does not hold``
    The data were tested, and the rule could have come out either way (the tests
    build a violating and a satisfying dataset for every claim).
``cannot be checked on these data``
    The data hold nothing the rule can test; ``our_value`` says why.
``identity``
    The statement follows from the model's equations alone (C7).  The rule
    checks that the fitted curves obey it, which tests the code, not the
    fingertip; it is not counted as evidence (:func:`verdict_counts`).

Every row also carries one sentence of ``reason`` for a reader, and the ``rule``
in full.

Inputs
------
fits : pandas.DataFrame
    The fit table, one row per subject and depth (columns of
    :data:`lineload.fitting.batch.FIT_COLUMNS`; ``fit_window_mm`` says which points
    were fitted).
averaged : pandas.DataFrame
    The averaged profiles of every subject, stacked (columns of
    :data:`lineload.averaging.AVERAGED_COLUMNS`).
forces : pandas.DataFrame or None
    The optional force readings (``subject``, ``depth_mm``, ``force_N``); only
    C11 takes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import brentq
from scipy.stats import norm
from scipy.stats import t as student_t

from lineload import mechanics, paper
from lineload.fitting.batch import in_fit_window
from lineload.fitting.sensitivity import curve_gap_mm
from lineload.io import config_defaults
from lineload.models import (
    arc_deflection_mm,
    boussinesq_deflection_mm,
    shifted_deflection_mm,
    waterbed_deflection_mm,
    waterbed_shift_mm,
)
from lineload.noise import NoiseModel
from lineload.publishing.tables import (
    at_bound,
    counted,
    every,
    format_fixed,
    join_words,
    markdown_table,
    notice_footer,
    percent_text,
)
from lineload.publishing.tables import span_text as _span

__all__ = [
    "CLAIM_COLUMNS",
    "CLAIM_FUNCTIONS",
    "CLAIM_IDS",
    "CLAIM_KINDS",
    "EVIDENCE_VERDICTS",
    "FORCE_CLAIMS",
    "MARGIN_GRID",
    "PAPER_CLAIM",
    "PAPER_SUGGESTION",
    "VERDICTS",
    "ClaimSettings",
    "InternalError",
    "chord_curvature",
    "claims_markdown",
    "compute_claims",
    "deformed_extent_mm",
    "deformed_extent_se_mm",
    "trial_key",
    "verdict_counts",
    "waterbed_zero_crossing_mm",
]


class InternalError(RuntimeError):
    """A check that can only fail through a bug in this code (never evidence)."""


HOLDS = "holds"
FAILS = "does not hold"
UNTESTABLE = "cannot be checked on these data"
IDENTITY = "identity"
#: The only verdicts a claim can get.
VERDICTS = (HOLDS, FAILS, UNTESTABLE, IDENTITY)
#: The verdicts that are evidence about the data (the others are not counted).
EVIDENCE_VERDICTS = (HOLDS, FAILS)

PAPER_CLAIM = "paper claim"
METHOD_PROPERTY = "property of the method"
METHOD_IDENTITY = "identity of the method"
MODEL_CHECK = "model-consistency check"
PAPER_SUGGESTION = "the paper's closing suggestion"
#: What each row is.  Only the paper's claims about fingers are counted as evidence
#: (:func:`verdict_counts`); the others are checked and reported apart:
#:
#: - C6 is a property of the paper's method at the data's W0/L, not evidence about
#:   fingers: both fits are one-parameter curves of the same membrane, so the gap
#:   between the paper's L and the exact arc's is fixed by W0/L (the arc and the
#:   parabola differ by about 1 % of W0 at W0/L = 0.1 and 4 % at 0.2) up to a standard
#:   error of hundredths of a percent; its verdict is a function of W0/L, the fingers
#:   entering only through L, which C5 tests.
#: - C7 is an identity of eq. 19.
#: - C11 is a claim the paper never makes: whether the fitted shapes and the forces go
#:   with the stress-free membrane, a check of the model's consistency.
CLAIM_KINDS = {
    **{claim: PAPER_CLAIM for claim in ("C1", "C2", "C3", "C4", "C5", "C8", "C9", "C10")},
    "C6": METHOD_PROPERTY,
    "C7": METHOD_IDENTITY,
    "C11": MODEL_CHECK,
    "C13": PAPER_SUGGESTION,
}

#: The margins searched for the smallest at which an equivalence test holds (C2, C6, C10).
MARGIN_GRID = tuple(k / 100 for k in range(1, 21))
#: ``smallest_margin`` where no margin of the grid makes the claim hold.
NO_MARGIN = "none"

#: Columns of the claims table, in order.
CLAIM_COLUMNS = [
    "claim",
    "kind",
    "statement",
    "paper_location",
    "paper_value",
    "our_value",
    "verdict",
    "smallest_margin",
    "reason",
    "rule",
]

#: The waterbed fits in the fit table: the paper's procedure and the two in
#: measured coordinates, with the words used for them in the table.
PAPER_FIT = "waterbed"
CONSISTENT_FITS = ("shifted", "arc")
FIT_WORDS = {
    "waterbed": "the paper's procedure",
    "shifted": "the shifted parabola",
    "arc": "the exact arc",
}
CURVES = {
    "waterbed": waterbed_deflection_mm,
    "shifted": shifted_deflection_mm,
    "arc": arc_deflection_mm,
}

#: The claim in our words, where the paper makes it, and what the paper gives.
CLAIM_TEXT = {
    "C1": (
        "At the same indentation depth the skin is deformed over a wider region in humans "
        "than in monkeys.",
        "Results, first paragraph; Fig. 7 caption",
        "humans 6-12 mm vs monkeys 3-7 mm from the wedge",
    ),
    "C2": (
        "The deflection profile is close to symmetric about the wedge (left side vs right side).",
        "Results, first paragraph (last sentence); Fig. 1 caption",
        "generally symmetrical (no number given)",
    ),
    "C3": (
        "Close to the load (within about 3 mm) the waterbed profile fits the data better than "
        "the modified Boussinesq profile.",
        "Abstract; Fig. 2 caption; Results, 'Comparison of theoretical and experimental "
        "results', end of paragraph; Discussion, second paragraph",
        "waterbed much better than Boussinesq up to about 3 mm (no number given)",
    ),
    "C4": (
        "Beyond about 3 mm from the load the waterbed is wrong: it predicts an upward bulge "
        "(W < 0) between L/3 and L which the measured skin does not show.",
        "Discussion, second paragraph",
        "bulge W < 0 on L/3 < X < L predicted, not observed",
    ),
    "C5": (
        "The fitted membrane half-width L lies between 10 and 15 mm.",
        "Results, 'Comparison of theoretical and experimental results' (Figs 6 and 7)",
        "10-15 mm",
    ),
    "C6": (
        "The horizontal shift U of the membrane is negligible: at X = L/3, where it is "
        "largest (8W₀²/(9L)), it is a small fraction of X.",
        "Results, 'Comparison of theoretical and experimental results'",
        "< 8 % of X",
    ),
    "C7": (
        "Each fitted waterbed curve crosses the zero line at X = L/3, where U is largest.",
        "Results, 'Comparison of theoretical and experimental results' (from eqs 19-20)",
        "X = L/3",
    ),
    "C8": (
        "The waterbed describes the data less well the deeper the indentation.",
        "Discussion, third (last) paragraph",
        "accuracy falls as depth increases (no number given)",
    ),
    "C9": (
        "At the larger depths the measured deflection within about 3 mm of the load is "
        "smaller than the waterbed predicts, i.e. the fingertip is stiffer than the model.",
        "Discussion, third (last) paragraph (last sentence); Figs 6 and 7",
        "data within 3 mm deflected less than the model curve at the higher depths, in all cases "
        "shown",
    ),
    "C10": (
        "Skin that does not touch the indenter takes a circular (constant-curvature) shape.",
        "Discussion, third (last) paragraph (eqs 4-5); Fig. 1 caption",
        "approximately circular on either side of the load (no number given)",
    ),
    "C11": (
        "(Implicit) The forces measured on the wedge fit the proposed membrane, which carries "
        "no tension at rest (N = Eε): through F = 2N sin θ₀, the fitted shapes fix "
        "how fast the force must grow with depth.",
        "Methods, 'Experimental procedure' (force range); eqs 3 and 7",
        f"{paper.FORCE_RANGE_N[0]:g}-{paper.FORCE_RANGE_N[1]:g} N over depths of "
        f"{min(paper.DEPTHS_MM):g}-{max(paper.DEPTHS_MM):g} mm: at most "
        f"{paper.FORCE_RANGE_N[1] / paper.FORCE_RANGE_N[0]:.2f} times more force at one depth "
        "than at another",
    ),
    "C13": (
        "(The paper's closing suggestion) The skin's bending stiffness accounts for the "
        "waterbed's worsening with depth: a skin that bends describes the profiles better "
        "than the membrane by more, relative to the deformation, the deeper the wedge.",
        "Discussion, last paragraph",
        "a suggestion, no number: for more accuracy the skin's thickness and bending "
        "rigidity may have to be modelled",
    ),
}

#: Claim ids in table order.
CLAIM_IDS = list(CLAIM_TEXT)

#: Where the reader finds the figure behind the coordinate claims.
COORDINATES_FIGURE = "supplementary figure 'coordinates'"


#: The schema's defaults of the claims' settings: read, never restated.
_DEFAULTS = {**config_defaults("claims"), "force_sd_N": config_defaults("mechanics")["force_sd_N"]}


@dataclass(frozen=True)
class ClaimSettings:
    """Thresholds of the verdict rules (config key ``claims``; defaults from its schema).

    Attributes
    ----------
    noise_mm : float or None
        Digitising noise of one reading of one side (tissue mm, standard
        deviation), set by hand (config ``claims: noise_mm``); None takes it
        from ``noise_model`` (see :attr:`reading_noise_mm`).
    large_depth_mm : float
        Depths at or above this are the 'larger depths' of C9.
    significance : float
        Error rate of the tests of C2, C3, C5, C6, C8, C10 and C11 (Bonferroni
        over the trials or subjects where a claim tests several).
    extent_fraction : float
        C1: the deformed region ends where the deflection falls through this
        fraction of the depth.
    symmetry_margin, shift_margin, circularity_margin : float
        The equivalence margins of C2, C6 and C10, the workflow's own (config keys of
        the same names; the schema gives the reasons).
    force_sd_N : float
        C11: precision of one force reading (N, standard deviation); config key
        ``mechanics: force_sd_N``.
    zero_crossing_rtol : float
        C7: largest relative distance between the numerical zero and L/3.  A
        bound on floating-point error, not on the data, so not a config key.
    noise_model : lineload.noise.NoiseModel or None
        The dataset's digitising noise (the noise table: measured parts and
        priors); the covariance of each trial's averaged points comes from it.
        None: independent readings of ``noise_mm`` and nothing else.
    trial_noise : dict or None
        ``(subject, depth_mm)`` -> the NoiseModel of a trial with rows of its own
        in the noise table (a digitised trial's registration error); the others
        take ``noise_model``.
    prior_multiples : tuple of float
        Multiples of the noise priors at which the claims are computed again
        (:mod:`lineload.priors`); config ``claims: prior_multiples``.
    """

    noise_mm: float | None = _DEFAULTS["noise_mm"]
    large_depth_mm: float = _DEFAULTS["large_depth_mm"]
    significance: float = _DEFAULTS["significance"]
    force_sd_N: float = _DEFAULTS["force_sd_N"]
    extent_fraction: float = _DEFAULTS["extent_fraction"]
    symmetry_margin: float = _DEFAULTS["symmetry_margin"]
    shift_margin: float = _DEFAULTS["shift_margin"]
    circularity_margin: float = _DEFAULTS["circularity_margin"]
    zero_crossing_rtol: float = 1e-6
    noise_model: NoiseModel | None = None
    trial_noise: dict | None = None
    prior_multiples: tuple = tuple(_DEFAULTS["prior_multiples"])

    @property
    def reading_noise_mm(self):
        """One reading's noise: ``noise_mm`` if set, else the noise model's reading and
        tracing errors together (``sqrt(reading**2 + tracing**2)``)."""
        if self.noise_mm is not None:
            return float(self.noise_mm)
        if self.noise_model is None:
            raise ValueError("the claims need noise_mm or a noise model")
        return math.hypot(self.noise_model.reading_sd_mm, self.noise_model.tracing_sd_mm)


# --------------------------------------------------------------------------- helpers


def _mm(value, decimals=2):
    return f"{format_fixed(value, decimals)} mm"


def _pct(fraction, decimals=1):
    return percent_text(fraction, decimals)


#: '1 trial', '3 trials' (:func:`lineload.publishing.tables.counted`).
_n = counted

#: 'the one trial', 'both trials', 'all 3 trials' (:func:`lineload.publishing.tables.every`).
_every = every


def _list(labels, limit=12):
    """'a, b and c': every item up to ``limit``; beyond it the first ones and a count.

    A dataset of thousands of trials cannot be listed in a sentence: then the
    first ``limit`` are named and the rest counted (claims.csv holds each trial).
    """
    labels = list(labels)
    if len(labels) <= limit:
        return join_words(labels)
    return ", ".join(labels[:limit]) + f" and {len(labels) - limit} more (claims.csv per trial)"


def _row(claim, our_value, verdict, reason, rule, smallest_margin=""):
    """One row of the claims table; ``smallest_margin`` only for the equivalence tests."""
    statement, location, paper_value = CLAIM_TEXT[claim]
    if verdict not in VERDICTS:
        raise ValueError(f"{claim}: unknown verdict {verdict!r}")
    return {
        "claim": claim,
        "kind": CLAIM_KINDS[claim],
        "statement": statement,
        "paper_location": location,
        "paper_value": paper_value,
        "our_value": our_value,
        "verdict": verdict,
        "smallest_margin": smallest_margin,
        "reason": reason,
        "rule": rule,
    }


def _smallest_margin(decide):
    """The smallest margin of :data:`MARGIN_GRID` at which ``decide(margin)`` says
    ``holds``, as a percentage ('4 %'), or :data:`NO_MARGIN`."""
    for margin in MARGIN_GRID:
        if decide(margin) == HOLDS:
            return _pct(margin, 0)
    return NO_MARGIN


def trial_key(subject, depth_mm):
    """The key of a trial in per-trial lookups (:attr:`ClaimSettings.trial_noise`)."""
    return (str(subject), round(float(depth_mm), 9))


def _profiles_by_trial(averaged):
    """Averaged points of each (subject, depth), sorted by distance."""
    out = {}
    for (subject, depth_mm), group in averaged.groupby(["subject", "depth_mm"], sort=False):
        out[trial_key(subject, depth_mm)] = group.sort_values("distance_mm", kind="stable")
    return out


def _trials(fits, averaged):
    """Pairs (fit row, averaged points) for every row of the fit table, in its order.

    A trial without averaged points gets an empty frame.
    """
    profiles = _profiles_by_trial(averaged)
    empty = averaged.iloc[0:0]
    for _, fit in fits.iterrows():
        yield fit, profiles.get(trial_key(fit["subject"], fit["depth_mm"]), empty)


def _window_points(fit, points):
    """Distances, deflections and side counts of a trial's fitted points (the fit window)."""
    x = points["distance_mm"].to_numpy(float)
    w = points["deflection_mm"].to_numpy(float)
    sides = points["n_sides"].to_numpy(float)
    keep = in_fit_window(x, float(fit["fit_window_mm"])) & np.isfinite(w)
    return x[keep], w[keep], sides[keep]


def _label(fit):
    return f"{fit['subject']} at {float(fit['depth_mm']):g} mm"


def _finite_L(fit, model=PAPER_FIT):
    L_mm = float(fit[f"{model}_L_mm"])
    return math.isfinite(L_mm) and L_mm > 0


def _noise_sd_mm(noise_mm, n_sides):
    """Noise of each averaged point: one reading's noise over the root of the sides averaged."""
    return noise_mm / np.sqrt(np.maximum(np.asarray(n_sides, dtype=float), 1.0))


# --------------------------------------------------------------------------- numerics


def deformed_extent_mm(distance_mm, deflection_mm, threshold_mm):
    """Distance from the load at which the deflection last falls through a threshold.

    After the farthest point whose deflection exceeds the threshold, the
    profile is interpolated linearly to the next point to find where it
    crosses the threshold.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        One averaged profile (mm), any order.
    threshold_mm : float
        Deflection taken as a real displacement (mm).

    Returns
    -------
    float
        The distance (mm); 0 when no point exceeds the threshold.  When the
        farthest reading still exceeds it, that reading's distance is returned
        (a lower bound: the readings stop while the skin is still displaced).
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    keep = np.isfinite(distance_mm) & np.isfinite(deflection_mm)
    order = np.argsort(distance_mm[keep], kind="stable")
    x, w = distance_mm[keep][order], deflection_mm[keep][order]
    above = np.flatnonzero(w > threshold_mm)
    if above.size == 0:
        return 0.0
    last = int(above[-1])
    if last == x.size - 1:
        return float(x[last])
    step = (w[last] - threshold_mm) / (w[last] - w[last + 1])
    return float(x[last] + step * (x[last + 1] - x[last]))


def deformed_extent_se_mm(distance_mm, deflection_mm, threshold_mm, covariance_mm2):
    """:func:`deformed_extent_mm` with its standard error under the readings' noise.

    The extent is where the line between the last point above the threshold and
    the next one crosses it.  To first order an error ``e`` of the interpolated
    deflection there moves the crossing by ``e / |slope|``; ``e`` has the variance
    of ``(1 - s) w_i + s w_(i+1)`` (``s`` the crossing's fraction of the step)
    under the covariance.  Where the farthest reading is still above the threshold
    the extent is a lower bound and its error is taken from the last step's slope.
    First order only: where the noise is comparable to the drop over one step, the
    last point above the threshold can change and the spread is larger (by 15 % on
    a straight decay with noise a quarter of a step's drop).

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        One averaged profile (mm), sorted by distance, all finite.
    threshold_mm : float
        As for :func:`deformed_extent_mm`.
    covariance_mm2 : array_like
        ``(n, n)`` covariance of the deflections (mm^2).

    Returns
    -------
    tuple of float
        ``(extent_mm, se_mm)``; ``(0, 0)`` when no point exceeds the threshold.
    """
    x = np.asarray(distance_mm, dtype=float)
    w = np.asarray(deflection_mm, dtype=float)
    c = np.asarray(covariance_mm2, dtype=float)
    extent = deformed_extent_mm(x, w, threshold_mm)
    above = np.flatnonzero(w > threshold_mm)
    if above.size == 0 or x.size < 2:
        return extent, 0.0
    i = int(above[-1])
    i, j = (i, i + 1) if i + 1 < x.size else (i - 1, i)
    s = float(np.clip((extent - x[i]) / (x[j] - x[i]), 0.0, 1.0))
    a = np.array([1.0 - s, s])
    variance = float(a @ c[np.ix_([i, j], [i, j])] @ a)
    slope = abs((w[j] - w[i]) / (x[j] - x[i]))
    if not slope > 0:
        return extent, math.inf
    return extent, math.sqrt(max(variance, 0.0)) / slope


def waterbed_zero_crossing_mm(depth_mm, L_mm, deflection=None):
    """Zero of a fitted small-slope waterbed curve inside the membrane, found numerically.

    Brent's method over ``[0, 2 L / 3]``: eq. 19 equals ``W0 > 0`` at the load and
    ``-W0 / 3`` at ``2 L / 3`` (the bottom of the bulge), so the bracket holds
    exactly one sign change.  Analytically the zero is ``L / 3``; this function
    does not use that.

    Parameters
    ----------
    depth_mm : float
        W0 (mm, > 0).
    L_mm : float
        Fitted half-width (mm, finite, > 0).
    deflection : callable, optional
        The curve ``f(distance_mm, depth_mm, L_mm)``; defaults to
        :func:`lineload.models.waterbed_deflection_mm` (eq. 19).

    Returns
    -------
    float
        The zero crossing (mm).
    """
    deflection = deflection or waterbed_deflection_mm

    def curve(distance_mm):
        return float(deflection(distance_mm, depth_mm, L_mm))

    return float(brentq(curve, 0.0, 2.0 * L_mm / 3.0, xtol=1e-14 * L_mm, rtol=1e-15))


def _chord_curvature_gls(x, w, covariance):
    """:func:`chord_curvature` with a full covariance of the deflections."""
    weight = np.linalg.inv(covariance)
    design = np.column_stack([np.ones_like(x), x])
    slope = np.linalg.solve(design.T @ weight @ design, design.T @ weight @ w)[1]
    cos, sin = 1.0 / math.hypot(1.0, slope), slope / math.hypot(1.0, slope)
    x_c, w_c = x - x.mean(), w - w.mean()
    u, v = x_c * cos + w_c * sin, -x_c * sin + w_c * cos
    weight = weight / cos**2  # vertical noise seen across the chord
    design = np.column_stack([np.ones_like(u), u, u * u])
    covariance_fit = np.linalg.inv(design.T @ weight @ design)
    _, b, c = covariance_fit @ (design.T @ weight @ v)
    factor = (1.0 + b * b) ** 1.5
    return float(2.0 * c / factor), float(2.0 * math.sqrt(covariance_fit[2, 2]) / factor)


def chord_curvature(distance_mm, deflection_mm, sd_mm):
    """Curvature of the circle that best fits a stretch of profile, with its standard error.

    The points are rotated into the frame of their least-squares chord, where a
    circle ``v = R - sqrt(R**2 - u**2) = u**2 / (2 R) + u**4 / (8 R**3) + ...`` is
    nearly a parabola; a weighted linear fit of ``v = a + b u + c u**2`` gives the
    curvature ``2 c / (1 + b**2)**1.5`` and, with the points' known noise, its
    standard error.  The quartic term biases the curvature of an exact circle
    upward by about ``(3/14) (h / R)**2`` (``h`` half the stretch's length), under
    1 % for the stretches used here.  Being linear, the fit works equally for a
    straight stretch (curvature near 0) and a curved one.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        At least four points of one profile (mm).
    sd_mm : array_like
        Standard deviation of each deflection (mm, vertical noise), or their
        ``(n, n)`` covariance (mm^2): the fit is then generalised least squares
        and the standard error honours correlated errors.

    Returns
    -------
    tuple of float
        ``(curvature_per_mm, standard_error_per_mm)``; the curvature is signed,
        positive where the deflection profile is convex (opens upward).
    """
    x = np.asarray(distance_mm, dtype=float)
    w = np.asarray(deflection_mm, dtype=float)
    if x.size < 4:
        raise ValueError(f"a curvature with an error needs at least 4 points, got {x.size}")
    if np.ndim(sd_mm) == 2:
        return _chord_curvature_gls(x, w, np.asarray(sd_mm, dtype=float))
    sd = np.broadcast_to(np.asarray(sd_mm, dtype=float), x.shape)
    slope = np.polyfit(x, w, 1, w=1.0 / sd)[0]
    cos, sin = 1.0 / math.hypot(1.0, slope), slope / math.hypot(1.0, slope)
    x_c, w_c = x - np.average(x, weights=sd**-2), w - np.average(w, weights=sd**-2)
    u, v = x_c * cos + w_c * sin, -x_c * sin + w_c * cos
    weight = (sd * cos) ** -2  # vertical noise seen across the chord
    design = np.column_stack([np.ones_like(u), u, u * u])
    normal = design.T @ (design * weight[:, None])
    covariance = np.linalg.inv(normal)
    _, b, c = covariance @ (design.T @ (weight * v))
    factor = (1.0 + b * b) ** 1.5
    return float(2.0 * c / factor), float(2.0 * math.sqrt(covariance[2, 2]) / factor)


def verdict_counts(claims):
    """How many of the paper's claims got each verdict; only ``holds`` and ``does not
    hold`` are evidence.

    Parameters
    ----------
    claims : pandas.DataFrame
        A claims table (column ``verdict``; with a column ``kind``, only the rows of
        kind ``paper claim`` are counted, see :data:`CLAIM_KINDS`).

    Returns
    -------
    dict
        Verdict -> count for every verdict of :data:`VERDICTS`, ``evidence`` (the
        number of claims the data tested), ``paper_claims`` (the rows counted) and
        ``checks`` (the rows of other kinds, reported apart).
    """
    counted = claims[claims["kind"] == PAPER_CLAIM] if "kind" in claims else claims
    counts = {v: int((counted["verdict"] == v).sum()) for v in VERDICTS}
    counts["evidence"] = sum(counts[v] for v in EVIDENCE_VERDICTS)
    counts["paper_claims"] = len(counted)
    counts["checks"] = len(claims) - len(counted)
    return counts


# --------------------------------------------------------------------------- claims


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
        key = round(float(fit["depth_mm"]), 9)
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
    ranges = (
        f"monkeys {_span(by_species['monkey'])} ({len(by_species['monkey'])} trials), "
        f"humans {_span(by_species['human'])} ({len(by_species['human'])} trials)"
    )
    shared = sorted(d for d, sp in extents.items() if "monkey" in sp and "human" in sp)
    if not shared:
        missing = [sp for sp in paper.SPECIES if not by_species[sp]]
        reason = (
            f"no {' and no '.join(missing)} trials"
            if missing
            else "no depth measured in both species"
        )
        return _row(
            "C1",
            f"{ranges}; {reason}",
            UNTESTABLE,
            f"The species cannot be compared: {reason}.",
            rule,
        )
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
    z_one = float(norm.ppf(1.0 - alpha))
    z_all = float(norm.ppf(1.0 - alpha / n_pairs))
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
    side's covariance (reading, tracing and side offset); without a noise model,
    twice ``noise_mm**2`` on the diagonal.
    """
    if settings.noise_model is not None and settings.noise_mm is None:
        return 2.0 * settings.noise_model.side_covariance_mm2(x_mm)
    return 2.0 * settings.reading_noise_mm**2 * np.eye(x_mm.size)


def asymmetry_excess(difference_mm, covariance_mm2):
    """Mean square of left minus right beyond what the noise gives, with its standard error.

    ``D = mean(d**2) - trace(C) / n`` estimates the mean square of the true
    difference between the sides; under Gaussian noise ``mean(d**2)`` has
    variance ``(2 trace(C C) + 4 a' C a) / n**2`` for a true difference ``a``,
    estimated with ``a' C a ~ max(D, 0) trace(C)``.

    Parameters
    ----------
    difference_mm : array_like
        Left minus right at the distances both sides read (mm).
    covariance_mm2 : array_like
        Their covariance under noise alone (mm^2).

    Returns
    -------
    tuple of float
        ``(D_mm2, se_mm2)``.
    """
    d = np.asarray(difference_mm, dtype=float)
    c = np.asarray(covariance_mm2, dtype=float)
    n = d.size
    excess = float(np.mean(d**2) - np.trace(c) / n)
    variance = (2.0 * float(np.sum(c * c)) + 4.0 * max(excess, 0.0) * float(np.trace(c))) / n**2
    return excess, math.sqrt(variance)


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
        "(twice one side's: reading, tracing and side offset; the noise table), and its "
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
    z_one = float(norm.ppf(1.0 - alpha))
    z_all = float(norm.ppf(1.0 - alpha / (2.0 * len(values))))
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
    bound = (margin * depths) ** 2
    fraction = np.sqrt(np.clip(excess, 0.0, None)) / np.sqrt(bound) * margin
    worst = values[int(np.argmax(fraction))][0]
    our = (
        f"true RMS left-right difference (noise removed) / depth: median "
        f"{_pct(np.median(fraction))}, largest {_pct(fraction.max())} ({worst}); "
        f"equivalent within {_pct(margin, 0)} in {int(equivalent.sum())} of {len(values)} "
        f"trials, different in {int(different.sum())}"
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


def claim_c3(fits, averaged, settings):
    """C3: waterbed better than Boussinesq within the fit window, a test per trial."""
    alpha = settings.significance
    rule = (
        "Same points for both models (the fit window). Per trial, D = SSE_Boussinesq - "
        "SSE_waterbed (the paper's procedure, one parameter, against the Boussinesq form, "
        "two): D = sum (f_w - f_B)(2 y - f_w - f_B) is linear in the readings, so its "
        "standard error is 2 sqrt(d' C d), d = f_w - f_B, with C the covariance of the "
        "averaged points from the measured noise (correlated errors included). The waterbed "
        f"is better in a trial if D exceeds zero by {format_fixed(norm.ppf(1 - alpha), 2)} "
        f"standard errors (one-sided, significance = {alpha:g}); the Boussinesq form is "
        "better if D is below zero by the one-sided Bonferroni quantile over the trials. "
        "Holds if the waterbed is better in every trial with both fits; does not hold if "
        "the Boussinesq form is better in some trial; cannot be checked otherwise. The "
        "comparison favours the Boussinesq form by its extra parameter. Shown beside it, "
        "not deciding: the RMSE ratio, and the count for the shifted parabola."
    )
    w_rmse = fits["waterbed_rmse_mm"].to_numpy(float)
    b_rmse = fits["boussinesq_rmse_mm"].to_numpy(float)
    tests = []
    for fit, points in _trials(fits, averaged):
        A_mm, x0_mm = float(fit["boussinesq_A_mm"]), float(fit["boussinesq_x0_mm"])
        if not (_finite_L(fit) and math.isfinite(A_mm) and math.isfinite(x0_mm)):
            continue
        if points.empty:
            continue
        x, y, sides = _window_points(fit, points)
        if x.size < 3:
            continue
        depth_mm = float(fit["depth_mm"])
        f_w = waterbed_deflection_mm(x, depth_mm, float(fit["waterbed_L_mm"]))
        f_b = boussinesq_deflection_mm(x, A_mm, x0_mm)
        gap = f_w - f_b
        covariance = _averaged_covariance_mm2(x, sides, y, fit, settings)
        sd = 2.0 * math.sqrt(max(float(gap @ covariance @ gap), 0.0))
        tests.append((_label(fit), float(gap @ (2 * y - f_w - f_b)), sd))
    if not tests:
        return _row(
            "C3",
            "no trial has both fits",
            UNTESTABLE,
            "No trial has enough points for both the waterbed and the Boussinesq fit.",
            rule,
        )
    labels = [t[0] for t in tests]
    D = np.array([t[1] for t in tests])
    sd = np.array([t[2] for t in tests])
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(sd > 0, D / sd, np.sign(D) * np.inf)
    waterbed = z > norm.ppf(1 - alpha)
    boussinesq = z < -norm.ppf(1 - alpha / len(tests))
    usable = np.isfinite(w_rmse) & np.isfinite(b_rmse)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = b_rmse[usable] / w_rmse[usable]
    shifted_better = fits["shifted_rmse_mm"].to_numpy(float) < b_rmse
    windows = pd.unique(fits["fit_window_mm"].dropna())
    window = f" within {float(windows[0]):g} mm" if len(windows) == 1 else ""
    our = (
        f"waterbed better{window} in {int(waterbed.sum())} of {_n(len(tests), 'trial')}, "
        f"the Boussinesq form in {int(boussinesq.sum())} (D / SE {_span(z, 1, '')}); "
        f"RMSE ratio Boussinesq/waterbed median {format_fixed(np.median(ratio), 2)} "
        f"(range {_span(ratio, 2, '')}); shifted parabola smaller RMSE in "
        f"{int(shifted_better[usable].sum())} of {int(usable.sum())}"
    )
    if boussinesq.any():
        worse = [lab for lab, b in zip(labels, boussinesq, strict=True) if b]
        reason = (
            f"The Boussinesq form fits better, beyond the noise, in {_list(worse)}, "
            "despite its extra parameter counting for nothing here."
        )
        return _row("C3", our, FAILS, reason, rule)
    if waterbed.all():
        reason = (
            f"In {_every(len(tests), 'trial')} the waterbed leaves smaller residuals than the "
            "Boussinesq form on the same points, beyond the noise, with one parameter fewer "
            f"(RMSE ratio {format_fixed(np.median(ratio), 1)}, median)."
        )
        return _row("C3", our, HOLDS, reason, rule)
    open_ = [lab for lab, w in zip(labels, waterbed, strict=True) if not w]
    reason = (
        f"In {_list(open_)} the two fits differ by less than the noise can resolve; "
        "no trial favours the Boussinesq form beyond it."
    )
    return _row("C3", our, UNTESTABLE, reason, rule)


def _bulge_errors(fit, x, w, sides, bulge, settings):
    """Standard errors of the readings' mean ``m`` over the bulge points, and of ``m -
    f``, ``f`` the fitted curve's mean there: ``f`` moves with the readings of the fit
    window through L (``dL = J' dy``), which the noise may correlate with the bulge's."""
    finite = np.isfinite(w)
    x, w, sides, bulge = x[finite], w[finite], sides[finite], bulge[finite]
    covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
    depth_mm, L_mm = float(fit["depth_mm"]), float(fit["waterbed_L_mm"])
    mean_of = np.where(bulge, 1.0 / bulge.sum(), 0.0)
    window = in_fit_window(x, float(fit["fit_window_mm"]))
    through_L = np.zeros_like(x)
    if window.sum() >= 1:
        J = _L_sensitivity(waterbed_deflection_mm, x[window], depth_mm, L_mm, w[window])
        below, _, above, step = _around_L(waterbed_deflection_mm, x[bulge], depth_mm, L_mm)
        slope = float(np.mean(above - below) / (2 * step))
        through_L[window] = slope * J
    var_m = float(mean_of @ covariance @ mean_of)
    gap = mean_of - through_L
    var_gap = float(gap @ covariance @ gap)
    return math.sqrt(max(var_m, 0.0)), math.sqrt(max(var_gap, 0.0))


def claim_c4(fits, averaged, settings):
    """C4: the predicted bulge beyond L/3 is not in the data, a test per trial."""
    alpha = settings.significance
    z_one = float(norm.ppf(1.0 - alpha))
    rule = (
        "Deflection W is positive downward, so the waterbed's bulge is W < 0: skin raised "
        "above its resting surface. Per trial: the averaged points with L/3 < distance < L "
        "at which the fitted waterbed curve is negative (its predicted bulge). Statistic: "
        "the mean of the readings there, m, against the curve's mean there, f (< 0), with "
        "standard errors from the covariance of the averaged points under the measured "
        "noise (correlated errors included), f's through the fitted L. The bulge is "
        f"resolvable in a trial if f lies more than {format_fixed(2 * z_one, 2)} standard "
        "errors of m - f below zero (readings at the resting surface then refute it with "
        f"probability {format_fixed(1 - alpha, 2)}), refuted if m exceeds f by more than "
        f"{format_fixed(z_one, 2)} of them (one-sided, significance = {alpha:g}), and seen "
        "if m is negative by more than the one-sided Bonferroni quantile over the trials "
        "times its standard error. Holds if no trial shows the bulge and every trial where "
        "it is resolvable refutes it; does not hold if some trial shows it; cannot be "
        "checked otherwise."
    )
    rows, n_trials = [], 0
    for fit, points in _trials(fits, averaged):
        if points.empty or not _finite_L(fit):
            continue
        n_trials += 1
        L_mm, depth_mm = float(fit["waterbed_L_mm"]), float(fit["depth_mm"])
        x = points["distance_mm"].to_numpy(float)
        w = points["deflection_mm"].to_numpy(float)
        sides = points["n_sides"].to_numpy(float)
        model = waterbed_deflection_mm(x, depth_mm, L_mm)
        bulge = (x > L_mm / 3.0) & (x < L_mm) & np.isfinite(w) & (model < 0.0)
        if not bulge.any():
            continue
        se_m, se_gap = _bulge_errors(fit, x, w, sides, bulge, settings)
        rows.append(
            {
                "label": _label(fit),
                "m": float(w[bulge].mean()),
                "f": float(model[bulge].mean()),
                "se_m": se_m,
                "se_gap": se_gap,
                "lowest": float(w[bulge].min()),
            }
        )
    if not rows:
        return _row(
            "C4",
            f"none of {n_trials} trials has readings where the fitted curve is negative "
            "(a bulge above the resting surface)",
            UNTESTABLE,
            "No reading lies where the fitted curve predicts a bulge.",
            rule,
        )
    m = np.array([r["m"] for r in rows])
    f = np.array([r["f"] for r in rows])
    se_m = np.array([r["se_m"] for r in rows])
    se_gap = np.array([r["se_gap"] for r in rows])
    z_all = float(norm.ppf(1.0 - alpha / len(rows)))
    with np.errstate(divide="ignore", invalid="ignore"):
        seen = np.where(se_m > 0, m / se_m < -z_all, m < 0)
        # the least bulge that readings at the resting surface refute with power 1 - alpha
        resolvable = np.where(se_gap > 0, f / se_gap < -2.0 * z_one, f < 0)
        refuted = np.where(se_gap > 0, (m - f) / se_gap > z_one, m > f)
    labels = [r["label"] for r in rows]
    our = (
        f"{len(rows)} of {n_trials} trials have readings in the predicted bulge; mean of the "
        f"fitted curve there {_span(f, 3)}, mean of the data {_span(m, 3)} (standard error "
        f"{_span(se_m, 3)}, of the difference {_span(se_gap, 3)}; lowest single point "
        f"{_mm(min(r['lowest'] for r in rows), 3)}); resolvable in {int(resolvable.sum())}, "
        f"refuted in {int((resolvable & refuted).sum())}, bulge seen in {int(seen.sum())}"
    )
    if seen.any():
        showing = [lab for lab, s_ in zip(labels, seen, strict=True) if s_]
        our += f" ({_list(showing)})"
        reason = (
            "The readings rise above the resting surface, beyond the noise, where the curve "
            f"predicts a bulge, in {_list(showing)}."
        )
        return _row("C4", our, FAILS, reason, rule)
    if resolvable.any() and refuted[resolvable].all():
        reason = (
            f"In the {int(resolvable.sum())} of {_n(len(f), 'trial')} where the noise could "
            "show a bulge (a subset of the ranges above), the fitted curves predict one of "
            f"{_span(-f[resolvable], 3)} on average and the readings average "
            f"{_span(m[resolvable], 3)} of deflection: in each of them the skin stays below "
            "the predicted bulge beyond the noise. No bulge."
        )
        return _row("C4", our, HOLDS, reason, rule)
    open_ = [lab for lab, r_, q in zip(labels, resolvable, refuted, strict=True) if r_ and not q]
    reason = (
        f"In {_list(open_)} the readings cannot be told from the predicted bulge"
        if open_
        else "The predicted bulge is smaller than the noise can resolve in every trial"
    ) + "; no trial shows it either."
    return _row("C4", our, UNTESTABLE, reason, rule)


def _scaled_interval(fit, model, z):
    """A trial's interval on L at another level: each side of the fit's 95 % profile
    interval scaled by ``z / z_0.975`` (the profile is close to quadratic at these
    widths; :mod:`lineload.simulation.coverage` measures the 95 % interval's coverage)."""
    L_mm = float(fit[f"{model}_L_mm"])
    scale = z / norm.ppf(0.975)
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
    z_inside = norm.ppf(1.0 - alpha)
    outcomes = {}
    for model in (PAPER_FIT, "shifted"):
        rows = [f for f in fits.to_dict("records") if _finite_L(f, model)]
        z_outside = norm.ppf(1.0 - alpha / (2 * max(len(rows), 1)))
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


def _around_L(curve, x_mm, depth_mm, L_mm):
    """``curve`` at ``L - step``, ``L`` and ``L + step`` (``step = 1e-4 L``), and the step:
    the central differences in L of :func:`_L_sensitivity` and C4's bulge."""
    step = 1e-4 * L_mm
    return (
        curve(x_mm, depth_mm, L_mm - step),
        curve(x_mm, depth_mm, L_mm),
        curve(x_mm, depth_mm, L_mm + step),
        step,
    )


def _L_sensitivity(curve, x_mm, depth_mm, L_mm, y_mm=None):
    """How a one-parameter least-squares L moves with the readings, to first order.

    At the minimum ``g . (y - m) = 0`` with ``g = dm/dL``; differentiating in the
    readings gives ``dL/dy = g / (g . g - r . h)``, ``r`` the residuals and
    ``h = d2m/dL2`` (central differences).  The ``r . h`` term matters where the
    model misfits the readings; without ``y_mm`` it is left out.
    """
    below, middle, above, step = _around_L(curve, x_mm, depth_mm, L_mm)
    g = (above - below) / (2 * step)
    curvature = 0.0
    if y_mm is not None:
        curvature = float(np.dot(y_mm - middle, (above - 2 * middle + below) / step**2))
    return g / (float(np.dot(g, g)) - curvature)


def _averaged_covariance_mm2(x_mm, sides, y_mm, fit, settings):
    """Covariance of a trial's averaged points under its noise.

    With a noise model, :meth:`lineload.noise.NoiseModel.average_covariance_mm2`
    (every measured part and every prior; the trial's own model where
    ``settings.trial_noise`` has one); otherwise independent readings of
    ``noise_mm`` over the number of sides averaged.
    """
    depth_mm = float(fit["depth_mm"])
    if settings.noise_model is not None and settings.noise_mm is None:
        model = (settings.trial_noise or {}).get(
            trial_key(fit["subject"], depth_mm), settings.noise_model
        )
        return model.average_covariance_mm2(x_mm, sides, y_mm, depth_mm)
    return np.diag(_noise_sd_mm(settings.reading_noise_mm, sides) ** 2)


def claim_c6(fits, averaged, settings):
    """C6: the paper's small-slope procedure against the exact arc, an equivalence test.

    A property of the paper's method at the data's W0/L, not evidence about fingers
    (:data:`CLAIM_KINDS`): reported, not counted.
    """
    margin = settings.shift_margin
    alpha = settings.significance
    z_equivalence = norm.ppf(1.0 - alpha)
    rule = (
        "A property of the paper's method at the data's W0/L, not counted as evidence about "
        "fingers: both fits are one-parameter curves of the same membrane, so the gap "
        "between their L is fixed by W0/L up to a standard error of hundredths of a percent. "
        "An equivalence test with the workflow's margin (config claims: shift_margin = "
        f"{_pct(margin, 0)}, reasons in the config schema; not the paper's 8 %, a bound on "
        "|U|/X). Neglecting U (eq. 19 read at the deformed position) is negligible if it "
        f"changes the fitted L by less than {_pct(margin, 0)}. The reference is the exact arc, the "
        "finite-deformation solution of the same membrane (consistent in both coordinates). "
        "Per trial with both fits: the paired relative difference d = (L of the paper's "
        "procedure − L of the arc) / L of the arc, both from the same readings, with its "
        "standard error from the fits' "
        "first-order sensitivities to the readings (misfit included) and the measured noise "
        "(the noise table: reading and tracing errors, side offsets, and the priors for what "
        "left-right differences cannot see). "
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
    z_difference = norm.ppf(1.0 - alpha / (2 * len(rows)))

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
        f"{deviations.size} trials"
    )
    reason = (
        "Every fitted curve crosses zero at L/3, as eq. 19 requires of any L; this says "
        "nothing about the fingertip."
    )
    return _row("C7", our, IDENTITY, reason, rule)


def _residual_noise_mm2(fit, x, w, sides, settings):
    """The mean square the noise alone leaves in the waterbed's residuals over the window.

    Fitting L removes the part of the noise along ``g = dm/dL``: under a covariance
    ``C`` the expected residual sum of squares of a one-parameter least-squares fit is
    ``trace(C) - g' C g / g' g`` to first order (``trace((I - H) C)``, ``H`` the fit's
    hat matrix ``g g' / g' g``); over ``n`` points, that over ``n``.  Without the
    second term, errors the fit absorbs through L (a depth error scales the profile,
    much as a change of L does) would be subtracted although they never reach the
    residuals, and the correction, largest relative to W0² at the smallest depth, would
    tilt the relative misfit against depth.
    """
    covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
    depth_mm = float(fit["depth_mm"])
    below, _, above, step = _around_L(
        waterbed_deflection_mm, x, depth_mm, float(fit["waterbed_L_mm"])
    )
    g = (above - below) / (2 * step)
    absorbed = float(g @ covariance @ g) / float(g @ g) if float(g @ g) > 0 else 0.0
    return (float(np.trace(covariance)) - absorbed) / x.size


def claim_c8(fits, averaged, settings):
    """C8: the waterbed's misfit relative to the depth grows with depth, tested across
    subjects.

    The statistic of a trial is ``q = (RMSE**2 - s**2) / W0**2``: the waterbed's mean
    square misfit beyond the noise (``s**2`` the mean noise variance of the fitted
    points, from the trial's covariance) over the depth squared.  The small-slope
    waterbed is linear in W0 at a fixed L, so a finger whose profile keeps one shape
    at every depth (``w = W0 f(x)``) has a misfit ``W0 (f - g)`` of fixed shape: its
    ``RMSE**2 - s**2`` grows as W0**2 although the model is no worse relative to the
    deformation, and ``q`` stays constant.  ``q`` grows only where the shape of the
    profile departs further from the waterbed's the deeper the indentation, which is
    what "describes the data less well" means for a model of the deformation.

    The correction ``s**2 / W0**2`` is largest at the smallest depth: a noise level
    stated too high makes ``q`` rise towards zero with depth and can make the claim
    hold on a model without misfit (a test shows it), so ``s**2`` comes from the
    measured noise table, never from a guess.

    Each subject with two or more depths gives the least-squares slope of ``q``
    against depth; the slopes are tested across subjects, species a fixed effect, by
    Student's t.  The t-test needs one degree of freedom for the spread between
    subjects, so at least one more subject with two depths than there are species;
    with fewer the claim cannot be checked.
    """
    alpha = settings.significance
    rule = (
        "Per trial: the waterbed's relative excess misfit q = (RMSE² − s²) / W₀², with "
        "RMSE over the fit window and s² the mean noise variance of the averaged points "
        "there under the trial's covariance from the noise table, less the part the fit of L "
        "absorbs (trace(C) − g'Cg/g'g over n, g = dm/dL); not truncated at zero, so "
        "noise averages out. Relative to W₀² because the waterbed is linear in W₀ at a "
        "fixed L: a profile that keeps one shape at every depth has an excess growing as "
        "W₀² but a constant q. Per subject with two or more depths: the least-squares "
        "slope of q against depth (per mm). Across subjects: the slopes regressed on "
        "species (a fixed effect), and the mean of the species' mean slopes tested "
        f"one-sided with Student's t (significance = {alpha:g}). Holds if the slope is "
        "significantly above zero (the relative misfit grows with depth); does not hold if "
        f"its upper one-sided {format_fixed(100 * (1 - alpha), 0)} % bound is below zero; "
        "cannot be checked otherwise, or with fewer subjects measured at two depths than "
        "species + 1 (the t-test needs one degree of freedom for the spread between "
        "subjects)."
    )
    relative = {}
    species_of = {}
    for fit, points in _trials(fits, averaged):
        rmse_mm = float(fit["waterbed_rmse_mm"])
        depth_mm = float(fit["depth_mm"])
        if points.empty or not math.isfinite(rmse_mm) or not depth_mm > 0:
            continue
        x, w, sides = _window_points(fit, points)
        variance = _residual_noise_mm2(fit, x, w, sides, settings) if x.size >= 2 else 0.0
        subject = str(fit["subject"])
        species_of[subject] = str(fit["species"])
        relative.setdefault(subject, []).append((depth_mm, (rmse_mm**2 - variance) / depth_mm**2))
    test = _slopes_across_subjects(relative, species_of, alpha)
    slopes, species, df = test["slopes"], test["species"], test["df"]
    per_depth = {}
    for values in relative.values():
        for depth_mm, value in values:
            per_depth.setdefault(depth_mm, []).append(value)
    means = ", ".join(
        f"{d:g} mm {format_fixed(100 * np.mean(v), 3)}" for d, v in sorted(per_depth.items())
    )
    if df < 1:
        return _too_few_subjects("C8", slopes, species, rule)
    estimate, se, t_value = test["estimate"], test["se"], test["t"]
    p_value, upper = test["p"], test["upper"]
    per_subject = ", ".join(f"{s} {format_fixed(100 * v, 3)}" for s, v in slopes.items())
    our = (
        f"relative excess misfit (RMSE² − s²) / W₀² (%), mean per depth: {means}; slope "
        f"per subject (% per mm of depth): {per_subject}; mean slope "
        f"{format_fixed(100 * estimate, 3)} ± {format_fixed(100 * se, 3)} (t = "
        f"{format_fixed(t_value, 2)}, "
        f"{counted(df, 'degree of freedom', 'degrees of freedom')}, one-sided p {_p_text(p_value)})"
    )
    if p_value < alpha:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the waterbed's misfit beyond the noise, "
            f"relative to the depth, grows with depth, by {format_fixed(100 * estimate, 3)} % "
            f"of W₀² per mm on average (one-sided p {_p_text(p_value)})."
        )
        return _row("C8", our, HOLDS, reason, rule)
    if upper < 0:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the misfit beyond the noise, relative to "
            f"the depth, shrinks with depth (upper bound {format_fixed(100 * upper, 3)} % of "
            "W₀² per mm)."
        )
        return _row("C8", our, FAILS, reason, rule)
    reason = (
        f"Across {_n(len(slopes), 'subject')} the mean slope of the relative misfit "
        f"({format_fixed(100 * estimate, 3)} ± {format_fixed(100 * se, 3)} % of W₀² per mm) is "
        "neither shown to be above zero nor below it."
    )
    return _row("C8", our, UNTESTABLE, reason, rule)


def _slopes_across_subjects(relative, species_of, alpha, variances=None):
    """Per-subject slopes of a per-trial statistic against depth, tested across subjects.

    Each subject with two or more depths gives the least-squares slope; the slopes are
    regressed on species (a fixed effect) and the mean of the species' mean slopes is
    tested one-sided by Student's t, with ``subjects - species`` degrees of freedom.

    Parameters
    ----------
    relative : dict
        Subject -> list of ``(depth_mm, value)``.
    species_of : dict
        Subject -> species.
    alpha : float
        Significance of the one-sided test.
    variances : dict, optional
        Subject -> list of the noise variance of each trial's value (in the order of
        ``relative``): where given, the slopes' own noise (propagated through each
        least-squares slope) sets a floor under the standard error, so that a value
        whose trend is the noise correction's, alike in every subject, is not taken
        for a finding because the subjects agree.

    Returns
    -------
    dict
        ``slopes`` (subject -> slope), ``species``, ``df``; with ``df >= 1`` also
        ``estimate``, ``se``, ``t``, ``p`` (one-sided, above zero) and ``upper`` (the
        one-sided ``1 - alpha`` upper bound).
    """
    slopes, slope_variances = {}, {}
    for subject, values in relative.items():
        depths = np.array([d for d, _ in values])
        if np.unique(depths).size >= 2:
            slopes[subject] = float(np.polyfit(depths, [q for _, q in values], 1)[0])
            if variances is not None:
                centred = depths - depths.mean()
                c = centred / float(np.sum(centred**2))
                slope_variances[subject] = float(np.sum(c**2 * np.asarray(variances[subject])))
    species = sorted({species_of[s] for s in slopes})
    df = len(slopes) - len(species)
    test = {"slopes": slopes, "species": species, "df": df}
    if df < 1:
        return test
    groups = {sp: np.array([v for s, v in slopes.items() if species_of[s] == sp]) for sp in species}
    group_means = np.array([g.mean() for g in groups.values()])
    residual = np.concatenate([g - g.mean() for g in groups.values()])
    variance = float(np.sum(residual**2)) / df
    # the contrast: mean over species of each species' mean slope
    weights = np.array([1.0 / len(species) / g.size for g in groups.values()])
    estimate = float(group_means.mean())
    se = math.sqrt(variance * float(np.sum(weights**2 * [g.size for g in groups.values()])))
    if slope_variances:
        weight_of = {sp: 1.0 / len(species) / g.size for sp, g in groups.items()}
        noise_se = math.sqrt(
            sum(weight_of[species_of[s]] ** 2 * v for s, v in slope_variances.items())
        )
        se = max(se, noise_se)
    t_value = estimate / se if se > 0 else math.copysign(math.inf, estimate)
    test.update(
        estimate=estimate,
        se=se,
        t=t_value,
        p=float(student_t.sf(t_value, df)),
        upper=estimate + float(student_t.ppf(1.0 - alpha, df)) * se,
    )
    return test


def _too_few_subjects(claim, slopes, species, rule):
    """The row of a slope test across subjects (C8, C13) with no degree of freedom left."""
    return _row(
        claim,
        f"{_n(len(slopes), 'subject')} measured at two or more depths, "
        f"{_n(len(species), 'species', 'species')}: no degree of freedom for the t-test",
        UNTESTABLE,
        "Too few subjects were measured at two or more depths to test the slope across "
        f"subjects (at least {len(species) + 1 if species else 2} are needed).",
        rule,
    )


def _p_text(p_value):
    """A p-value as the test can resolve it: '< 0.001' below that, else three decimals."""
    return "< 0.001" if p_value < 0.001 else f"= {p_value:.3f}"


def _mean_residual(fit, x, w, sides, model, settings):
    """A trial's mean residual (readings minus the fitted curve) over the fit window
    and its standard error under the trial's covariance.

    The residual moves with the readings directly and through the fitted L
    (:func:`_L_sensitivity`): ``a = 1/n - mean(dm/dL) J``, so its variance is
    ``a' C a`` with ``C`` the covariance of the averaged points.
    """
    depth_mm, L_mm = float(fit["depth_mm"]), float(fit[f"{model}_L_mm"])
    curve = CURVES[model]
    below, middle, above, step = _around_L(curve, x, depth_mm, L_mm)
    J = _L_sensitivity(curve, x, depth_mm, L_mm, w)
    a = np.full(x.size, 1.0 / x.size) - float(np.mean((above - below) / (2 * step))) * J
    covariance = _averaged_covariance_mm2(x, sides, w, fit, settings)
    se = math.sqrt(max(float(a @ covariance @ a), 0.0))
    return float(np.mean(w - middle)), se, float(np.mean(w < middle))


def claim_c9(fits, averaged, settings):
    """C9: at larger depths the data are deflected less than the waterbed near the load, in any
    coordinates; a test per trial of the mean residual under the trial's covariance."""
    large = settings.large_depth_mm
    alpha = settings.significance
    models = (PAPER_FIT, *CONSISTENT_FITS)
    rule = (
        f"Per trial at depth >= large_depth_mm = {large:g} mm, for the paper's procedure and "
        "the two fits in measured coordinates (shifted parabola, exact arc): the mean "
        "residual m (readings minus the fitted curve) over the fit window, with its standard "
        "error under the trial's covariance (the noise table: every measured part and "
        "prior), the fitted L's response to the readings included. The readings fall short "
        f"of a curve if m is below zero by z(1 - {alpha:g}) standard errors (one-sided, "
        f"significance = {alpha:g}; in the figures, whose deflection axis points down, such "
        "points sit above the curve); they exceed it if m is above zero by the one-sided "
        "Bonferroni quantile over the trials and the three curves. Holds if the readings "
        "fall short of all three curves in every such trial (each at significance "
        f"{alpha:g}: a claim of all is wrong only if some trial's test is); does not hold if "
        "they exceed some curve in some trial; cannot be checked otherwise, and the reason "
        "says where they fall short of the paper's curve only (then 'stiffer than the "
        "model' is an artefact of the coordinates). Beside it: the fraction of points "
        "deflected less than each curve."
    )
    results = {m: [] for m in models}
    labels = []
    for fit, points in _trials(fits, averaged):
        if float(fit["depth_mm"]) < large or points.empty:
            continue
        if not all(_finite_L(fit, m) for m in models):
            continue
        x, w, sides = _window_points(fit, points)
        if x.size < 2:
            continue
        labels.append(_label(fit))
        for model in models:
            results[model].append(_mean_residual(fit, x, w, sides, model, settings))
    if not labels:
        return _row(
            "C9",
            f"no trial at a depth of {large:g} mm or more with all three fits",
            UNTESTABLE,
            f"No trial reaches {large:g} mm with the three waterbed fits.",
            rule,
        )
    z_one = float(norm.ppf(1.0 - alpha))
    z_all = float(norm.ppf(1.0 - alpha / (len(labels) * len(models))))
    short, over = {}, {}
    for model in models:
        m = np.array([r[0] for r in results[model]])
        se = np.array([r[1] for r in results[model]])
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(se > 0, m / se, np.sign(m) * np.inf)
        short[model], over[model] = z < -z_one, z > z_all
    our = "; ".join(
        f"{FIT_WORDS[m]}: mean residual "
        f"{_span([1e3 * r[0] for r in results[m]], 1, ' µm')} (standard error "
        f"{_span([1e3 * r[1] for r in results[m]], 1, ' µm')}), "
        f"{_pct(min(r[2] for r in results[m]), 0)} to {_pct(max(r[2] for r in results[m]), 0)} "
        f"of points deflected less; short of the curve in {int(short[m].sum())} of "
        f"{len(labels)} trials, beyond it in {int(over[m].sum())}"
        for m in models
    )
    everywhere = np.logical_and.reduce([short[m] for m in models])
    if everywhere.all():
        reason = (
            f"In {_every(len(labels), 'trial')} at {large:g} mm or deeper the readings are "
            "deflected less than the fitted curve on average, beyond the noise, whichever "
            "coordinates the curve is placed in."
        )
        return _row("C9", our, HOLDS, reason, rule)
    parts = []
    exceeding = np.logical_or.reduce([over[m] for m in models])
    if exceeding.any():
        parts.append(
            "the readings are deflected more than a fitted curve, beyond the noise, in "
            + _list([lab for lab, e in zip(labels, exceeding, strict=True) if e])
        )
    coordinates = short[PAPER_FIT] & ~short["shifted"]
    finite = short[PAPER_FIT] & short["shifted"] & ~short["arc"]
    open_ = ~short[PAPER_FIT] & ~exceeding
    if coordinates.any():
        parts.append(
            f"in {_list([lab for lab, c in zip(labels, coordinates, strict=True) if c])} they "
            "fall short of the paper's curve but not, beyond the noise, of the same parabola "
            "placed in measured coordinates, so there the 'stiffer' reading may be an "
            f"artefact of the paper's coordinates ({COORDINATES_FIGURE})"
        )
    if finite.any():
        parts.append(
            f"in {_list([lab for lab, c in zip(labels, finite, strict=True) if c])} they fall "
            "short of both parabolas but not, beyond the noise, of the exact arc, so there it "
            "may come from the small-slope approximation rather than the fingertip"
        )
    if open_.any():
        parts.append(
            f"in {_list([lab for lab, c in zip(labels, open_, strict=True) if c])} the noise "
            "cannot tell the readings from the paper's curve on average"
        )
    reason = "; ".join(parts)
    verdict = FAILS if exceeding.any() else UNTESTABLE
    return _row("C9", our, verdict, reason[0].upper() + reason[1:] + ".", rule)


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
        "lineload.claims.rules.chord_curvature). The statistic is the relative change r = (inner - "
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
    z_one = float(norm.ppf(1.0 - alpha))
    z_all = float(norm.ppf(1.0 - alpha / (2.0 * len(tested))))

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
        f"{_pct(pooled)} ± {_pct(pooled_se)} (SE) over {len(tested)} trials; per trial "
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


def _force_checks(fits, forces, force_sd_N):
    """Per subject with forces at two or more depths: the stress-free and the full fit."""
    variant = mechanics.WATERBED_VARIANT
    lookup = mechanics._force_lookup(forces)
    checks = {}
    for subject, rows in fits.groupby("subject", sort=False):
        rows = rows.sort_values("depth_mm", kind="stable")
        depth = rows["depth_mm"].to_numpy(float)
        L_mm = rows[f"{variant}_L_mm"].to_numpy(float)
        L_sd = mechanics.sd_from_interval(
            rows[f"{variant}_L_ci_low_mm"], rows[f"{variant}_L_ci_high_mm"]
        )
        force = np.array([lookup.get((str(subject), round(d, 9)), np.nan) for d in depth])
        use = np.isfinite(force) & np.isfinite(L_mm) & np.isfinite(L_sd)
        if np.unique(depth[use]).size < 2:
            continue
        args = (depth[use], L_mm[use], force[use], force_sd_N, L_sd[use])
        checks[str(subject)] = {
            "stress_free": mechanics.fit_membrane(*args, stress_free=True),
            "tensioned": mechanics.fit_membrane(*args),
            "ratio": float(force[use][-1] / force[use][0]),
        }
    return checks


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
        f"each force with variance force_sd_N² = ({settings.force_sd_N:g} N)² plus the "
        "part from L's uncertainty, and its chi-square against the chi-square distribution "
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
    measured = _force_checks(fits, forces, settings.force_sd_N) if forces is not None else {}
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
            f"forces of forces.csv, {_n(len(measured), 'subject')}: ratio "
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


def claim_c13(fits, averaged, settings):
    """C13: the bending skin's advantage over the waterbed, relative to the deformation,
    grows with depth (the paper's closing suggestion, :mod:`lineload.bending`).

    The statistic of a trial is ``b = (RMSE_w**2 - RMSE_b**2 - s**2 / (2 n)) / W0**2``:
    how much less mean square misfit the bending skin leaves than the waterbed (the
    waterbed being the bending skin's limit ``l_b -> 0``, the difference is never
    negative beyond rounding), over W0**2 as C8 measures the waterbed's misfit.  Fitting
    pure noise, the extra parameter takes ``s**2 / 2`` of the sum of squares on average
    (half the time the fit stays at the membrane, the range's end, and takes nothing;
    Self and Liang 1987), ``s**2`` the mean noise variance of the points: that is
    subtracted, so noise alone gives no trend on average.  A trial whose bending length
    stays at the membrane has ``b = -s**2 / (2 n W0**2)`` exactly, a value that rises with
    depth alike in every subject: the slopes' standard error is therefore at least what
    the noise gives them (``n b W0**2 / s**2`` varies as ``1/2 chi2_0 + 1/2 chi2_1``,
    variance 1.25), not only their spread between subjects.  The slopes of ``b`` against
    depth are tested across subjects as C8's (:func:`_slopes_across_subjects`).
    """
    alpha = settings.significance
    rule = (
        "Per trial: the bending skin's advantage b = (RMSE²(waterbed) − RMSE²(bending) − "
        "s²/(2n)) / W₀² over the same fit window, s² the mean noise variance of the averaged "
        "points under the trial's covariance (s²/2 is what the extra parameter takes from "
        "noise alone, on average). Per subject with two or more depths: the least-squares "
        "slope of b against depth; across subjects: the slopes regressed on species, the "
        "mean of the species' mean slopes tested one-sided with Student's t (significance "
        f"= {alpha:g}), as in C8, its standard error at least what the noise alone gives "
        "the slopes (noise alone makes n(RMSE²(waterbed) − RMSE²(bending)) vary as 1.25 s⁴). "
        "Holds if the slope is significantly above zero (bending "
        "accounts for more of the misfit the deeper the wedge); does not hold if its upper "
        f"one-sided {format_fixed(100 * (1 - alpha), 0)} % bound is below zero; cannot be "
        "checked otherwise, without bending fits, or with fewer subjects measured at two "
        "depths than species + 1."
    )
    if "bending_rmse_mm" not in fits:
        return _row(
            "C13",
            "no bending fits",
            UNTESTABLE,
            "The bending skin was not fitted to these data.",
            rule,
        )
    relative, species_of, variances = {}, {}, {}
    for fit, points in _trials(fits, averaged):
        waterbed, bending = float(fit["waterbed_rmse_mm"]), float(fit["bending_rmse_mm"])
        depth_mm = float(fit["depth_mm"])
        if points.empty or not (math.isfinite(waterbed) and math.isfinite(bending)):
            continue
        if not depth_mm > 0:
            continue
        x, w, sides = _window_points(fit, points)
        if x.size < 2:
            continue
        noise = float(np.mean(np.diag(_averaged_covariance_mm2(x, sides, w, fit, settings))))
        value = (waterbed**2 - bending**2 - noise / (2 * x.size)) / depth_mm**2
        subject = str(fit["subject"])
        species_of[subject] = str(fit["species"])
        relative.setdefault(subject, []).append((depth_mm, value))
        # noise alone: n (RMSE_w² - RMSE_b²) ~ s² (½χ²₀ + ½χ²₁), variance 1.25 s⁴
        variances.setdefault(subject, []).append(1.25 * (noise / (x.size * depth_mm**2)) ** 2)
    test = _slopes_across_subjects(relative, species_of, alpha, variances)
    slopes, species, df = test["slopes"], test["species"], test["df"]
    if df < 1:
        return _too_few_subjects("C13", slopes, species, rule)
    estimate, se, p_value, upper = test["estimate"], test["se"], test["p"], test["upper"]
    per_subject = ", ".join(f"{s} {format_fixed(100 * v, 3)}" for s, v in slopes.items())
    our = (
        f"bending skin's advantage over the waterbed, slope against depth per subject "
        f"(% of W₀² per mm): {per_subject}; mean slope {format_fixed(100 * estimate, 3)} ± "
        f"{format_fixed(100 * se, 3)} (t = {format_fixed(test['t'], 2)}, "
        f"{counted(df, 'degree of freedom', 'degrees of freedom')}, one-sided p "
        f"{_p_text(p_value)})"
    )
    if p_value < alpha:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the bending skin's advantage over the "
            "membrane, relative to the depth, grows with depth (one-sided p "
            f"{_p_text(p_value)})."
        )
        return _row("C13", our, HOLDS, reason, rule)
    if upper < 0:
        reason = (
            f"Across {_n(len(slopes), 'subject')} the bending skin's advantage, relative to "
            f"the depth, shrinks with depth (upper bound {format_fixed(100 * upper, 3)} % of "
            "W₀² per mm): bending does not account for the worsening."
        )
        return _row("C13", our, FAILS, reason, rule)
    reason = (
        f"Across {_n(len(slopes), 'subject')} the mean slope of the bending skin's advantage "
        f"({format_fixed(100 * estimate, 3)} ± {format_fixed(100 * se, 3)} % of W₀² per mm) "
        "is neither shown to be above zero nor below it."
    )
    return _row("C13", our, UNTESTABLE, reason, rule)


CLAIM_FUNCTIONS = {
    "C1": claim_c1,
    "C2": claim_c2,
    "C3": claim_c3,
    "C4": claim_c4,
    "C5": claim_c5,
    "C6": claim_c6,
    "C7": claim_c7,
    "C8": claim_c8,
    "C9": claim_c9,
    "C10": claim_c10,
    "C11": claim_c11,
    "C13": claim_c13,
}

#: Claims that also take the force readings (keyword ``forces``).
FORCE_CLAIMS = ("C11",)


def compute_claims(fits, averaged, settings=None, forces=None):
    """The claims table: one row per claim C1-C11, each verdict from its stated rule.

    Parameters
    ----------
    fits : pandas.DataFrame
        Fit table (one row per subject and depth).
    averaged : pandas.DataFrame
        Averaged profiles of the subjects in ``fits``, stacked.
    settings : ClaimSettings, optional
        Thresholds of the rules; defaults as in the config schema.
    forces : pandas.DataFrame, optional
        Force readings (``subject``, ``depth_mm``, ``force_N``) for C11; None
        when the dataset has none (C11 then uses the shapes alone).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`CLAIM_COLUMNS`, rows C1 to C11 in order.
    """
    settings = settings or ClaimSettings()
    rows = [
        CLAIM_FUNCTIONS[claim](
            fits, averaged, settings, **({"forces": forces} if claim in FORCE_CLAIMS else {})
        )
        for claim in CLAIM_IDS
    ]
    return pd.DataFrame(rows, columns=CLAIM_COLUMNS)


def summary_sentence(claims):
    """One sentence counting the verdicts, evidence apart from identities.

    Parameters
    ----------
    claims : pandas.DataFrame
        Output of :func:`compute_claims`.

    Returns
    -------
    str
    """
    counts = verdict_counts(claims)
    text = (
        f"Of the paper's {counts['paper_claims']} claims about fingers, the data tested "
        f"{counts['evidence']}: {counts[HOLDS]} hold and {counts[FAILS]} do not"
    )
    extras = []
    if counts[UNTESTABLE]:
        extras.append(f"{counts[UNTESTABLE]} cannot be checked on these data")
    if counts[IDENTITY]:
        extras.append(
            f"{counts[IDENTITY]} {'is an identity' if counts[IDENTITY] == 1 else 'are identities'}"
            " of the model's equations and not evidence"
        )
    if "kind" in claims and counts["checks"]:
        others = claims[claims["kind"] != PAPER_CLAIM]
        extras.append(
            "checked and reported apart, not counted as evidence: "
            + join_words(f"{r['claim']} ({r['kind']})" for _, r in others.iterrows())
        )
    return text + ("; " + "; ".join(extras) if extras else "") + "."


def claims_markdown(claims, notice="", error_rates=None):
    """The claims table as Markdown: a table of verdicts, the rule of each claim, and
    how often each rule was wrong in the calibration.

    Parameters
    ----------
    claims : pandas.DataFrame
        Output of :func:`compute_claims`.
    notice : str, optional
        Data notice; when non-empty it is added as a footer line.
    error_rates : dict, optional
        Claim -> sentence, from :func:`lineload.simulation.calibration.claim_error_rates`
        (the calibration kept in ``docs/calibration/``); no section if None.

    Returns
    -------
    str
    """
    headers = [
        "Claim",
        "Kind",
        "Statement",
        "Where in the paper",
        "Paper",
        "Ours",
        "Verdict",
        "Reason",
    ]
    rows = [
        [
            r["claim"],
            r.get("kind", PAPER_CLAIM),
            r["statement"],
            r["paper_location"],
            r["paper_value"],
            r["our_value"],
            f"**{r['verdict']}**"
            + (
                f" (holds from a margin of {r['smallest_margin']})"
                if r.get("smallest_margin") not in (None, "", NO_MARGIN)
                else " (at no margin up to 20 %)"
                if r.get("smallest_margin") == NO_MARGIN
                else ""
            ),
            r["reason"],
        ]
        for _, r in claims.iterrows()
    ]
    text = (
        "# Claims of Srinivasan (1989), recomputed\n\n"
        "Each verdict comes from applying the rule below to numbers computed from the data "
        "this table was built from; it describes those data, not the paper's fingertips. "
        "Only the paper's claims about fingers (kind 'paper claim') are counted as evidence; "
        "a property or identity of the paper's method, and a check of the model's "
        "consistency, are checked and reported apart. The equivalence margins are the "
        "workflow's own (config claims: symmetry_margin, shift_margin, circularity_margin); "
        "beside each such verdict, the smallest margin of 1-20 % at which the claim holds. "
        f"{summary_sentence(claims)}\n\n"
    )
    text += markdown_table(headers, rows, "llllllll")
    text += "\n## Rules\n\n"
    text += "".join(
        f"- **{r['claim']}**: {' '.join(r['rule'].split())}\n" for _, r in claims.iterrows()
    )
    if error_rates:
        text += (
            "\n## How often each rule is wrong\n\n"
            "Measured by `snakemake calibration` (kept in `docs/calibration/`) on the "
            "synthetic reconstruction's design: its seven fingers and reading grids, read "
            "again and again with fresh digitising errors, in its own world and in worlds "
            "either side of a claim's boundary, where it just holds and where it just "
            "fails. The rates hold for other data as far as their "
            "design and noise resemble it.\n\n"
        )
        text += "".join(
            f"- **{claim}**: {error_rates[claim]}.\n"
            for claim in claims["claim"]
            if claim in error_rates
        )
    return text + notice_footer(notice)
