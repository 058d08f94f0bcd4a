"""Plane-strain geometry: a fingertip's section (a pad around a rigid bone), a half-space box.

The section lies in the plane of the measured profile. The 1989 wedge lies across the finger,
so its edge is perpendicular to that plane and the profile runs along the finger's length: the
section is the finger's longitudinal section, cut through the wedge's middle. Plane strain
along the edge is the paper's own assumption. Coordinates: ``x`` along the resting surface
away from the wedge (mm), ``z`` upward (mm); the wedge comes down on the section's highest
point, which sits at the origin. The section is symmetric about ``x = 0`` (the wedge's axis),
so the solver meshes only ``x >= 0``.

The outer outline is an ellipse of the given length (along the finger) and height; the bone is
a smaller ellipse on the same axis, its top ``pad_thickness_mm`` below the skin under the
wedge. Where each value comes from is written beside it (:data:`SPECIES`): the fingertip's
width across the finger is the 2003 paper's (it is the wedge's loaded length, out of the
section's plane); the section's length, height, bone and pad are stated assumptions with
ranges, to be treated as nuisances when fitting, never as facts. :func:`sample_sections`
draws sections from the ranges jointly, keeping only those that can be meshed.
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
    length_mm
        The outline's extent along the finger, in the profile's plane (the ellipse's full
        horizontal axis).
    height_mm
        The outline's volar-dorsal extent (the full vertical axis).
    bone_length_mm, bone_height_mm
        The bone's full axes.
    pad_thickness_mm
        From the skin under the wedge down to the bone's top.
    dorsal_clamped
        Whether the dorsal half of the outline (below the section's mid-height) is held fixed,
        as by a nail glued to a support (assumed; the 2003 models treat the nail as rigid). If
        not, the flanks beside the bone hang free and follow the pad down.
    """

    length_mm: float
    height_mm: float
    bone_length_mm: float
    bone_height_mm: float
    pad_thickness_mm: float
    dorsal_clamped: bool = True

    def __post_init__(self):
        a, b = self.length_mm / 2, self.height_mm / 2
        if min(self.length_mm, self.height_mm, self.bone_length_mm, self.bone_height_mm) <= 0:
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
        a, b = self.length_mm / 2, self.height_mm / 2
        return a * np.sin(theta), b * np.cos(theta) - b

    def outer_normal(self, theta):
        """The outline's outward unit normal at parametric angle ``theta``."""
        a, b = self.length_mm / 2, self.height_mm / 2
        nx, nz = np.sin(theta) / a, np.cos(theta) / b
        norm = np.hypot(nx, nz)
        return nx / norm, nz / norm

    def bone_outline_mm(self, theta):
        """Points of the bone's outline at parametric angle ``theta`` (0 at its top)."""
        return (
            self.bone_length_mm / 2 * np.sin(theta),
            self.bone_centre_z_mm + self.bone_height_mm / 2 * np.cos(theta),
        )

    def outer_level(self, x_mm, z_mm):
        """The outline's implicit function: 1 on the skin, below 1 inside."""
        a, b = self.length_mm / 2, self.height_mm / 2
        return (np.asarray(x_mm) / a) ** 2 + ((np.asarray(z_mm) + b) / b) ** 2

    def bone_level(self, x_mm, z_mm):
        """The bone's implicit function: 1 on the bone, below 1 inside it."""
        return (np.asarray(x_mm) / (self.bone_length_mm / 2)) ** 2 + (
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
        a, b = self.length_mm / 2, self.height_mm / 2
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
    """One species' section, each value with its range and source.

    ``width`` is across the finger: the wedge's loaded length, which turns a force per unit
    length into a force; it is not a size of the section. The others are the section's.
    """

    width: Range
    length: Range
    height: Range
    bone_length: Range
    bone_height: Range
    pad_thickness: Range
    outer_layer_thickness: Range

    def section(self) -> FingerSection:
        """The section at the default values."""
        return FingerSection(
            length_mm=self.length.value_mm,
            height_mm=self.height.value_mm,
            bone_length_mm=self.bone_length.value_mm,
            bone_height_mm=self.bone_height.value_mm,
            pad_thickness_mm=self.pad_thickness.value_mm,
        )


#: The section's values that :func:`sample_sections` draws, in the order of its columns.
SECTION_VALUES = ("length", "height", "bone_length", "bone_height", "pad_thickness")
#: The bone's length as a share of the section's (the bone's stated range, drawn jointly).
BONE_LENGTH_SHARE = (0.4, 0.6)


_DANDEKAR_2003 = (
    "Dandekar, Raju and Srinivasan (2003), J. Biomech. Eng. 125:682-691: fingertip width "
    "about 8-10 mm in monkeys and 16-20 mm in humans (across the finger: the wedge's loaded "
    "length, not a size of the section)"
)
_ASSUMED_LENGTH = (
    "assumption: no source in this project measures the pad's extent along the finger, and "
    "the skin continues past the distal pad, so the phalanx's length does not bound it. The "
    "paper reports deformed skin out to 3-7 mm from the wedge in monkeys and 6-12 mm in "
    "humans; the range runs from a section whose half-length is the middle of those extents "
    "(its own end would confine the profile) to one whose half-length is well past their far "
    "end, wide enough to be fitted as a nuisance"
)
_ASSUMED_HEIGHT = (
    "assumption: a fingertip somewhat flatter than it is wide (height 0.7-0.9 of the width); "
    "no source in this project measures it"
)
_ASSUMED_BONE_LENGTH = (
    "assumption: the distal phalanx runs along the finger under the pad, 0.4-0.6 of the "
    "section's length; the 1996 and 2003 models treat the bone as rigid, their sizes are not "
    "used here"
)
_ASSUMED_BONE = (
    "assumption: the distal phalanx's tuft about a third of the fingertip's height; the 1996 "
    "and 2003 models treat the bone as rigid, their exact sizes are not used here"
)
_ASSUMED_PAD = (
    "assumption: the volar pulp between skin and bone a quarter to a half of the fingertip's "
    "height, and (in monkeys) thicker than the paper's deepest indentation, 2 mm, which met no "
    "bone; the profile's far field depends on it, so it is a nuisance when fitting"
)
_ASSUMED_LAYER = (
    "assumption: the stiffer outer layer (epidermis and dermis) about a tenth of the pad's "
    "thickness; it trades off against the modulus ratio, so a fit reports what is identifiable"
)

#: Per species: the section's values, each with its range and source.
SPECIES: dict[str, SpeciesGeometry] = {
    "monkey": SpeciesGeometry(
        width=Range(9.0, 8.0, 10.0, _DANDEKAR_2003),
        length=Range(16.0, 10.0, 24.0, _ASSUMED_LENGTH),
        height=Range(7.2, 5.6, 9.0, _ASSUMED_HEIGHT),
        bone_length=Range(8.0, 4.0, 14.4, _ASSUMED_BONE_LENGTH),
        bone_height=Range(2.4, 1.8, 3.0, _ASSUMED_BONE),
        pad_thickness=Range(2.8, 2.4, 3.6, _ASSUMED_PAD),
        outer_layer_thickness=Range(0.4, 0.2, 0.8, _ASSUMED_LAYER),
    ),
    "human": SpeciesGeometry(
        width=Range(18.0, 16.0, 20.0, _DANDEKAR_2003),
        length=Range(28.0, 18.0, 40.0, _ASSUMED_LENGTH),
        height=Range(14.4, 11.2, 18.0, _ASSUMED_HEIGHT),
        bone_length=Range(14.0, 7.2, 24.0, _ASSUMED_BONE_LENGTH),
        bone_height=Range(4.8, 3.6, 6.0, _ASSUMED_BONE),
        pad_thickness=Range(5.0, 3.6, 7.2, _ASSUMED_PAD),
        outer_layer_thickness=Range(0.8, 0.4, 1.6, _ASSUMED_LAYER),
    ),
}


def sample_sections(species, count, seed, fits=None):
    """Sections drawn jointly from a species' stated ranges: the default first, then a
    Latin hypercube over the ranges, keeping only sections ``fits`` accepts.

    The ranges are not independent (a thick pad in a flat finger leaves no room for the
    bone), so the draws are filtered, not a product of the ranges: the section's length,
    height, bone height and pad thickness are drawn across their ranges, the bone's length
    as a share of the section's (:data:`BONE_LENGTH_SHARE`). The draws are deterministic
    for a seed.

    Parameters
    ----------
    species : SpeciesGeometry
        The ranges.
    count : int
        How many sections (>= 1), the default section among them.
    seed : int
        Seed of the Latin hypercube.
    fits : callable, optional
        ``fits(section) -> bool``: whether a drawn section is usable (that its thickest
        outer layer meshes, say); a section the outline refuses is always left out.

    Returns
    -------
    list of FingerSection
    """
    from scipy.stats import qmc  # here: the geometry is imported where scipy.stats is not

    if count < 1:
        raise ValueError(f"need at least one section, not {count}")
    sections = [species.section()]
    sampler = qmc.LatinHypercube(d=len(SECTION_VALUES), seed=seed)
    draws = 0
    while len(sections) < count:
        if draws > 100 * count:
            raise RuntimeError(f"fewer than {count} usable sections in {draws} draws")
        for u in sampler.random(count):
            draws += 1
            values = {}
            for name, share in zip(SECTION_VALUES, u, strict=True):
                if name == "bone_length":
                    continue
                span = getattr(species, name)
                values[f"{name}_mm"] = float(span.low_mm + share * (span.high_mm - span.low_mm))
            low, high = BONE_LENGTH_SHARE
            values["bone_length_mm"] = float(values["length_mm"] * (low + u[2] * (high - low)))
            try:
                section = FingerSection(**values)
            except ValueError:
                continue
            if fits is None or fits(section):
                sections.append(section)
            if len(sections) == count:
                break
    return sections
