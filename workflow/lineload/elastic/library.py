"""The solution library: the finger's surface profiles over a grid of its unknowns.

A profile's shape does not depend on the modulus (a depth-driven wedge, no pre-stress: the
solver's tests), so the grid has no modulus axis: per species, for each section drawn jointly
from the stated ranges (:func:`lineload.elastic.geometry.sample_sections`), each outer-layer
thickness across its range and each modulus ratio on a log grid (1 is the homogeneous finger),
the wedge is pushed to each depth on one factorisation (:func:`lineload.elastic.solver.
solve_depths`) and the deflection read on a fixed grid of distances, log-spaced so that linear
interpolation in ``ln x`` is accurate near the wedge, where the profile bends most. The force
per unit length per unit pulp modulus (mm) comes with each profile: a recorded force then fixes
the modulus.

One row per (species, section, thickness, ratio, depth): the section's sizes, the force, then
the deflections, columns ``deflection_at_<x>_mm`` (:mod:`lineload.elastic.table`, which the
fits read without importing the solver). :func:`library_rows` builds a species' rows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lineload.elastic import materials, solver
from lineload.elastic import mesh as meshing
from lineload.elastic.geometry import SPECIES, sample_sections
from lineload.elastic.table import (
    DEFLECTION_DECIMALS,
    KEY_COLUMNS,
    SIZE_DECIMALS,
    column_of,
    grid_distances_mm,
    library_columns,
)
from lineload.elastic.wedge import Wedge

__all__ = [
    "KEY_COLUMNS",
    "LibraryGrid",
    "grid_distances_mm",
    "library_columns",
    "library_rows",
    "library_sections",
]


@dataclass(frozen=True)
class LibraryGrid:
    """The library's grid (the configuration's ``elastic`` keys).

    Attributes
    ----------
    depths_mm : tuple of float
        The wedge's depths (mm).
    ratio_max : float
        The stiffest outer layer, as a multiple of the pulp's modulus (ratios run from 1).
    ratios : int
        Modulus ratios, log-spaced from 1 to ``ratio_max``.
    thicknesses : int
        Outer-layer thicknesses, log-spaced across each species' stated range.
    sections : int
        Sections per species drawn from the ranges, the default one first.
    seed : int
        Seed of the sections' draw.
    first_mm, last_mm : float
        The distance grid's ends (mm).
    distances : int
        Distances, log-spaced between the ends.
    grade : float
        The mesh's grade (:func:`lineload.elastic.mesh.graded`).
    """

    depths_mm: tuple
    ratio_max: float
    ratios: int
    thicknesses: int
    sections: int
    seed: int
    first_mm: float
    last_mm: float
    distances: int
    grade: float

    @classmethod
    def from_config(cls, elastic):
        """The grid from the configuration's ``elastic`` mapping (other keys ignored)."""
        return cls(
            depths_mm=tuple(float(d) for d in elastic["depths_mm"]),
            ratio_max=float(elastic["ratio_max"]),
            ratios=int(elastic["ratios"]),
            thicknesses=int(elastic["thicknesses"]),
            sections=int(elastic["sections"]),
            seed=int(elastic["section_seed"]),
            first_mm=float(elastic["first_distance_mm"]),
            last_mm=float(elastic["last_distance_mm"]),
            distances=int(elastic["distances"]),
            grade=float(elastic["grade"]),
        )

    def modulus_ratios(self):
        """The ratios, 1 (homogeneous) to ``ratio_max``, log-spaced."""
        return np.geomspace(1.0, self.ratio_max, self.ratios)

    def layer_thicknesses_mm(self, species):
        """A species' outer-layer thicknesses, log-spaced across its stated range (mm)."""
        span = SPECIES[species].outer_layer_thickness
        if self.thicknesses == 1:
            return np.array([span.value_mm])
        return np.round(np.geomspace(span.low_mm, span.high_mm, self.thicknesses), SIZE_DECIMALS)

    def distances_mm(self):
        """The distance grid (mm), rounded as its column names write it."""
        return np.round(np.geomspace(self.first_mm, self.last_mm, self.distances), SIZE_DECIMALS)


def library_sections(species, grid):
    """The sections of a species the library uses: those whose thickest layer meshes and
    whose pad is thicker than the deepest depth (the wedge must not reach the bone)."""
    thickest_mm = grid.layer_thicknesses_mm(species).max()
    deepest_mm = max(grid.depths_mm)

    def usable(section):
        if not section.pad_thickness_mm > deepest_mm:
            return False
        try:
            meshing.coarse_finger_mesh(section, thickest_mm)
        except ValueError:
            return False
        return True

    return sample_sections(SPECIES[species], grid.sections, grid.seed, usable)


def library_rows(species, grid, sections=None, thicknesses_mm=None, ratios=None, progress=None):
    """A species' library rows: every section, thickness, ratio and depth of the grid.

    Parameters
    ----------
    species : str
        A key of :data:`lineload.elastic.geometry.SPECIES`.
    grid : LibraryGrid
    sections, thicknesses_mm, ratios : sequence, optional
        Indices into the grid's sections, or values of its thicknesses and ratios, to build
        only a slice (the regeneration test); all of them by default.
    progress : callable, optional
        Called with a line of text after each factorisation.

    Returns
    -------
    list of dict
        Rows with the columns of :func:`library_columns`.
    """
    wedge = Wedge()
    finest_mm = solver.FINEST_PER_TIP_RADIUS * wedge.tip_radius_mm
    distances_mm = grid.distances_mm()
    all_sections = library_sections(species, grid)
    chosen = range(len(all_sections)) if sections is None else sections
    thicknesses_mm = (
        grid.layer_thicknesses_mm(species) if thicknesses_mm is None else thicknesses_mm
    )
    ratios = grid.modulus_ratios() if ratios is None else ratios
    rows = []
    for index in chosen:
        section = all_sections[index]
        sizes = {
            "length_mm": section.length_mm,
            "height_mm": section.height_mm,
            "bone_length_mm": section.bone_length_mm,
            "bone_height_mm": section.bone_height_mm,
            "pad_thickness_mm": section.pad_thickness_mm,
        }
        for thickness_mm in thicknesses_mm:
            mesh = meshing.finger_mesh(section, float(thickness_mm), finest_mm, grid.grade)
            for ratio in ratios:
                material = materials.TwoLayer(1.0, float(ratio), float(thickness_mm))
                series = solver.solve_depths(mesh, section, material, wedge, grid.depths_mm)
                for depth_mm, solution in zip(grid.depths_mm, series, strict=True):
                    deflection_mm = solution.deflection_at_mm(distances_mm)
                    rows.append(
                        {
                            "species": species,
                            "section": index,
                            **{k: round(v, SIZE_DECIMALS) for k, v in sizes.items()},
                            "layer_thickness_mm": round(float(thickness_mm), SIZE_DECIMALS),
                            "modulus_ratio": round(float(ratio), 6),
                            "depth_mm": depth_mm,
                            "force_per_length_per_pulp_modulus_mm": float(
                                f"{solution.force_per_length_N_per_mm:.6g}"
                            ),
                            "elements": solution.elements,
                            **{
                                column_of(x): round(float(w), DEFLECTION_DECIMALS)
                                for x, w in zip(distances_mm, deflection_mm, strict=True)
                            },
                        }
                    )
                if progress is not None:
                    progress(
                        f"{species} section {index} layer {thickness_mm:g} mm ratio {ratio:.3g}: "
                        f"{mesh.t.shape[1]} triangles"
                    )
    return rows
