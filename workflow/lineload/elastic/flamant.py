"""Flamant's solution: a line force on an elastic half-space in plane strain.

A force P per unit length, normal to the surface of a half-space of Young's modulus E and
Poisson's ratio nu, lowers the surface at distance x by 2 (1 - nu^2) P / (pi E) ln(d / x) plus a
constant that depends on where the displacement is measured from (Johnson 1985, Contact
Mechanics, section 2.2). Only differences between two distances are free of that constant; they
are what a finite model can be checked against.
"""

from __future__ import annotations

import numpy as np


def deflection_difference_mm(near_mm, far_mm, force_per_length_N_per_mm, modulus_MPa, poisson):
    """How much deeper the surface lies at ``near_mm`` than at ``far_mm`` (mm).

    Parameters
    ----------
    near_mm, far_mm
        Distances from the load's line (mm).
    force_per_length_N_per_mm
        The line force (N/mm).
    modulus_MPa, poisson
        Young's modulus (MPa = N/mm^2) and Poisson's ratio.

    Returns
    -------
    float or ndarray
        w(near) - w(far), downward positive (mm).
    """
    scale = 2 * (1 - poisson**2) * force_per_length_N_per_mm / (np.pi * modulus_MPa)
    return scale * np.log(np.asarray(far_mm) / np.asarray(near_mm))
