"""Surface-deflection models for a fingertip under a line load.

Four profiles, all giving the downward deflection of the skin surface as a
function of the horizontal distance from the wedge (both in millimetres):

* the waterbed membrane in its small-slope form (Srinivasan 1989, eq. 19),
  with the horizontal shift of material points (eq. 20).  Eq. 19 gives the
  deflection W at the *resting* position X of a point;
* the same small-slope solution placed where a photograph sees it: W(X) at the
  *deformed* position ``x = X + U(X)`` ("shifted");
* the exact finite-deformation waterbed: a circular arc from the load point to
  the channel wall that encloses zero net area (a curve in the deformed plane,
  so already in measured coordinates);
* the modified Boussinesq (Flamant) half-space, ``A ln(x0 / x)``.

The waterbed models live on ``0 <= X <= L``; beyond the wall (``X > L``) the
surface does not move, so they return zero there.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = [
    "MODELS",
    "MODEL_NAMES",
    "TABLE_MODELS",
    "ModelNames",
    "arc_deflection_mm",
    "arc_geometry",
    "boussinesq_deflection_mm",
    "resting_position_mm",
    "shift_is_one_to_one",
    "shifted_deflection_mm",
    "waterbed_deflection_mm",
    "waterbed_load_angle_rad",
    "waterbed_shift_mm",
    "waterbed_strain",
]


class ModelNames(NamedTuple):
    """How the outputs name one fitted model.

    Attributes
    ----------
    short : str or None
        Label in the headers of the Markdown and LaTeX fit and summary tables
        (``RMSE exact arc (mm)``); None for a model whose columns they leave out.
    refit : str
        Name in the sensitivity tables and figure, which say how W0 was fixed.
    legend : str or None
        Name in the figure legends; None for a model drawn only in the sensitivity
        figure (which uses ``refit``).
    """

    short: str | None
    refit: str
    legend: str | None


#: Every model the workflow fits, keyed as in the tables' column prefixes and
#: ``model`` cells, in the order of the sensitivity refits, with its names in the outputs.
#: The registry of model families (:mod:`lineload.fitting.families`) holds the rest of
#: each (curve, parameters, solver, columns, colour) and its tests check that both name
#: the same families; the names stay here so that the tables and the article read them
#: without importing the fitting wing.
MODEL_NAMES = {
    "waterbed": ModelNames("waterbed", "parabola, W₀ = depth", "waterbed parabola (eq. 19)"),
    "waterbed_free_depth": ModelNames(None, "parabola, W₀ free", None),
    "shifted": ModelNames(
        None, "parabola in measured coordinates", "parabola in measured coordinates"
    ),
    "arc": ModelNames("exact arc", "exact arc, W₀ = depth", "waterbed exact arc"),
    "boussinesq": ModelNames("Boussinesq", "Boussinesq", "modified Boussinesq"),
}

#: The model keys, in the order of the sensitivity refits.
MODELS = tuple(MODEL_NAMES)

#: The models of the fit table (one column group each), in column order (the registry's
#: families with fit-table columns, :func:`lineload.fitting.families.table_families`).
TABLE_MODELS = ("waterbed", "shifted", "arc", "boussinesq")


def waterbed_deflection_mm(distance_mm, depth_mm, L_mm):
    """Small-slope waterbed profile W(X) (eq. 19).

    ``W = W0 (3 s**2 - 4 s + 1)`` with ``s = X / L`` on ``0 <= X <= L`` and
    zero beyond the wall.

    Parameters
    ----------
    distance_mm : array_like
        Initial horizontal coordinate X from the load (mm, >= 0).
    depth_mm : float
        Deflection under the load, W0 (mm).
    L_mm : float
        Half-width of the membrane, L (mm, > 0).

    Returns
    -------
    numpy.ndarray
        Downward deflection W(X) (mm); negative values are the upward bulge.
    """
    s = np.asarray(distance_mm, dtype=float) / L_mm
    profile = depth_mm * (3.0 * s**2 - 4.0 * s + 1.0)
    return np.where(s > 1.0, 0.0, profile)  # NaN stays NaN


def waterbed_shift_mm(distance_mm, depth_mm, L_mm):
    """Horizontal shift U(X) of a membrane point in the small-slope solution (eq. 20).

    ``U = -(6 W0**2 / L) s (s - 1)**2`` with ``s = X / L``; zero at both ends,
    largest in magnitude at ``X = L / 3`` where it equals ``-8 W0**2 / (9 L)``.

    Parameters
    ----------
    distance_mm : array_like
        Initial horizontal coordinate X (mm, >= 0).
    depth_mm : float
        Deflection under the load, W0 (mm).
    L_mm : float
        Half-width of the membrane, L (mm).

    Returns
    -------
    numpy.ndarray
        Horizontal displacement U(X) (mm); negative means towards the load.
    """
    s = np.asarray(distance_mm, dtype=float) / L_mm
    shift = -(6.0 * depth_mm**2 / L_mm) * s * (s - 1.0) ** 2
    return np.where(s > 1.0, 0.0, shift)


#: Largest W0 / L at which x = X + U(X) is one-to-one on [0, L]: dx/dX = 1 - 6 (W0/L)**2 at
#: the load, and it is larger everywhere else on the membrane.
MAX_ONE_TO_ONE_RATIO = 1.0 / math.sqrt(6.0)


def shift_is_one_to_one(depth_mm, L_mm):
    """Whether the small-slope map ``x = X + U(X)`` is one-to-one on ``[0, L]``.

    ``dx/dX = 1 - 6 (W0/L)**2 (s - 1)(3 s - 1)`` with ``s = X / L``; the product
    ``(s - 1)(3 s - 1)`` lies in ``[-1/3, 1]`` with its maximum at the load, so
    the map folds (points near the load overtake each other) when
    ``6 (W0/L)**2 > 1``; at equality its slope at the load is zero.  Both are
    treated as not one-to-one: ``L <= sqrt(6) W0``.  There the small-slope
    solution has a slope of at least 1.6 at the load and is far outside its
    own assumptions.

    Parameters
    ----------
    depth_mm, L_mm : float or array_like
        W0 and L (mm).

    Returns
    -------
    bool or numpy.ndarray of bool
    """
    return 6.0 * (np.asarray(depth_mm, dtype=float) / np.asarray(L_mm, dtype=float)) ** 2 < 1.0


def _clipped_newton(start, params, step_of, converged, bounds):
    """Newton's method, each step clipped to ``bounds``, for many independent elements.

    ``step_of(value, *params)`` gives the step of each element (``params``: arrays
    of per-element data).  Each element iterates on its own until it meets
    ``converged(step, new_value)``, or its steps, already below 1e-10 of its size,
    stop shrinking (it has reached the rounding noise of its equation, where further
    steps would move it at random within that noise), or after 50 steps.  Finished
    elements are set aside, so a batch costs what its slowest element costs.
    """
    value = np.array(start, dtype=float)
    position = np.arange(value.size)
    current = value
    previous = np.full(value.size, np.inf)
    for _ in range(50):
        if position.size == 0:
            break
        step = step_of(current, *params)
        new = current - step
        np.clip(new, *bounds, out=new)
        size = np.abs(step)
        done = converged(step, new) | (new == current)
        done |= (size >= previous) & (size <= 1e-10 * np.maximum(np.abs(new), 1.0))
        if done.any():
            value[position[done]] = new[done]
            going = ~done
            position, current = position[going], new[going]
            params = tuple(values[going] for values in params)
            previous = size[going]
        else:
            current, previous = new, size
    value[position] = current
    return value


def resting_position_mm(distance_mm, depth_mm, L_mm):
    """Resting position X of the membrane point seen at deformed position x (inverse of eq. 20).

    Solves ``X + U(X) = x`` on ``0 <= x <= L``; with ``s = X / L``,
    ``t = x / L`` and ``k = 6 (W0/L)**2`` that is the cubic
    ``s - k s (s - 1)**2 = t``, increasing in ``s`` on ``[0, 1]`` when ``k < 1``
    (see :func:`shift_is_one_to_one`).  Newton's method from the first-order
    inverse ``s = t + k t (t - 1)**2``, each step clipped to ``[0, 1]``, reaches
    rounding in under 10 steps for ``k <= 0.999`` and slows only near the fold
    (about 20 steps at ``k = 1 - 1e-9``); each point stops when its step is below
    1e-15 or has reached rounding noise (see ``_clipped_newton``).  The tests check
    the residual of the cubic on a dense grid of ``k`` and ``t`` up to
    ``1 - 1e-9``.  Beyond the wall (``x > L``), and for a flat membrane
    (``L`` infinite), ``X = x``.

    Parameters
    ----------
    distance_mm : array_like
        Deformed horizontal position x (mm, >= 0).
    depth_mm : float
        W0 (mm).
    L_mm : float or array_like
        Half-width L (mm); broadcast against ``distance_mm``.

    Returns
    -------
    numpy.ndarray
        X (mm); NaN where the map is not one-to-one (``6 (W0/L)**2 >= 1``).
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    L_mm = np.asarray(L_mm, dtype=float)
    shape = np.broadcast_shapes(distance_mm.shape, L_mm.shape, np.shape(depth_mm))
    k = 6.0 * (depth_mm / L_mm) ** 2
    t = distance_mm / L_mm
    # on the membrane (t < 1, k < 1) and curved (k > 0); elsewhere the start is exact
    # (every step would be 0) and only these are iterated
    curved = np.broadcast_to((t < 1.0) & ((k < 1.0) & (k > 0.0)), shape)
    t_c, k_c = np.broadcast_to(t, shape)[curved], np.broadcast_to(k, shape)[curved]

    def step_of(s, t, k):
        # s - k s (s - 1)^2 - t over its derivative 1 - k (s - 1)(3 s - 1)
        u = s - 1.0
        return (s - k * s * u**2 - t) / (1.0 - k * u * (3.0 * s - 1.0))

    s = _clipped_newton(
        np.clip(t_c + k_c * t_c * (t_c - 1.0) ** 2, 0.0, 1.0),
        (t_c, k_c),
        step_of,
        lambda step, s: np.abs(step) <= 1e-15,
        (0.0, 1.0),
    )
    X_mm = np.array(np.broadcast_to(distance_mm, shape), order="C")
    X_mm[curved] = s * np.broadcast_to(L_mm, shape)[curved]
    folded = ~(k < 1.0)
    return np.where(folded, np.nan, X_mm) if folded.any() else X_mm


def shifted_deflection_mm(distance_mm, depth_mm, L_mm):
    """Small-slope waterbed seen in measured coordinates: W(X) at ``x = X + U(X)``.

    A photograph shows each point of the skin where it is after the load, at
    ``x = X + U(X)``; eq. 19 gives its deflection as a function of where it was,
    X.  This profile places eq. 19 at the deformed position (eqs 19-20), the
    coordinate-consistent form of the paper's small-slope solution.  Since
    ``U <= 0``, it lies slightly inside (towards the load) of eq. 19 plotted
    against x: both are equal at the load and meet at the wall, and where eq. 19
    read at x crosses zero at ``L/3``, this curve crosses at
    ``x = L/3 - 8 W0**2 / (9 L)``.

    Parameters
    ----------
    distance_mm : array_like
        Deformed horizontal position x (mm, >= 0).
    depth_mm : float
        W0 (mm).
    L_mm : float or array_like
        Half-width L (mm); broadcast against ``distance_mm``.

    Returns
    -------
    numpy.ndarray
        Downward deflection (mm); zero beyond the wall; NaN where the map
        ``X -> x`` is not one-to-one (``L <= sqrt(6) W0``).
    """
    X_mm = resting_position_mm(distance_mm, depth_mm, L_mm)
    return waterbed_deflection_mm(X_mm, depth_mm, L_mm)


def waterbed_strain(depth_mm, L_mm):
    """Uniform membrane (Green) strain of the small-slope solution, ``2 W0**2 / L**2``.

    Parameters
    ----------
    depth_mm : float or array_like
        Deflection under the load, W0 (mm).
    L_mm : float or array_like
        Half-width of the membrane (mm).

    Returns
    -------
    float or numpy.ndarray
        Dimensionless strain.
    """
    return 2.0 * np.asarray(depth_mm, dtype=float) ** 2 / np.asarray(L_mm, dtype=float) ** 2


def waterbed_load_angle_rad(depth_mm, L_mm):
    """Angle theta0 between the membrane and the horizontal at the load.

    In the small-slope solution the slope at ``X = 0`` is ``-4 W0 / L``, so
    ``theta0 = arctan(4 W0 / L)``; the load balances ``F = 2 N sin(theta0)``.

    Parameters
    ----------
    depth_mm : float or array_like
        Deflection under the load, W0 (mm).
    L_mm : float or array_like
        Half-width of the membrane (mm).

    Returns
    -------
    float or numpy.ndarray
        theta0 in radians.
    """
    return np.arctan(4.0 * np.asarray(depth_mm, dtype=float) / np.asarray(L_mm, dtype=float))


def _shape_and_slope(phi):
    """Shape function ``f = (2 phi - sin 2 phi) / (4 sin**2 phi)`` and its slope, phi >= 1e-3.

    The slope is ``1 - (2 phi - sin 2 phi) sin 2 phi / (4 sin**4 phi)``; both
    share their trigonometry.  (Near zero, ``f = phi/3 + 2 phi**3/45 + ...``.)
    """
    sin, sin2 = np.sin(phi), np.sin(2.0 * phi)
    numerator = 2.0 * phi - sin2
    return numerator / (4.0 * sin**2), 1.0 - numerator * sin2 / (4.0 * sin**4)


def _solve_half_angle(target):
    """Solve ``(2 phi - sin 2 phi) / (4 sin**2 phi) = target`` for ``0 <= target <= 1/2``.

    The shape function rises from 0 with slope 1/3 and is convex on
    ``[0, pi/2]``, where it reaches ``pi/4 > 1/2``.  Newton's method on a convex
    increasing function converges monotonically from any start right of the
    root, and from a start left of it the first step lands on the right.  The
    start is the inverted small-angle series ``phi = 3t - 3.6 t^3`` (from
    ``f = phi/3 + 2 phi^3/45 + ...``), already close, so a few steps suffice.
    Below ``phi = 1e-3`` the series itself is exact to rounding.
    """
    target = np.asarray(target, dtype=float)
    shape, target = target.shape, target.reshape(-1)
    start = np.minimum(3.0 * target - 3.6 * target**3, np.pi / 2)
    iterated = ~(start < 1e-3)  # below, the start is kept

    def step_of(phi, target):
        shape, slope = _shape_and_slope(phi)
        return (shape - target) / slope

    phi = start.copy()
    phi[iterated] = _clipped_newton(
        start[iterated],
        (target[iterated],),
        step_of,
        lambda step, phi: np.abs(step) <= 1e-15 + 1e-13 * phi,
        (1e-3, np.pi / 2),
    )
    return phi.reshape(shape)


def arc_geometry(depth_mm, L_mm):
    """Circle through the load point and the wall that encloses zero net area.

    The arc runs from ``(0, -W0)`` to ``(L, 0)`` (z upward).  With
    ``delta = W0 / L`` and chord ``c = L sqrt(1 + delta**2)``, its half-angle
    ``phi`` solves ``c**2 (2 phi - sin 2 phi) / (4 sin**2 phi) = W0 L``, so the
    circular segment above the chord cancels the triangle below the baseline.

    Parameters
    ----------
    depth_mm : float or array_like
        Deflection under the load, W0 (mm, > 0).
    L_mm : float or array_like
        Half-width of the membrane (mm, > 0); broadcast against ``depth_mm``.

    Returns
    -------
    dict of numpy.ndarray
        ``phi_rad`` (half-angle), ``radius_mm``, ``centre_x_mm``, ``centre_z_mm``
        and ``is_graph`` (True where the arc is a single-valued function of x on
        ``[0, L]``, i.e. it does not fold back past the load axis).
    """
    depth_mm, L_mm = np.broadcast_arrays(
        np.asarray(depth_mm, dtype=float), np.asarray(L_mm, dtype=float)
    )
    target = depth_mm * L_mm / (L_mm**2 + depth_mm**2)  # delta / (1 + delta**2) <= 1/2
    phi = _solve_half_angle(target)
    chord_mm = np.hypot(L_mm, depth_mm)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius_mm = chord_mm / (2.0 * np.sin(phi))
        # distance from the chord's midpoint to the centre, away from the bulge
        offset_mm = radius_mm * np.cos(phi)
        centre_x_mm = L_mm / 2.0 + offset_mm * depth_mm / chord_mm
        centre_z_mm = -depth_mm / 2.0 - offset_mm * L_mm / chord_mm
    is_graph = np.tan(phi) * depth_mm <= L_mm
    return {
        "phi_rad": phi,
        "radius_mm": radius_mm,
        "centre_x_mm": centre_x_mm,
        "centre_z_mm": centre_z_mm,
        "is_graph": is_graph,
    }


def arc_deflection_mm(distance_mm, depth_mm, L_mm, geometry=None):
    """Exact waterbed profile: the zero-area circular arc, as downward deflection.

    Parameters
    ----------
    distance_mm : array_like
        Horizontal distance x from the load in the deformed state (mm, >= 0).
    depth_mm : float or array_like
        Deflection under the load, W0 (mm, > 0).
    L_mm : float or array_like
        Half-width of the membrane (mm, > 0).  Arrays of ``depth_mm`` and
        ``L_mm`` broadcast against each other and against ``distance_mm``; the
        circle is solved once per (W0, L), not per distance.
    geometry : dict, optional
        ``arc_geometry(depth_mm, L_mm)`` if already at hand (a fit evaluates
        many distances for each (W0, L)); its arrays broadcast like ``L_mm``.

    Returns
    -------
    numpy.ndarray
        Downward deflection w(x) (mm); zero beyond the wall and NaN for every
        distance of an arc that is not a function of x (extreme W0 / L).
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    L_mm = np.asarray(L_mm, dtype=float)
    if geometry is None:
        geometry = arc_geometry(depth_mm, L_mm)
    is_graph = np.asarray(geometry["is_graph"])
    if is_graph.ndim == 0 and not bool(is_graph):
        return np.full(distance_mm.shape, np.nan)
    radius_squared = np.asarray(geometry["radius_mm"]) ** 2
    dx = distance_mm - geometry["centre_x_mm"]
    z_mm = geometry["centre_z_mm"] + np.sqrt(np.maximum(radius_squared - dx**2, 0.0))
    w_mm = np.where(distance_mm <= L_mm, -z_mm, 0.0)
    return w_mm if is_graph.ndim == 0 else np.where(is_graph, w_mm, np.nan)


def boussinesq_deflection_mm(distance_mm, A_mm, x0_mm):
    """Modified Boussinesq (Flamant) surface profile ``A ln(x0 / x)``.

    The half-space solution is infinite under the load; the modified form is
    used away from it only.  With a measured force per unit length ``P`` and
    Poisson's ratio 1/2, ``A = 3 P / (2 pi E)``.

    Parameters
    ----------
    distance_mm : array_like
        Distance from the load (mm, > 0).
    A_mm : float
        Amplitude (mm): the drop in deflection per unit of natural log distance.
    x0_mm : float
        Distance at which the deflection reaches zero (mm, > 0).

    Returns
    -------
    numpy.ndarray
        Downward deflection (mm); negative beyond ``x0``.
    """
    return A_mm * np.log(x0_mm / np.asarray(distance_mm, dtype=float))
