"""The waterbed with a skin that bends: a tensioned plate on an incompressible core.

The paper's waterbed is a membrane: it carries tension N but no bending moment, so
under the wedge it takes a kink and between the wedge and the wall it takes the
constant curvature the core's pressure gives it (a parabola in the small-slope
form, eq. 19).  The paper closes by suggesting that the skin's thickness and
bending rigidity may matter.  This module adds that rigidity, and nothing else.

The model
---------
Plane strain, as the paper's waterbed: a strip of skin of width 2L over an
incompressible fluid in a rigid channel, pushed down at its middle to the depth
W0.  Per unit length of the wedge the skin carries a tension N (constant, as in
the paper's eq. 5, in the small-slope limit) and has a bending rigidity D; the
fluid's excess pressure p is fixed by volume conservation.  With W the downward
deflection at the resting position X (the paper's convention), small slopes give

    D W'''' - N W'' + p = 0        on 0 < X < L,

the beam-column equation of a tensioned plate.  With the bending length
``l_b = sqrt(D / N)`` and ``s = X / L``, ``kappa = L / l_b``, the solution is a
quadratic (the membrane part, ``p / 2N`` its curvature) plus two hyperbolic terms;
written with the decaying exponentials that span the same space as ``cosh`` and
``sinh`` (so it stays exact and well conditioned when ``l_b`` is small)

    W / W0 = a + b s + c s**2 + e exp(-kappa s) + g exp(-kappa (1 - s)).

Boundary conditions (five, for the five coefficients, p included through c):

* under the wedge, ``W(0) = W0``: the depth is imposed, as in the paper's fit;
* under the wedge, ``W'(0) = 0``: the wedge is treated as a line load on a skin
  that bends.  Such a skin cannot take a kink: by symmetry its slope at the load is
  zero, and it turns over a length of about ``l_b`` towards the membrane's slope.
  A sharp wedge would indent a real skin over its faces; at the depths here the
  contact over the faces is not modelled (it would add the wedge's angle as a
  parameter), and the line load is the limit of a narrow contact;
* at the wall, ``W(L) = 0``;
* at the wall, clamped, ``W'(L) = 0`` (the default), or pinned, ``W''(L) = 0``.
  The wall is where the deformation has died out; beyond it the skin lies at rest,
  flat.  A skin that bends keeps its slope continuous, and the skin beyond the
  wall has zero slope, so the clamped condition is the one that matches a skin
  continuing at rest past L.  The pinned wall (no moment, slope free) is the
  paper's own channel wall with a plate in place of the membrane; it is offered
  to show how much the choice matters;
* volume, ``integral_0^L W dX = 0`` (eq. 2): the core is incompressible.

As ``l_b -> 0`` the exponential terms shrink to boundary layers of width ``l_b``
at the wedge and the wall, and the profile tends to the paper's parabola (eq. 19)
with an error of order ``W0 l_b / L``.  The load needed per unit tension,
``F / N = 2 l_b**2 |W'''(0+)|``, tends to the membrane's ``2 sin(theta0) ~ 8 W0 / L``
(eq. 3 in the small-slope limit).  The shape depends on W0, L and ``l_b`` only, not
on N or D themselves: a profile identifies ``L`` and ``l_b``.

References
----------
Srinivasan, M. A. (1989), J. Biomech. 22(4):343-349: the waterbed (eqs 2-9, 19).
Timoshenko, S. P. and Gere, J. M. (1961), Theory of Elastic Stability, ch. 1: the
beam-column equation ``D w'''' - N w'' = q``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "WALLS",
    "bending_coefficients",
    "bending_deflection_mm",
    "bending_load_per_tension",
]

#: The wall conditions the model offers, the default first.
WALLS = ("clamped", "pinned")


def _check_wall(wall):
    if wall not in WALLS:
        raise ValueError(f"wall must be one of {', '.join(WALLS)}, got {wall!r}")


def bending_coefficients(kappa, wall="clamped"):
    """Coefficients of the bending-skin profile for ``kappa = L / l_b``.

    The profile is ``W / W0 = a + b s + c s**2 + e exp(-kappa s) + g exp(-kappa (1 - s))``
    with ``s = X / L`` (see the module's notes for the five conditions that fix them).

    Parameters
    ----------
    kappa : float or array_like
        Half-width over bending length, ``L / l_b`` (> 0).
    wall : {"clamped", "pinned"}
        The condition at the wall: zero slope, or zero moment.

    Returns
    -------
    numpy.ndarray
        Shape ``(*kappa.shape, 5)``: ``a, b, c, e, g``.  When ``l_b`` exceeds ``L``
        the terms cancel (the profile tends to the plate's quartic, which every term
        approximates): at ``l_b = 2 L`` the coefficients are about 6e3 and a profile
        carries a relative rounding error of about 1e-12, still far below any
        reading's.  ``2 c W0 / L**2`` is the
        curvature the core's pressure gives the skin, ``p / N``.
    """
    _check_wall(wall)
    kappa = np.asarray(kappa, dtype=float)
    k = kappa.reshape(-1)
    if np.any(~(k > 0)):
        raise ValueError("kappa = L / l_b must be > 0")
    q = np.exp(-k)
    mean_exp = -np.expm1(-k) / k  # integral_0^1 exp(-k s) ds
    one = np.ones_like(k)
    zero = np.zeros_like(k)
    # rows scaled so that every entry stays of order one whatever kappa is
    k1 = np.maximum(k, 1.0)
    rows = [
        [one, zero, zero, one, q],  # W(0) = W0
        [zero, one / k1, zero, -k / k1, k * q / k1],  # W'(0) = 0
        [one, one, one, q, one],  # W(L) = 0
    ]
    if wall == "clamped":
        rows.append([zero, one / k1, 2 * one / k1, -k * q / k1, k / k1])  # W'(L) = 0
    else:
        k2 = k1**2
        rows.append([zero, zero, 2 * one / k2, k**2 * q / k2, k**2 / k2])  # W''(L) = 0
    rows.append([one, one / 2, one / 3, mean_exp, mean_exp])  # volume
    matrix = np.moveaxis(np.array(rows), (0, 1), (1, 2))  # (n, 5, 5)
    rhs = np.zeros((k.size, 5, 1))
    rhs[:, 0, 0] = 1.0
    coefficients = np.linalg.solve(matrix, rhs)[..., 0]
    return coefficients.reshape((*kappa.shape, 5))


def bending_deflection_mm(distance_mm, depth_mm, L_mm, bending_length_mm, wall="clamped"):
    """Small-slope profile of the bending skin, W(X), zero beyond the wall.

    Parameters
    ----------
    distance_mm : array_like
        Resting horizontal distance X from the load (mm, >= 0).
    depth_mm : float or array_like
        Deflection under the load, W0 (mm).
    L_mm : float or array_like
        Half-width of the channel, L (mm, > 0).
    bending_length_mm : float or array_like
        ``l_b = sqrt(D / N)`` (mm, > 0).  Arrays of the three parameters broadcast
        against each other and against ``distance_mm`` (``L_mm[:, None]`` and
        ``distance_mm[None, :]`` give one profile per row), the coefficients being
        solved once per parameter set.
    wall : {"clamped", "pinned"}
        The condition at the wall.

    Returns
    -------
    numpy.ndarray
        Downward deflection (mm), the broadcast shape of the arguments.
    """
    L_mm = np.asarray(L_mm, dtype=float)
    s = np.asarray(distance_mm, dtype=float) / L_mm
    kappa = L_mm / np.asarray(bending_length_mm, dtype=float)
    a, b, c, e, g = np.moveaxis(bending_coefficients(kappa, wall), -1, 0)
    inside = np.clip(s, 0.0, 1.0)
    shape = (
        a
        + b * inside
        + c * inside**2
        + e * np.exp(-kappa * inside)
        + g * np.exp(-kappa * (1.0 - inside))
    )
    return np.where(s > 1.0, 0.0, depth_mm * shape)


def bending_load_per_tension(depth_mm, L_mm, bending_length_mm, wall="clamped"):
    """Wedge force per unit tension, ``F / N``, for the bending skin (dimensionless).

    The shear just beside the load carries half the force: ``F / 2 = D |W'''(0+)|``
    (the tension's share ``N W'(0)`` is zero, the slope being zero there), so
    ``F / N = 2 l_b**2 |W'''(0+)| = 2 (W0 / L) kappa |e - g exp(-kappa)|``.  As
    ``l_b -> 0`` it tends to the membrane's ``8 W0 / L``.

    Parameters
    ----------
    depth_mm, L_mm, bending_length_mm : float or array_like
        W0, L and l_b (mm).
    wall : {"clamped", "pinned"}

    Returns
    -------
    numpy.ndarray
    """
    depth_mm, L_mm, bending_length_mm = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (depth_mm, L_mm, bending_length_mm))
    )
    kappa = L_mm / bending_length_mm
    coefficients = bending_coefficients(kappa, wall)
    e, g = coefficients[..., 3], coefficients[..., 4]
    return 2.0 * (depth_mm / L_mm) * kappa * np.abs(e - g * np.exp(-kappa))
