"""Plane-strain geometry: a fingertip's section (a pad around a rigid bone), a half-space box.

The section lies in the plane of the measured profile: the wedge's edge is perpendicular to it
and long (25 mm against the fingertip's few millimetres of deformation), so plane strain along
the edge is the paper's own assumption. Coordinates: ``x`` along the resting surface away from
the wedge (mm), ``z`` upward (mm); the wedge comes down on the section's highest point, which
sits at the origin. The section is symmetric about ``x = 0`` (the wedge's axis), so the solver
meshes only ``x >= 0``.

The outer outline is an ellipse of the given width and height; the bone is a smaller ellipse on
the same axis, its top ``pad_thickness_mm`` below the skin under the wedge. Where each value
comes from is written beside it (:data:`SPECIES`): the widths are the 2003 paper's fingertip
widths; the height, the bone and the pad's thickness are stated assumptions with ranges, to be
treated as nuisances when fitting, never as facts.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

#: Points per millimetre of outline when measuring a point's depth below the skin.
_OUTLINE_SAMPLES_PER_MM = 400


@dataclass(frozen=True)
class Range:
    """A geometric value with its stated range and where both come from.

    Parameters
    ----------
    value_mm
        The default (mm).
    low_mm, high_mm
        The stated range (mm).
    source
        The source of the range, or ``"assumption: ..."`` with the reason.
    """

    value_mm: float
    low_mm: float
    high_mm: float
    source: str


@dataclass(frozen=True)
class FingerSection:
    """A fingertip's plane-strain section: an elliptic pad around a rigid elliptic bone.

    Parameters
    ----------
    width_mm
        The outline's extent along the surface (the ellipse's full horizontal axis).
    height_mm
        The outline's volar-dorsal extent (the full vertical axis).
    bone_width_mm, bone_height_mm
        The bone's full axes.
    pad_thickness_mm
        From the skin under the wedge down to the bone's top.
    dorsal_clamped
        Whether the dorsal half of the outline (below the section's mid-height) is held fixed,
        as by a nail glued to a support (assumed; the 2003 models treat the nail as rigid). If
        not, the flanks beside the bone hang free and follow the pad down.
    """

    width_mm: float
    height_mm: float
    bone_width_mm: float
    bone_height_mm: float
    pad_thickness_mm: float
    dorsal_clamped: bool = True

    def __post_init__(self):
        a, b = self.width_mm / 2, self.height_mm / 2
        if min(self.width_mm, self.height_mm, self.bone_width_mm, self.bone_height_mm) <= 0:
            raise ValueError(f"every size of the section must be positive: {self}")
        if self.pad_thickness_mm <= 0:
            raise ValueError(f"the pad must have a positive thickness: {self}")
        # the bone must lie inside the outline, with room for at least a thin layer of pad
        theta = np.linspace(0, 2 * np.pi, 721)
        bone_x, bone_z = self.bone_outline_mm(theta)
        level = (bone_x / a) ** 2 + ((bone_z + b) / b) ** 2
        if level.max() >= 0.95:
            raise ValueError(f"the bone does not fit inside the fingertip's outline: {self}")

    @property
    def bone_centre_z_mm(self) -> float:
        """The bone's centre height (mm; the skin under the wedge is at z = 0)."""
        return -self.pad_thickness_mm - self.bone_height_mm / 2

    def outer_outline_mm(self, theta):
        """Points of the skin's outline at parametric angle ``theta`` (0 under the wedge)."""
        a, b = self.width_mm / 2, self.height_mm / 2
        return a * np.sin(theta), b * np.cos(theta) - b

    def outer_normal(self, theta):
        """The outline's outward unit normal at parametric angle ``theta``."""
        a, b = self.width_mm / 2, self.height_mm / 2
        nx, nz = np.sin(theta) / a, np.cos(theta) / b
        norm = np.hypot(nx, nz)
        return nx / norm, nz / norm

    def bone_outline_mm(self, theta):
        """Points of the bone's outline at parametric angle ``theta`` (0 at its top)."""
        return (
            self.bone_width_mm / 2 * np.sin(theta),
            self.bone_centre_z_mm + self.bone_height_mm / 2 * np.cos(theta),
        )

    def outer_level(self, x_mm, z_mm):
        """The outline's implicit function: 1 on the skin, below 1 inside."""
        a, b = self.width_mm / 2, self.height_mm / 2
        return (np.asarray(x_mm) / a) ** 2 + ((np.asarray(z_mm) + b) / b) ** 2

    def bone_level(self, x_mm, z_mm):
        """The bone's implicit function: 1 on the bone, below 1 inside it."""
        return (np.asarray(x_mm) / (self.bone_width_mm / 2)) ** 2 + (
            (np.asarray(z_mm) - self.bone_centre_z_mm) / (self.bone_height_mm / 2)
        ) ** 2

    def project_to_skin(self, x_mm, z_mm):
        """Move points radially (from the outline's centre) onto the skin's outline."""
        b = self.height_mm / 2
        scale = np.sqrt(self.outer_level(x_mm, z_mm))
        return np.asarray(x_mm) / scale, (np.asarray(z_mm) + b) / scale - b

    def project_to_bone(self, x_mm, z_mm):
        """Move points radially (from the bone's centre) onto the bone's outline."""
        zc = self.bone_centre_z_mm
        scale = np.sqrt(self.bone_level(x_mm, z_mm))
        return np.asarray(x_mm) / scale, (np.asarray(z_mm) - zc) / scale + zc

    def _nearest_on_skin(self, x_mm, z_mm):
        """Each point's distance to the skin (mm) and the parametric angle of the nearest point."""
        a, b = self.width_mm / 2, self.height_mm / 2
        perimeter_mm = np.pi * (3 * (a + b) - np.sqrt((3 * a + b) * (a + 3 * b)))
        theta = np.linspace(0, 2 * np.pi, int(perimeter_mm * _OUTLINE_SAMPLES_PER_MM))
        outline = np.column_stack(self.outer_outline_mm(theta))
        distance_mm, nearest = cKDTree(outline).query(np.column_stack([x_mm, z_mm]))
        return distance_mm, theta[nearest]

    def depth_below_skin_mm(self, x_mm, z_mm):
        """Each point's distance to the skin's outline (mm), to within 1/400 mm."""
        return self._nearest_on_skin(x_mm, z_mm)[0]

    def layer_face_mm(self, theta, thickness_mm):
        """Points ``thickness_mm`` inside the skin along its normal, at parametric angle theta."""
        skin_x, skin_z = self.outer_outline_mm(theta)
        normal_x, normal_z = self.outer_normal(theta)
        return skin_x - thickness_mm * normal_x, skin_z - thickness_mm * normal_z

    def project_to_layer_face(self, x_mm, z_mm, thickness_mm):
        """Move points onto the face ``thickness_mm`` below the skin, along the skin's normal."""
        _, theta = self._nearest_on_skin(x_mm, z_mm)
        return self.layer_face_mm(theta, thickness_mm)


@dataclass(frozen=True)
class HalfSpaceBox:
    """A large box standing for a half-space: surface at z = 0, clamped far sides.

    Parameters
    ----------
    half_width_mm
        From the load's axis to the clamped side.
    depth_mm
        From the surface to the clamped bottom.
    """

    half_width_mm: float
    depth_mm: float

    def depth_below_skin_mm(self, x_mm, z_mm):
        """Each point's depth below the surface (mm)."""
        return -np.asarray(z_mm, dtype=float)


@dataclass(frozen=True)
class SpeciesGeometry:
    """One species' section, each value with its range and source."""

    width: Range
    height: Range
    bone_width: Range
    bone_height: Range
    pad_thickness: Range
    outer_layer_thickness: Range

    def section(self) -> FingerSection:
        """The section at the default values."""
        return FingerSection(
            width_mm=self.width.value_mm,
            height_mm=self.height.value_mm,
            bone_width_mm=self.bone_width.value_mm,
            bone_height_mm=self.bone_height.value_mm,
            pad_thickness_mm=self.pad_thickness.value_mm,
        )


_DANDEKAR_2003 = (
    "Dandekar, Raju and Srinivasan (2003), J. Biomech. Eng. 125:682-691: fingertip width "
    "about 8-10 mm in monkeys and 16-20 mm in humans"
)
_ASSUMED_HEIGHT = (
    "assumption: a fingertip somewhat flatter than it is wide (height 0.7-0.9 of the width); "
    "no source in this project measures it"
)
_ASSUMED_BONE = (
    "assumption: the distal phalanx's tuft about half the fingertip's width and a third of its "
    "height; the 1996 and 2003 models treat the bone as rigid, their exact sizes are not used here"
)
_ASSUMED_PAD = (
    "assumption: the volar pulp between skin and bone a quarter to a half of the fingertip's "
    "height; the profile's far field depends on it, so it is a nuisance when fitting"
)
_ASSUMED_LAYER = (
    "assumption: the stiffer outer layer (epidermis and dermis) about a tenth of the pad's "
    "thickness; it trades off against the modulus ratio, so a fit reports what is identifiable"
)

#: Per species: the section's values, each with its range and source.
SPECIES: dict[str, SpeciesGeometry] = {
    "monkey": SpeciesGeometry(
        width=Range(9.0, 8.0, 10.0, _DANDEKAR_2003),
        height=Range(7.2, 5.6, 9.0, _ASSUMED_HEIGHT),
        bone_width=Range(4.5, 3.5, 5.5, _ASSUMED_BONE),
        bone_height=Range(2.4, 1.8, 3.0, _ASSUMED_BONE),
        pad_thickness=Range(2.5, 1.8, 3.6, _ASSUMED_PAD),
        outer_layer_thickness=Range(0.4, 0.2, 0.8, _ASSUMED_LAYER),
    ),
    "human": SpeciesGeometry(
        width=Range(18.0, 16.0, 20.0, _DANDEKAR_2003),
        height=Range(14.4, 11.2, 18.0, _ASSUMED_HEIGHT),
        bone_width=Range(9.0, 7.0, 11.0, _ASSUMED_BONE),
        bone_height=Range(4.8, 3.6, 6.0, _ASSUMED_BONE),
        pad_thickness=Range(5.0, 3.6, 7.2, _ASSUMED_PAD),
        outer_layer_thickness=Range(0.8, 0.4, 1.6, _ASSUMED_LAYER),
    ),
}
