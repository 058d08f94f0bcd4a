"""The bending skin at finite slopes: a numerical solution, to measure the small-slope error.

:mod:`lineload.bending` solves the tensioned plate in its small-slope form, as the
paper solves its membrane (eq. 19).  At 2 mm of depth on a half-width of 10 mm the
slope under the wedge is far from small, and the paper's own membrane is then
measurably off its exact solution, the circular arc.  This module solves the same
skin without the small-slope step, so that the error of that step can be measured
where it matters (it is not used by the fits).

Equations
---------
The skin is a planar rod of bending rigidity D; with arc length s from the load,
tangent angle theta, position (x, z) (z upward, the load at ``z = -W0``), and the
internal force ``F = (Fx, Fz)`` that the part beyond s exerts on the part before it:

* the core's pressure p acts along the normal, so ``dF/ds = -p n`` with
  ``n = (-sin theta, cos theta)``; integrated, ``Fx = H + p (z + W0)`` and
  ``Fz = V - p x``, with H and V the force's components at the load;
* moments: ``D theta'' = Fx sin theta - Fz cos theta``;
* volume: ``integral z dx = 0`` over the half-width (eq. 2, without the
  small-slope step).

For small slopes (``theta ~ -W'``, ``Fx ~ H``) the moment equation becomes
``D W'''' - H W'' + p = 0``: the small-slope model with ``N = H``.  So here the
bending length is ``l_b = sqrt(D / H)``, H the horizontal force at the load.

Conditions: at the load ``x = 0``, ``z = -W0``, ``theta = 0``; at the wall
``x = L``, ``z = 0`` and ``theta = 0`` (clamped) or ``theta' = 0`` (pinned).  The
unknowns beside the profile are p, V and the deformed length S of the half-skin.
With ``l_b -> 0`` the solution tends to the membrane's exact arc
(:func:`lineload.models.arc_deflection_mm`); with ``W0 -> 0`` to the small-slope
profile.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_bvp

from lineload.bending import bending_coefficients, bending_deflection_mm, bending_load_per_tension

__all__ = ["SMALL_SLOPE_COLUMNS", "bending_finite_profile", "small_slope_error"]


def bending_finite_profile(depth_mm, L_mm, bending_length_mm, wall="clamped", n_nodes=801):
    """The bending skin's profile without the small-slope approximation.

    Parameters
    ----------
    depth_mm, L_mm, bending_length_mm : float
        W0, L and ``l_b = sqrt(D / H)`` (mm).
    wall : {"clamped", "pinned"}
    n_nodes : int
        Nodes of the starting mesh (solve_bvp refines it), graded towards both ends
        where the layers of width ``l_b`` lie.

    Returns
    -------
    dict
        ``distance_mm`` (the deformed position x, from 0 to L, increasing),
        ``deflection_mm`` (downward, ``-z``), ``pressure_per_H_per_mm`` (p / H),
        ``load_per_H`` (the wedge's force over H, ``2 V / H``: the wedge pushes down
        on two halves, each holding it up with V) and
        ``length_mm`` (the deformed length of the half-skin).

    Raises
    ------
    RuntimeError
        If the collocation does not converge (very steep or very thin layers).
    """
    W0, L, lb = float(depth_mm), float(L_mm), float(bending_length_mm)
    D = lb**2  # with H = 1: lengths stay in mm, forces in units of H

    # sigma in [0, 1] is s / S; y = (x, z, theta, dtheta/ds, integral of z dx)
    def rhs(sigma, y, params):
        p, V, S = params
        x, z, theta, curvature, _ = y
        Fx = 1.0 + p * (z + W0)
        Fz = V - p * x
        return S * np.vstack(
            [
                np.cos(theta),
                np.sin(theta),
                curvature,
                (Fx * np.sin(theta) - Fz * np.cos(theta)) / D,
                z * np.cos(theta),
            ]
        )

    def ends(ya, yb, params):
        far = yb[2] if wall == "clamped" else yb[3]
        return np.array([ya[0], ya[1] + W0, ya[2], ya[4], yb[0] - L, yb[1], far, yb[4]])

    # a mesh graded at both ends, and the small-slope solution as the start
    u = np.linspace(0.0, 1.0, n_nodes)
    sigma = 0.5 - 0.5 * np.cos(np.pi * u)
    X = sigma * L
    W = bending_deflection_mm(X, W0, L, lb, wall)
    slope = np.gradient(-W, X)
    guess = np.vstack([X, -W, np.arctan(slope), np.gradient(np.arctan(slope), X), np.zeros_like(X)])
    c = bending_coefficients(L / lb, wall)[2]
    p0 = 2.0 * c * W0 / L**2
    V0 = 0.5 * bending_load_per_tension(W0, L, lb, wall)
    length0 = float(np.sum(np.hypot(np.diff(X), np.diff(W))))
    solution = solve_bvp(rhs, ends, sigma, guess, p=[p0, V0, length0], tol=1e-8, max_nodes=200_000)
    if not solution.success:
        raise RuntimeError(f"no finite-slope solution found: {solution.message}")
    fine = np.linspace(0.0, 1.0, 4 * n_nodes)
    x, z = solution.sol(fine)[:2]
    if np.any(np.diff(x) <= 0):
        raise RuntimeError("the skin folds back past the load axis: not a graph of x")
    p, V, S = solution.p
    return {
        "distance_mm": x,
        "deflection_mm": -z,
        "pressure_per_H_per_mm": float(p),
        "load_per_H": float(2.0 * V),
        "length_mm": float(S),
    }


#: Columns of :func:`small_slope_error` rows, units in their names.
SMALL_SLOPE_COLUMNS = [
    "depth_mm",
    "L_mm",
    "bending_length_mm",
    "wall",
    "max_error_in_window_mm",
    "fitted_L_mm",
    "fitted_bending_length_mm",
    "fit_rmse_mm",
]


def small_slope_error(depth_mm, L_mm, bending_length_mm, distance_mm, wall="clamped"):
    """What the small-slope step costs for one skin: its error, and what a fit makes of it.

    The finite-slope profile (:func:`bending_finite_profile`) is read at
    ``distance_mm`` as a photograph would read it (at the deformed position), and the
    small-slope model is fitted to it (:func:`lineload.fitting.bending.fit_bending`) with
    W0 at the depth, as the workflow fits readings.

    Parameters
    ----------
    depth_mm, L_mm, bending_length_mm : float
        The skin (mm).
    distance_mm : array_like
        Where the profile is read (mm, > 0): the readings of one fit window.
    wall : {"clamped", "pinned"}

    Returns
    -------
    dict
        One row with the keys of :data:`SMALL_SLOPE_COLUMNS`: the largest difference
        between the two profiles at the readings, and the small-slope fit's ``L``,
        ``l_b`` and RMSE on the finite-slope profile.
    """
    from lineload.fitting.bending import fit_bending

    distance_mm = np.asarray(distance_mm, dtype=float)
    exact = bending_finite_profile(depth_mm, L_mm, bending_length_mm, wall)
    read = np.interp(distance_mm, exact["distance_mm"], exact["deflection_mm"])
    small = bending_deflection_mm(distance_mm, depth_mm, L_mm, bending_length_mm, wall)
    fit = fit_bending(distance_mm, read, depth_mm, wall=wall)
    return {
        "depth_mm": depth_mm,
        "L_mm": L_mm,
        "bending_length_mm": bending_length_mm,
        "wall": wall,
        "max_error_in_window_mm": float(np.max(np.abs(read - small))),
        "fitted_L_mm": fit.params["L_mm"],
        "fitted_bending_length_mm": fit.params["bending_length_mm"],
        "fit_rmse_mm": fit.rmse_mm,
    }
