"""Meshes graded toward the wedge: triangles refined until each is small beside its distance.

The line load's field is log-singular, so a uniform mesh wastes elements far away and misses the
contact near the wedge. Each mesh starts from a coarse structured one and is refined (scikit-fem's
conforming red-green-blue refinement) until every triangle's longest side is at most
``grade`` times its distance from the wedge's tip, and never needs to be smaller than
``finest_mm`` (a fraction of the tip's radius). After each refinement the new nodes on a curved
outline are moved onto it, one level at a time, so no triangle turns over.

Boundaries are named for the solver: ``surface`` (the free skin, where the wedge may touch),
``symmetry`` (the wedge's axis, x = 0), ``clamped`` (the bone and, if the section says so, the
dorsal half of the outline; the box's far sides). The finger's triangles between the skin and
the outer layer's inner face form the subdomain ``outer``, kept through every refinement; the
face's new nodes move onto it like the skin's, so the layer keeps its thickness exactly.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from skfem import MeshTri

from lineload.elastic.geometry import FingerSection, HalfSpaceBox

#: Coarse stations of the finger's outline in the half section (0 to pi).
_OUTLINE_STATIONS = 25
#: Coarse stations from the outer layer's inner face down to the bone.
_PULP_STATIONS = 6
#: Coarse stations along each side of the box.
_BOX_STATIONS = 5
#: A node this close to x = 0 is on the axis of symmetry (mm).
_ON_AXIS_MM = 1e-12
#: The refinement stops after this many passes whatever the criterion says.
_MAX_PASSES = 40


def _tensor_triangles(points_x, points_z):
    """Triangulate a structured grid of points given as (n_i, n_j) arrays."""
    n_i, n_j = points_x.shape
    index = np.arange(n_i * n_j).reshape(n_i, n_j)
    a, b = index[:-1, :-1].ravel(), index[1:, :-1].ravel()
    c, d = index[1:, 1:].ravel(), index[:-1, 1:].ravel()
    triangles = np.hstack([np.vstack([a, b, c]), np.vstack([a, c, d])])
    return MeshTri(np.vstack([points_x.ravel(), points_z.ravel()]), triangles)


def coarse_finger_mesh(section: FingerSection, layer_thickness_mm: float) -> MeshTri:
    """A structured half section whose grid lines follow the outer layer's inner face.

    Parameters
    ----------
    section
        The fingertip's section.
    layer_thickness_mm
        The outer layer's thickness: a grid line runs at this depth below the skin (a
        homogeneous finger meshed with the same value differs from the layered one only in
        its moduli).

    Returns
    -------
    MeshTri
        The coarse mesh of ``x >= 0``.
    """
    theta = np.linspace(0, np.pi, _OUTLINE_STATIONS)
    skin_x, skin_z = section.outer_outline_mm(theta)
    face_x, face_z = section.layer_face_mm(theta, layer_thickness_mm)
    bone_x, bone_z = section.bone_outline_mm(theta)
    if np.any(section.bone_level(face_x, face_z) <= 1.0) or np.any(face_x < -1e-12):
        raise ValueError(
            f"an outer layer {layer_thickness_mm} mm thick does not fit above the bone of {section}"
        )
    in_layer = np.linspace(0, 1, 3)[:, None]
    in_pulp = np.linspace(0, 1, _PULP_STATIONS)[1:, None]
    points_x = np.vstack(
        [
            skin_x + in_layer * (face_x - skin_x),
            face_x + in_pulp * (bone_x - face_x),
        ]
    )
    points_z = np.vstack(
        [
            skin_z + in_layer * (face_z - skin_z),
            face_z + in_pulp * (bone_z - face_z),
        ]
    )
    points_x[:, 0] = 0.0
    points_x[:, -1] = 0.0
    mesh = _tensor_triangles(points_x.T, points_z.T)
    # the triangles of the first two bands below the skin: the outer layer
    bands = points_x.shape[0] - 1
    quad = np.arange(mesh.t.shape[1] // 2)
    outer_quads = quad[quad % bands < in_layer.size - 1]
    outer = np.concatenate([outer_quads, outer_quads + quad.size])
    return replace(mesh, _subdomains={"outer": np.sort(outer)})


def coarse_box_mesh(box: HalfSpaceBox) -> MeshTri:
    """A uniform structured half box; the refinement grades it toward the load."""
    x = np.linspace(0.0, box.half_width_mm, _BOX_STATIONS)
    z = np.linspace(0.0, -box.depth_mm, _BOX_STATIONS)
    grid_x, grid_z = np.meshgrid(x, z, indexing="ij")
    return _tensor_triangles(grid_x, grid_z)


def _longest_side_mm(mesh: MeshTri):
    p = mesh.p[:, mesh.t]
    sides = [np.hypot(*(p[:, i] - p[:, (i + 1) % 3])) for i in range(3)]
    return np.max(sides, axis=0)


def layer_face_nodes(mesh: MeshTri):
    """The nodes shared by the outer layer's triangles and the pulp's."""
    outer = np.zeros(mesh.t.shape[1], dtype=bool)
    outer[mesh.subdomains["outer"]] = True
    return np.intersect1d(mesh.t[:, outer], mesh.t[:, ~outer])


def _snap_to_outlines(mesh: MeshTri, section: FingerSection, layer_thickness_mm) -> MeshTri:
    """Move boundary nodes onto the nearer outline (skin or bone), face nodes onto the face.

    Nodes on the axis stay on it: the face's two ends there keep x = 0 exactly.
    """
    p = mesh.p.copy()
    face = layer_face_nodes(mesh)
    p[0, face], p[1, face] = section.project_to_layer_face(*mesh.p[:, face], layer_thickness_mm)
    p[0, face[mesh.p[0, face] <= _ON_AXIS_MM]] = 0.0
    nodes = np.setdiff1d(mesh.boundary_nodes(), face)
    x, z = mesh.p[:, nodes]
    off_axis = x > _ON_AXIS_MM
    nodes, x, z = nodes[off_axis], x[off_axis], z[off_axis]
    on_skin = np.abs(section.outer_level(x, z) - 1) < np.abs(section.bone_level(x, z) - 1)
    p[0, nodes[on_skin]], p[1, nodes[on_skin]] = section.project_to_skin(x[on_skin], z[on_skin])
    p[0, nodes[~on_skin]], p[1, nodes[~on_skin]] = section.project_to_bone(x[~on_skin], z[~on_skin])
    return replace(mesh, doflocs=p)


def graded(mesh: MeshTri, finest_mm: float, grade: float, snap=None) -> MeshTri:
    """Refine until every triangle's longest side is <= max(finest_mm, grade * distance).

    Parameters
    ----------
    mesh
        The coarse mesh.
    finest_mm
        The smallest side needed (mm), at the wedge's tip.
    grade
        The largest side per unit distance from the tip (dimensionless, 0.05-0.5).
    snap
        A function moving a refined mesh's new nodes onto the curved outlines they belong to;
        ``None`` for the box, whose outline is straight.

    Returns
    -------
    MeshTri
        The graded mesh.
    """
    if not finest_mm > 0 or not 0.05 <= grade <= 10:
        raise ValueError(
            f"the finest side must be positive ({finest_mm} mm), the grade in [0.05, 10] ({grade})"
        )
    for _ in range(_MAX_PASSES):
        centroid = mesh.p[:, mesh.t].mean(axis=1)
        distance_mm = np.hypot(*centroid)
        marked = np.flatnonzero(_longest_side_mm(mesh) > np.maximum(finest_mm, grade * distance_mm))
        if marked.size == 0:
            return mesh
        mesh = mesh.refined(marked)
        if snap is not None:
            mesh = snap(mesh)
    raise RuntimeError(f"the mesh is still too coarse after {_MAX_PASSES} refinements")


def named_boundaries(mesh: MeshTri, geometry) -> MeshTri:
    """Name the boundary facets ``surface``, ``symmetry`` and ``clamped``."""
    facets = mesh.boundary_facets()
    mid_x, mid_z = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
    on_axis = mid_x < 1e-9
    if isinstance(geometry, HalfSpaceBox):
        on_surface = (mid_z > -1e-9) & ~on_axis
    else:
        on_surface = ~on_axis & (
            np.abs(geometry.outer_level(mid_x, mid_z) - 1)
            < np.abs(geometry.bone_level(mid_x, mid_z) - 1)
        )
        if geometry.dorsal_clamped:
            on_surface &= mid_z > -geometry.height_mm / 2
    return mesh.with_boundaries(
        {
            "surface": facets[on_surface],
            "symmetry": facets[on_axis],
            "clamped": facets[~on_surface & ~on_axis],
        }
    )


def finger_mesh(section, layer_thickness_mm, finest_mm, grade) -> MeshTri:
    """The finger's half section, graded toward the wedge, boundaries named, layer marked."""
    mesh = graded(
        coarse_finger_mesh(section, layer_thickness_mm),
        finest_mm,
        grade,
        lambda refined: _snap_to_outlines(refined, section, layer_thickness_mm),
    )
    return named_boundaries(mesh, section)


def box_mesh(box, finest_mm, grade) -> MeshTri:
    """The half-space box, graded toward the load, boundaries named."""
    return named_boundaries(graded(coarse_box_mesh(box), finest_mm, grade), box)
