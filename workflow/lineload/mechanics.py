"""Forces on the wedge from the waterbed's shape: membrane pre-tension and stiffness.

The paper measured the steady reaction force on the wedge but never used it.
The waterbed ties force to shape.  Per unit length of wedge edge, the load is
carried by the two membrane halves (eq. 3), and the membrane force follows the
strain (eq. 7); this module lets the membrane carry a force at rest too::

    f = F / l = 2 N sin(theta0)        (eq. 3; l the length of edge in contact)
    N = N0 + E eps                      (eq. 7 with a pre-tension N0 >= 0 allowed)

``N``, ``N0`` and ``f`` are forces per unit length of wedge (N/mm).  ``E`` is a
*membrane* stiffness, force per unit length per unit strain (N/mm): Young's
modulus times the thickness of the skin, as in the paper's eq. 7.  ``eps`` is
the Green strain of eq. 8.  ``prestrain = N0 / E`` is the strain at which a
stress-free membrane would carry the tension ``N0``: the stretch the skin has at
rest, on the same scale as ``eps``.

Which waterbed supplies the geometry
------------------------------------
The exact solution (the circular arc, ``arc_L_mm`` of the fit table): its fitted
``L`` is in measured coordinates, and for that ``L`` this module computes the
exact load angle and strain.  The small-slope values, ``tan(theta0) = 4 W0/L``
and ``eps = 2 (W0/L)**2`` (:func:`lineload.models.waterbed_load_angle_rad`,
:func:`lineload.models.waterbed_strain`), are off by up to 7 % (angle) and 3 %
(strain) at 2 mm depth and ``L`` near 12 mm, several times the precision of a
force reading; they are kept in the tables beside the exact ones for comparison.
At any slope, moreover, the small-slope angle is short by ``3.6 (W0/L)**2``,
that is ``1.8 eps``, of itself: the pre-tension term ``N0 sin(theta0)`` then
loses ``1.8 N0 eps``, which a fit reads as a stiffness ``E - 1.8 N0``.  With a
tension at rest, ``E`` needs the exact angle (``tests/test_mechanics.py``).

Exact geometry (derived here, tested in ``tests/test_mechanics.py``).  The arc
runs from the load point ``(0, -W0)`` to the wall ``(L, 0)``; its chord rises at
``alpha = arctan(W0 / L)`` and it subtends ``2 phi`` at its centre
(:func:`lineload.models.arc_geometry`).  The angle between a circular arc and its
chord is ``phi`` at either end, and the arc bulges above the chord (the segment
above it cancels the triangle below the rest line), so at the load the membrane
makes ``theta0 = alpha + phi`` with the horizontal.  ``U = 0`` at both ends
(eq. 9a): the half-membrane, of length ``L`` at rest, becomes the whole arc,
of length ``2 phi R``; since the tension, and so the strain, is uniform, every
element stretches by ``lambda = 2 phi R / L``.  With ``1 + U'`` and ``W'`` the
components of the stretched element, eq. 8 is ``((1 + U')**2 + W'**2 - 1) / 2``,
so the Green strain is ``(lambda**2 - 1) / 2``.  (The engineering strain
``lambda - 1`` is smaller by ``(lambda - 1)**2 / 2``: 0.1 % of strain at 2 mm,
2 % of the strain there.)  For small ``delta = W0 / L``, ``phi = 3 delta``, so
``theta0 = 4 delta`` and the strain is ``2 delta**2``: the small-slope values.

The force fit
-------------
With ``u = sin(theta0)`` and ``v = eps sin(theta0)`` of each trial, the force is
linear in two constants::

    F = A u + B v,   A = 2 l N0,   B = 2 l E   (newtons)

so a subject's forces at two or more depths give ``A`` and ``B`` by weighted
least squares, ``prestrain = A / B`` without any contact length, and ``N0``, ``E``
when ``l`` is known.  Each force has the stated precision ``force_sd_N``; the
uncertainty of the fitted ``L`` (its 95 % interval read as +-1.96 standard
errors) moves ``u`` and ``v`` and is added to each force's variance through the
slope of the model in ``L`` (effective variance, iterated to a fixed point).
The force's own precision is measured from the pooled chi-square of all
subjects' fits (:func:`pooled_force_sd`; the config's value a floor and a
fallback), and the standard errors come from those variances; each subject's
``chi2`` says whether its scatter matches them.  A stress-free membrane is the
special case ``A = 0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from lineload import paper
from lineload.distributions import chi2_survival
from lineload.models import arc_geometry, waterbed_load_angle_rad, waterbed_strain
from lineload.trials import trial_key

__all__ = [
    "INTERVAL_Z",
    "SUBJECT_COLUMNS",
    "TRIAL_COLUMNS",
    "WATERBED_VARIANT",
    "MembraneFit",
    "allowed_force_ratio",
    "arc_load_angle_rad",
    "arc_strain",
    "arc_stretch",
    "fit_membrane",
    "force_groups",
    "force_terms",
    "mechanics_tables",
    "pooled_force_sd",
    "ratio_check",
    "reconciling_prestrain",
    "sd_from_interval",
]

#: The waterbed fit of the fit table whose L the mechanics use (columns ``arc_L_*``).
WATERBED_VARIANT = "arc"

#: A 95 % interval spans this many standard errors either side of the estimate.
INTERVAL_Z = 1.959963984540054

#: Relative step of the central difference in L (the geometry is smooth in L).
_L_STEP = 1e-6


def arc_stretch(depth_mm, L_mm):
    """Stretch of the exact waterbed membrane, arc length over rest length.

    Parameters
    ----------
    depth_mm : float or array_like
        Deflection under the load, W0 (mm, > 0).
    L_mm : float or array_like
        Half-width of the membrane at rest (mm, > 0).

    Returns
    -------
    numpy.ndarray
        ``2 phi R / L`` (dimensionless, > 1); NaN where the arc is not a graph
        over ``[0, L]`` or an input is not finite.
    """
    depth_mm, L_mm = np.broadcast_arrays(
        np.asarray(depth_mm, dtype=float), np.asarray(L_mm, dtype=float)
    )
    ok = np.isfinite(depth_mm) & np.isfinite(L_mm) & (depth_mm > 0) & (L_mm > 0)
    geometry = arc_geometry(np.where(ok, depth_mm, 1.0), np.where(ok, L_mm, 10.0))
    stretch = 2.0 * geometry["phi_rad"] * geometry["radius_mm"] / np.where(ok, L_mm, 10.0)
    return np.where(ok & geometry["is_graph"], stretch, np.nan)


def arc_strain(depth_mm, L_mm):
    """Green strain of the exact waterbed membrane, ``(lambda**2 - 1) / 2`` (eq. 8).

    Parameters
    ----------
    depth_mm, L_mm : float or array_like
        W0 and L (mm).

    Returns
    -------
    numpy.ndarray
        Dimensionless strain; tends to ``2 (W0/L)**2`` for small ``W0/L``.
    """
    stretch = arc_stretch(depth_mm, L_mm)
    return (stretch**2 - 1.0) / 2.0


def arc_load_angle_rad(depth_mm, L_mm):
    """Angle of the exact waterbed membrane with the horizontal at the load.

    ``theta0 = arctan(W0 / L) + phi``: the chord's rise plus the angle between
    the arc and its chord (see the module text).

    Parameters
    ----------
    depth_mm, L_mm : float or array_like
        W0 and L (mm).

    Returns
    -------
    numpy.ndarray
        theta0 (rad); tends to ``arctan(4 W0 / L)`` for small ``W0/L``; NaN where
        :func:`arc_stretch` is NaN.
    """
    depth_mm, L_mm = np.broadcast_arrays(
        np.asarray(depth_mm, dtype=float), np.asarray(L_mm, dtype=float)
    )
    ok = np.isfinite(arc_stretch(depth_mm, L_mm))
    safe_depth, safe_L = np.where(ok, depth_mm, 1.0), np.where(ok, L_mm, 10.0)
    phi = arc_geometry(safe_depth, safe_L)["phi_rad"]
    return np.where(ok, np.arctan2(safe_depth, safe_L) + phi, np.nan)


def force_terms(depth_mm, L_mm):
    """The two shape terms of the force, ``u = sin(theta0)`` and ``v = eps sin(theta0)``.

    ``F = 2 l (N0 u + E v)``: ``u`` carries the pre-tension, ``v`` the stiffness.
    Exact arc geometry (:func:`arc_load_angle_rad`, :func:`arc_strain`).

    Parameters
    ----------
    depth_mm, L_mm : float or array_like
        W0 and L (mm).

    Returns
    -------
    tuple of numpy.ndarray
        ``(u, v)``, dimensionless.
    """
    sine = np.sin(arc_load_angle_rad(depth_mm, L_mm))
    return sine, arc_strain(depth_mm, L_mm) * sine


def _force_term_slopes(depth_mm, L_mm):
    """d u / d L and d v / d L (per mm), by central differences."""
    depth_mm, L_mm = np.asarray(depth_mm, dtype=float), np.asarray(L_mm, dtype=float)
    step = _L_STEP * L_mm
    u_hi, v_hi = force_terms(depth_mm, L_mm + step)
    u_lo, v_lo = force_terms(depth_mm, L_mm - step)
    return (u_hi - u_lo) / (2.0 * step), (v_hi - v_lo) / (2.0 * step)


def sd_from_interval(low_mm, high_mm):
    """Standard error from a 95 % interval: its width over ``2 x 1.96``; NaN if open.

    Parameters
    ----------
    low_mm, high_mm : float or array_like
        Ends of the interval (mm).

    Returns
    -------
    numpy.ndarray
    """
    low_mm, high_mm = np.asarray(low_mm, dtype=float), np.asarray(high_mm, dtype=float)
    width = high_mm - low_mm
    return np.where(np.isfinite(width), width / (2.0 * INTERVAL_Z), np.nan)


@dataclass(frozen=True)
class MembraneFit:
    """A subject's forces fitted by ``F = A u + B v`` (see the module text).

    Attributes
    ----------
    tension_N, tension_se_N : float
        ``A = 2 l N0`` and its standard error (N); exactly 0 for a stress-free fit.
    stiffness_N, stiffness_se_N : float
        ``B = 2 l E`` and its standard error (N).
    covariance_N2 : tuple of float
        ``(var A, cov AB, var B)`` (N^2).
    prestrain, prestrain_se : float
        ``N0 / E = A / B`` and its standard error (delta method); 0 for a
        stress-free fit.
    chi2 : float
        Sum of squared residuals over each force's variance.
    dof : int
        Forces minus fitted constants.
    rms_residual_N : float
        Root-mean-square of measured minus fitted force (N).
    fitted_force_N : tuple of float
        The fitted force of each input trial, in input order.
    force_variance_N2 : tuple of float
        The variance given to each force (precision plus the part from L).
    stress_free : bool
        Whether ``A`` was held at 0.
    """

    tension_N: float
    tension_se_N: float
    stiffness_N: float
    stiffness_se_N: float
    covariance_N2: tuple
    prestrain: float
    prestrain_se: float
    chi2: float
    dof: int
    rms_residual_N: float
    fitted_force_N: tuple
    force_variance_N2: tuple
    stress_free: bool

    def per_length(self, contact_length_mm):
        """``N0``, its SE, ``E`` and its SE (N/mm) for a contact length; NaN without one.

        Parameters
        ----------
        contact_length_mm : float or None
            Length of wedge edge in contact with the finger (mm).

        Returns
        -------
        tuple of float
            ``(N0, N0_se, E, E_se)``.
        """
        if contact_length_mm is None or not math.isfinite(contact_length_mm):
            return (math.nan,) * 4
        scale = 2.0 * contact_length_mm
        return (
            self.tension_N / scale,
            self.tension_se_N / scale,
            self.stiffness_N / scale,
            self.stiffness_se_N / scale,
        )

    @property
    def p_value(self):
        """Probability of a chi2 at least this large if the model and variances are right."""
        return float(chi2_survival(self.chi2, self.dof)) if self.dof > 0 else math.nan


def fit_membrane(depth_mm, L_mm, force_N, force_sd_N, L_sd_mm=None, stress_free=False):
    """Fit pre-tension and stiffness (or stiffness alone) to one subject's forces.

    Parameters
    ----------
    depth_mm : array_like
        Indentation depth W0 of each trial (mm).
    L_mm : array_like
        Fitted half-width of the exact arc of each trial (mm).
    force_N : array_like
        Steady reaction force on the wedge of each trial (N).
    force_sd_N : float
        Precision of one force reading (N, standard deviation, > 0).
    L_sd_mm : array_like, optional
        Standard error of each L (mm); None or 0 for L known exactly.
    stress_free : bool, optional
        Hold the pre-tension at 0 (the paper's eq. 7) and fit the stiffness alone.

    Returns
    -------
    MembraneFit

    Raises
    ------
    ValueError
        If the inputs differ in length, a value is not finite, or there are
        fewer forces than constants to fit.
    """
    depth_mm = np.asarray(depth_mm, dtype=float)
    L_mm = np.asarray(L_mm, dtype=float)
    force_N = np.asarray(force_N, dtype=float)
    L_sd_mm = np.zeros_like(L_mm) if L_sd_mm is None else np.asarray(L_sd_mm, dtype=float)
    if not depth_mm.shape == L_mm.shape == force_N.shape == L_sd_mm.shape:
        raise ValueError("depth_mm, L_mm, force_N and L_sd_mm need one value per trial")
    n_constants = 1 if stress_free else 2
    if force_N.size < n_constants:
        raise ValueError(f"need at least {n_constants} forces, got {force_N.size}")
    if not (force_sd_N > 0 and math.isfinite(force_sd_N)):
        raise ValueError(f"force_sd_N must be a positive number, got {force_sd_N}")
    u, v = force_terms(depth_mm, L_mm)
    du, dv = _force_term_slopes(depth_mm, L_mm)
    values = np.concatenate([u, v, du, dv, force_N, L_sd_mm])
    if not np.all(np.isfinite(values)):
        raise ValueError("every depth, L, force and L error must be finite")
    design = v[:, None] if stress_free else np.column_stack([u, v])
    slopes = dv[:, None] if stress_free else np.column_stack([du, dv])
    variance = np.full(force_N.shape, force_sd_N**2)
    constants = np.zeros(n_constants)
    for _ in range(200):
        weight = 1.0 / variance
        normal = design.T @ (design * weight[:, None])
        new = np.linalg.solve(normal, design.T @ (weight * force_N))
        variance = force_sd_N**2 + (slopes @ new * L_sd_mm) ** 2
        converged = np.all(np.abs(new - constants) <= 1e-13 * np.maximum(np.abs(new), 1e-300))
        constants = new
        if converged:
            break
    covariance = np.linalg.inv(design.T @ (design / variance[:, None]))
    fitted = design @ constants
    dof = int(force_N.size - n_constants)
    # with as many forces as constants the fit is exact: no residual but rounding
    residual = force_N - fitted if dof > 0 else np.zeros_like(force_N)
    if stress_free:
        A, var_A, cov_AB = 0.0, 0.0, 0.0
        B, var_B = float(constants[0]), float(covariance[0, 0])
        prestrain, prestrain_se = 0.0, 0.0
    else:
        A, B = float(constants[0]), float(constants[1])
        var_A, cov_AB, var_B = (
            float(covariance[0, 0]),
            float(covariance[0, 1]),
            float(covariance[1, 1]),
        )
        prestrain = A / B
        gradient = np.array([1.0 / B, -A / B**2])
        prestrain_se = float(np.sqrt(gradient @ covariance @ gradient))
    return MembraneFit(
        tension_N=A,
        tension_se_N=math.sqrt(var_A),
        stiffness_N=B,
        stiffness_se_N=math.sqrt(var_B),
        covariance_N2=(var_A, cov_AB, var_B),
        prestrain=prestrain,
        prestrain_se=prestrain_se,
        chi2=float(np.sum(residual**2 / variance)),
        dof=dof,
        rms_residual_N=float(np.sqrt(np.mean(residual**2))),
        fitted_force_N=tuple(float(f) for f in fitted),
        force_variance_N2=tuple(float(s) for s in variance),
        stress_free=stress_free,
    )


def allowed_force_ratio(force_range_N=paper.FORCE_RANGE_N):
    """Largest ratio of two forces inside a range: its top over its bottom.

    Every force the paper reports lies in 0.3-1 N (:data:`lineload.paper.FORCE_RANGE_N`),
    so no subject's force at one depth can exceed its force at another by more
    than ``1.0 / 0.3``.

    Parameters
    ----------
    force_range_N : tuple of float
        ``(low, high)`` (N, ``0 < low <= high``).

    Returns
    -------
    float
    """
    low, high = force_range_N
    return float(high) / float(low)


def reconciling_prestrain(small, large, allowed_ratio):
    """Smallest pre-strain that brings the force ratio of two trials within a bound.

    With pre-strain ``p``, the ratio of the larger trial's force to the smaller
    one's is ``R(p) = (v2 + p u2) / (v1 + p u1)``: the stress-free ratio ``v2/v1``
    at ``p = 0``, moving monotonically to the tension-only ratio ``u2/u1`` as ``p``
    grows.  So the bound is met by ``p = 0`` if ``v2/v1`` meets it, by
    ``p = (v2 - R v1) / (R u1 - u2)`` if only the tension-only limit does, and by
    no pre-strain at all otherwise.

    Parameters
    ----------
    small, large : tuple of float
        ``(u, v)`` of the shallower and of the deeper trial (:func:`force_terms`).
    allowed_ratio : float
        The largest ratio allowed (> 0).

    Returns
    -------
    float
        The pre-strain (dimensionless, >= 0); ``inf`` if none reconciles; NaN if
        an input is not finite.
    """
    (u1, v1), (u2, v2) = small, large
    if not all(math.isfinite(x) for x in (u1, v1, u2, v2)):
        return math.nan
    if v2 <= allowed_ratio * v1:
        return 0.0
    if u2 >= allowed_ratio * u1:
        return math.inf
    return (v2 - allowed_ratio * v1) / (allowed_ratio * u1 - u2)


def ratio_check(depth_small_mm, L_small, depth_large_mm, L_large, allowed_ratio):
    """Force ratios a waterbed with these shapes implies between two depths.

    Parameters
    ----------
    depth_small_mm, depth_large_mm : float
        The shallower and the deeper depth (mm).
    L_small, L_large : tuple of float
        ``(L, interval low, interval high)`` of each (mm), the exact arc's fit.
    allowed_ratio : float
        The largest ratio allowed (:func:`allowed_force_ratio`).

    Returns
    -------
    dict
        ``stress_free`` (ratio at the fitted L), ``stress_free_low`` and
        ``stress_free_high`` (the smallest and largest ratio with each L anywhere
        in its interval: an L is larger for a flatter membrane, which needs less
        force), ``tension_only`` (the limit of a membrane held by its pre-tension
        alone), ``prestrain`` (:func:`reconciling_prestrain` at the fitted L).
        An open or missing interval gives 0 and ``inf`` at the ends.
    """
    u1, v1 = (float(x) for x in force_terms(depth_small_mm, L_small[0]))
    u2, v2 = (float(x) for x in force_terms(depth_large_mm, L_large[0]))

    def term_v(depth_mm, L_mm):
        if not (math.isfinite(L_mm) and L_mm > 0):
            return math.nan
        return float(force_terms(depth_mm, L_mm)[1])

    low = term_v(depth_large_mm, L_large[2]) / term_v(depth_small_mm, L_small[1])
    high = term_v(depth_large_mm, L_large[1]) / term_v(depth_small_mm, L_small[2])
    return {
        "stress_free": v2 / v1,
        "stress_free_low": low if math.isfinite(low) else 0.0,
        "stress_free_high": high if math.isfinite(high) else math.inf,
        "tension_only": u2 / u1,
        "prestrain": reconciling_prestrain((u1, v1), (u2, v2), allowed_ratio),
    }


# --------------------------------------------------------------------------- tables

#: Columns of ``mechanics_trials.csv``: one row per trial of the fit table.
TRIAL_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "waterbed_variant",
    "L_mm",
    "L_sd_mm",
    "load_angle_rad",
    "strain",
    "small_slope_load_angle_rad",
    "small_slope_strain",
    "force_N",
    "contact_length_mm",
    "force_per_length_N_per_mm",
    "membrane_force_N_per_mm",
    "fitted_force_N",
    "stress_free_force_N",
]

#: Columns of ``mechanics.csv``: one row per subject with forces at two or more depths.
SUBJECT_COLUMNS = [
    "subject",
    "species",
    "n_depths",
    "contact_length_mm",
    "pretension_N_per_mm",
    "pretension_se_N_per_mm",
    "stiffness_N_per_mm",
    "stiffness_se_N_per_mm",
    "prestrain",
    "prestrain_se",
    "chi2",
    "dof",
    "rms_residual_N",
    "stress_free_chi2",
    "stress_free_dof",
    "stress_free_p_value",
    "force_sd_N",
    "force_sd_dof",
    "force_sd_source",
]


def pooled_force_sd(groups, prior_sd_N):
    """The precision of one force reading, from the pooled chi-square of the membrane fits.

    Each subject's two-constant fit (:func:`fit_membrane`) leaves ``n - 2`` degrees of
    freedom; over all subjects, the SD ``s`` at which the chi-squares add up to their
    degrees of freedom, ``sum chi2(s) = sum dof`` (each force's variance ``s**2`` plus
    the part from its L), is the estimate.  The config's prior is a floor (a scatter
    the L errors already explain does not shrink it) and the fallback where no subject
    leaves a degree of freedom.

    Parameters
    ----------
    groups : sequence of tuple
        ``(depth_mm, L_mm, force_N, L_sd_mm)`` arrays of each subject with forces at
        two or more depths.
    prior_sd_N : float
        The config's ``mechanics: force_sd_N`` (N).

    Returns
    -------
    tuple
        ``(sd_N, dof, source)``: the SD used, the pooled degrees of freedom and
        ``"pooled chi-square"``, ``"config prior (floor)"`` or ``"config prior
        (no degrees of freedom)"``.
    """
    from scipy.optimize import brentq

    usable = [g for g in groups if len(g[0]) > 2]
    dof = sum(len(g[0]) - 2 for g in usable)
    if dof == 0:
        return prior_sd_N, 0, "config prior (no degrees of freedom)"

    def excess(log_sd):
        sd = math.exp(log_sd)
        return sum(fit_membrane(*g[:3], sd, g[3]).chi2 for g in usable) - dof

    low, high = math.log(prior_sd_N), math.log(prior_sd_N)
    if excess(low) <= 0:
        return prior_sd_N, dof, "config prior (floor)"
    while excess(high) > 0:
        high += math.log(2.0)
    sd = math.exp(brentq(excess, low, high, xtol=1e-10))
    return sd, dof, "pooled chi-square"


def _force_lookup(forces):
    """Force by trial (:func:`lineload.trials.trial_key`), from subject, depth_mm, force_N."""
    if forces is None or len(forces) == 0:
        return {}
    return {
        trial_key(s, d): float(f)
        for s, d, f in zip(forces["subject"], forces["depth_mm"], forces["force_N"], strict=True)
    }


def _subject_arrays(subject, rows, lookup):
    """One subject's fit rows in order of depth, with their depth, exact-arc L, L's SD
    (from its interval) and force (NaN where none): ``(rows, depth, L, L_sd, force)``."""
    rows = rows.sort_values("depth_mm", kind="stable")
    depth = rows["depth_mm"].to_numpy(float)
    L_mm = rows[f"{WATERBED_VARIANT}_L_mm"].to_numpy(float)
    L_sd = sd_from_interval(
        rows[f"{WATERBED_VARIANT}_L_ci_low_mm"], rows[f"{WATERBED_VARIANT}_L_ci_high_mm"]
    )
    force = np.array([lookup.get(trial_key(subject, d), math.nan) for d in depth])
    return rows, depth, L_mm, L_sd, force


def force_groups(fits, forces):
    """Each subject's trials that a membrane fit can use: forces at two or more depths.

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``subject``, ``depth_mm`` and the ``arc_L_*`` columns).
    forces : pandas.DataFrame or None
        ``subject``, ``depth_mm``, ``force_N`` (N).

    Returns
    -------
    dict
        Subject -> ``(depth_mm, L_mm, force_N, L_sd_mm)`` arrays in order of depth, the
        trials with a force, a finite exact-arc L with a finite interval and a load
        angle; only subjects with two or more such depths.
    """
    lookup = _force_lookup(forces)
    groups = {}
    for subject, rows in fits.groupby("subject", sort=False):
        _, depth, L_mm, L_sd, force = _subject_arrays(subject, rows, lookup)
        usable = np.isfinite(force) & np.isfinite(arc_load_angle_rad(depth, L_mm))
        usable &= np.isfinite(L_sd)
        if np.unique(depth[usable]).size >= 2:
            groups[str(subject)] = (depth[usable], L_mm[usable], force[usable], L_sd[usable])
    return groups


def mechanics_tables(fits, forces=None, contact_length_mm=None, force_sd_N=None):
    """The per-trial and per-subject mechanics tables.

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``subject``, ``species``, ``depth_mm`` and the ``arc_L_*``
        columns), subject-sheet order.
    forces : pandas.DataFrame, optional
        ``subject``, ``depth_mm``, ``force_N`` (N); None when there is none.
    contact_length_mm : dict, optional
        Subject -> length of wedge edge in contact (mm); subjects missing or
        None have none.
    force_sd_N : float, optional
        The config's precision of one force reading (N; None takes the schema's
        default, ``mechanics: force_sd_N``): a floor and a fallback of the
        precision measured from the pooled chi-square of the membrane fits
        (:func:`pooled_force_sd`), which the standard errors use.

    Returns
    -------
    tuple of pandas.DataFrame
        ``(subjects, trials)`` with columns :data:`SUBJECT_COLUMNS` and
        :data:`TRIAL_COLUMNS`.  A subject gets a row of ``subjects`` when it has
        forces at two or more depths with a finite arc L and L interval.
    """
    if force_sd_N is None:
        from lineload.io import config_defaults

        force_sd_N = config_defaults("mechanics")["force_sd_N"]
    lengths = {
        str(k): (math.nan if v is None else float(v)) for k, v in (contact_length_mm or {}).items()
    }
    lookup = _force_lookup(forces)
    trials, subjects = [], []
    groups = force_groups(fits, forces)
    prior_sd_N = force_sd_N
    force_sd_N, sd_dof, sd_source = pooled_force_sd(list(groups.values()), prior_sd_N)
    for subject, rows in fits.groupby("subject", sort=False):
        subject = str(subject)
        rows, depth, L_mm, L_sd, force = _subject_arrays(subject, rows, lookup)
        length = lengths.get(subject, math.nan)
        angle = arc_load_angle_rad(depth, L_mm)
        strain = arc_strain(depth, L_mm)
        _, v = force_terms(depth, L_mm)
        per_length = force / length
        usable = np.isfinite(force) & np.isfinite(angle) & np.isfinite(L_sd)
        fitted = np.full(depth.shape, math.nan)
        stress_free = np.full(depth.shape, math.nan)
        if usable.any():
            first = int(np.argmax(usable))  # smallest depth with a usable force
            stress_free = np.where(np.isfinite(v), force[first] * v / v[first], math.nan)
        if np.unique(depth[usable]).size >= 2:
            fit = fit_membrane(depth[usable], L_mm[usable], force[usable], force_sd_N, L_sd[usable])
            free = fit_membrane(
                depth[usable], L_mm[usable], force[usable], force_sd_N, L_sd[usable], True
            )
            fitted[usable] = fit.fitted_force_N
            N0, N0_se, E, E_se = fit.per_length(length)
            subjects.append(
                {
                    "subject": subject,
                    "species": rows["species"].iloc[0],
                    "n_depths": int(usable.sum()),
                    "contact_length_mm": length,
                    "pretension_N_per_mm": N0,
                    "pretension_se_N_per_mm": N0_se,
                    "stiffness_N_per_mm": E,
                    "stiffness_se_N_per_mm": E_se,
                    "prestrain": fit.prestrain,
                    "prestrain_se": fit.prestrain_se,
                    "chi2": fit.chi2,
                    "dof": fit.dof,
                    "rms_residual_N": fit.rms_residual_N,
                    "stress_free_chi2": free.chi2,
                    "stress_free_dof": free.dof,
                    "stress_free_p_value": free.p_value,
                    "force_sd_N": force_sd_N,
                    "force_sd_dof": sd_dof,
                    "force_sd_source": sd_source,
                }
            )
        for i, (_, row) in enumerate(rows.iterrows()):
            trials.append(
                {
                    "subject": subject,
                    "species": row["species"],
                    "depth_mm": depth[i],
                    "waterbed_variant": WATERBED_VARIANT,
                    "L_mm": L_mm[i],
                    "L_sd_mm": float(L_sd[i]),
                    "load_angle_rad": float(angle[i]),
                    "strain": float(strain[i]),
                    "small_slope_load_angle_rad": float(waterbed_load_angle_rad(depth[i], L_mm[i])),
                    "small_slope_strain": float(waterbed_strain(depth[i], L_mm[i])),
                    "force_N": force[i],
                    "contact_length_mm": length,
                    "force_per_length_N_per_mm": per_length[i],
                    "membrane_force_N_per_mm": per_length[i] / (2.0 * math.sin(angle[i])),
                    "fitted_force_N": fitted[i],
                    "stress_free_force_N": float(stress_free[i]),
                }
            )
    return (
        pd.DataFrame(subjects, columns=SUBJECT_COLUMNS),
        pd.DataFrame(trials, columns=TRIAL_COLUMNS),
    )
