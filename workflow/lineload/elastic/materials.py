"""The finger's materials: one isotropic linear-elastic solid, or a stiffer outer layer over pulp.

Soft tissue is nearly incompressible, so the Poisson ratio defaults to 0.4999 (0.5 is allowed:
the mixed solver carries the pressure as its own unknown). Moduli are in MPa (N/mm^2), so with
lengths in mm a force per unit length comes out in N/mm. Only the element-wise moduli reach the
solver; which elements form the outer layer is the mesh's subdomain ``outer``, whose inner face
lies at the layer's thickness below the skin (``mesh.finger_mesh``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Soft tissue's Poisson ratio, nearly incompressible (the paper's models take 0.5).
NEARLY_INCOMPRESSIBLE = 0.4999


@dataclass(frozen=True)
class Homogeneous:
    """One isotropic solid.

    Parameters
    ----------
    modulus_MPa
        Young's modulus (MPa).
    poisson
        Poisson's ratio, 0 <= nu <= 0.5.
    """

    modulus_MPa: float
    poisson: float = NEARLY_INCOMPRESSIBLE

    def __post_init__(self):
        _check(self.modulus_MPa, self.poisson)

    @property
    def layer_thickness_mm(self) -> float | None:
        """No layer: the mesh may put its grid line anywhere."""
        return None

    def moduli_MPa(self, in_outer_layer):
        """Young's modulus of each element (MPa), wherever it lies."""
        return np.full(np.shape(in_outer_layer), self.modulus_MPa)

    def scaled(self, factor: float) -> Homogeneous:
        """The same solid with every modulus multiplied by ``factor``."""
        return Homogeneous(self.modulus_MPa * factor, self.poisson)


@dataclass(frozen=True)
class TwoLayer:
    """A stiffer outer layer of given thickness over soft pulp, bonded, same Poisson ratio.

    Parameters
    ----------
    pulp_modulus_MPa
        The inner (pulp) modulus (MPa).
    modulus_ratio
        Outer over inner modulus (>= 1 for a stiffer skin; 1 is the homogeneous solid).
    layer_thickness_mm
        The outer layer's thickness (mm).
    poisson
        Poisson's ratio of both.
    """

    pulp_modulus_MPa: float
    modulus_ratio: float
    layer_thickness_mm: float
    poisson: float = NEARLY_INCOMPRESSIBLE

    def __post_init__(self):
        _check(self.pulp_modulus_MPa, self.poisson)
        if not self.modulus_ratio > 0:
            raise ValueError(f"the modulus ratio must be positive, not {self.modulus_ratio}")
        if not self.layer_thickness_mm > 0:
            raise ValueError(f"the layer must be thicker than 0 mm, not {self.layer_thickness_mm}")

    def moduli_MPa(self, in_outer_layer):
        """Young's modulus of each element (MPa), given whether it lies in the outer layer."""
        outer = np.asarray(in_outer_layer, dtype=bool)
        return np.where(outer, self.pulp_modulus_MPa * self.modulus_ratio, self.pulp_modulus_MPa)

    def scaled(self, factor: float) -> TwoLayer:
        """The same solid with every modulus multiplied by ``factor``."""
        return TwoLayer(
            self.pulp_modulus_MPa * factor,
            self.modulus_ratio,
            self.layer_thickness_mm,
            self.poisson,
        )


def lame_MPa(modulus_MPa, poisson):
    """The shear modulus and the inverse of Lame's first parameter (0 when incompressible).

    Returns
    -------
    shear_MPa, inverse_lambda_per_MPa
        Arrays like ``modulus_MPa``.
    """
    modulus_MPa = np.asarray(modulus_MPa, dtype=float)
    shear_MPa = modulus_MPa / (2 * (1 + poisson))
    inverse_lambda = (1 + poisson) * (1 - 2 * poisson) / (modulus_MPa * poisson)
    return shear_MPa, inverse_lambda


def _check(modulus_MPa, poisson):
    if not modulus_MPa > 0:
        raise ValueError(f"a Young's modulus must be positive, not {modulus_MPa} MPa")
    if not 0 < poisson <= 0.5:
        raise ValueError(f"Poisson's ratio must lie in (0, 0.5], not {poisson}")
