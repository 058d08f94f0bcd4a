"""The wedge: a rigid body with two flat faces meeting in a rounded edge.

The paper's wedge is epoxy, its edge under 50 um wide (Methods), so the tip's radius defaults to
25 um. Its angle is not reported: the half-angle between each face and the axis is an assumption
(30 degrees), and matters only where the skin wraps onto the faces, within about a tenth of a
millimetre of the edge at 2 mm depth, inside the zone the photographs lose to glare.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Half the paper's upper bound on the edge's width (Methods: under 50 um).
TIP_RADIUS_MM = 0.025
#: Assumed: the paper does not report the wedge's angle.
HALF_ANGLE_DEG = 30.0


@dataclass(frozen=True)
class Wedge:
    """A rigid wedge pointing down, its axis at x = 0.

    Parameters
    ----------
    tip_radius_mm
        The rounded edge's radius (mm).
    half_angle_deg
        The angle between each face and the axis (degrees, 0-90).
    """

    tip_radius_mm: float = TIP_RADIUS_MM
    half_angle_deg: float = HALF_ANGLE_DEG

    def __post_init__(self):
        if not self.tip_radius_mm > 0:
            raise ValueError(f"the tip radius must be positive, not {self.tip_radius_mm} mm")
        if not 0 < self.half_angle_deg < 90:
            raise ValueError(f"the half-angle must lie in (0, 90) degrees: {self.half_angle_deg}")

    def underside_mm(self, distance_mm, depth_mm: float):
        """Height of the wedge's underside above each distance from its axis (mm).

        Parameters
        ----------
        distance_mm
            Horizontal distances from the axis (mm).
        depth_mm
            How far the edge's lowest point is below the resting skin at the axis (z = 0).

        Returns
        -------
        ndarray
            z of the underside (mm): the arc of the rounded edge, then the straight faces.
        """
        alpha = np.deg2rad(self.half_angle_deg)
        radius = self.tip_radius_mm
        distance_mm = np.abs(np.asarray(distance_mm, dtype=float))
        tangent_mm = radius * np.cos(alpha)
        on_arc = np.minimum(distance_mm, tangent_mm)
        arc = radius - np.sqrt(radius**2 - on_arc**2)
        faces = np.maximum(distance_mm - tangent_mm, 0.0) / np.tan(alpha)
        return -depth_mm + arc + faces
