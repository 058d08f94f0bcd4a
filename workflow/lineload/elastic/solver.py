"""Plane-strain linear elasticity with a rigid wedge in one-sided frictionless contact.

The solid is nearly incompressible, where displacement-only elements lock (they stiffen as nu
approaches 1/2). The default formulation is mixed: quadratic displacements and a continuous
linear pressure (the Taylor-Hood pair, stable for Stokes flow and so for the incompressible
limit), with the pressure p = lambda div u carried as an unknown and the term p q / lambda, which
vanishes at nu = 1/2; the pair's stability keeps the system regular then too, since part of the
boundary (the skin) is free. The displacement-only formulation (quadratic elements) stays
available to show the difference.

The wedge is driven by its depth. Contact is one-sided and frictionless, on the nodes of the
skin: a node may not rise above the wedge's underside (u_z <= gap, the gap measured vertically
at the node's resting distance: the small-displacement approximation), and the wedge may only
push. The system is factorised once; its inverse at the candidate nodes (those the wedge's
underside comes near) is the skin's compliance there, and an active-set iteration on that small
matrix finds which nodes touch: a touching node whose force would pull is released, a free node
that passes through the wedge is made to touch, until the set stops changing (the linear
complementarity problem solved exactly, no penalty to tune). Afterwards every node of the skin
is checked against the wedge, candidate or not. The touching nodes' forces sum to the force per
unit length.

Boundary conditions: the bone and, by default, the dorsal half of the outline (or the box's far
sides) clamped; u_x = 0 on the axis of symmetry; the rest of the skin free.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import bmat
from scipy.sparse.linalg import splu
from skfem import (
    Basis,
    BilinearForm,
    ElementTriP0,
    ElementTriP1,
    ElementTriP2,
    ElementVector,
    asm,
)
from skfem.helpers import ddot, div, sym_grad

from lineload.elastic import materials
from lineload.elastic import mesh as meshing
from lineload.elastic.geometry import FingerSection, HalfSpaceBox
from lineload.elastic.wedge import Wedge

#: The formulations: Taylor-Hood (mixed) or displacement-only quadratic elements.
FORMULATIONS = ("mixed", "displacement")
#: Quadrature exact for the products of quadratic gradients on straight triangles.
_INTORDER = 4
#: The active-set iteration gives up after this many passes.
_MAX_ACTIVE_SET_PASSES = 60
#: Candidate contact nodes: the wedge's underside within this fraction of the depth above them.
_CANDIDATE_MARGIN = 0.1
#: How far the mesh's layer may be from the material's thickness (the depth's resolution, mm).
_LAYER_TOLERANCE_MM = 0.005
#: The smallest mesh side at the wedge, as a fraction of the tip's radius.
FINEST_PER_TIP_RADIUS = 0.4
#: Where a homogeneous finger's mesh has its grid line below the skin, unless told (mm).
_HOMOGENEOUS_GRID_LINE_MM = 1.0
#: The default grade: the longest side per unit distance from the wedge.
GRADE = 0.2


@dataclass(frozen=True)
class ContactSolution:
    """What the wedge does to the skin.

    Attributes
    ----------
    distance_mm
        The skin's nodes on the loaded side, by resting horizontal distance from the wedge (mm).
    deflection_mm
        Their vertical displacement, downward positive (mm).
    force_per_length_N_per_mm
        The wedge's force per unit length of its edge, both sides of the axis (N/mm).
    contact_half_width_mm
        The farthest touching node's distance from the axis (mm).
    passes
        Active-set passes taken.
    elements
        Triangles in the (half) mesh.
    """

    distance_mm: np.ndarray
    deflection_mm: np.ndarray
    force_per_length_N_per_mm: float
    contact_half_width_mm: float
    passes: int
    elements: int

    def deflection_at_mm(self, distance_mm):
        """The finite-element deflection at the given distances (mm), exactly.

        The skin's nodes alternate: a triangle's corner, the midpoint of its straight side,
        the next corner. Along a side the quadratic element's trace is the parabola through
        those three, and the distance is linear along it, so the parabola in distance is the
        solution itself, not an interpolation of it (a straight line between the nodes would
        add an error of w'' h^2 / 8, about 1 um at 1 mm from the wedge on the default mesh).
        """
        distance_mm = np.asarray(distance_mm, dtype=float)
        corners_mm = self.distance_mm[::2]
        if np.any(distance_mm < 0) or np.any(distance_mm > corners_mm[-1]):
            raise ValueError(
                f"distances must lie in [0, {corners_mm[-1]:.3f}] mm, the profile's extent"
            )
        side = np.clip(np.searchsorted(corners_mm, distance_mm) - 1, 0, corners_mm.size - 2)
        corner_mm, middle_mm, next_mm = (self.distance_mm[2 * side + k] for k in range(3))
        w0, w1, w2 = (self.deflection_mm[2 * side + k] for k in range(3))
        t = distance_mm
        return (
            w0 * (t - middle_mm) * (t - next_mm) / ((corner_mm - middle_mm) * (corner_mm - next_mm))
            + w1
            * (t - corner_mm)
            * (t - next_mm)
            / ((middle_mm - corner_mm) * (middle_mm - next_mm))
            + w2
            * (t - corner_mm)
            * (t - middle_mm)
            / ((next_mm - corner_mm) * (next_mm - middle_mm))
        )


@BilinearForm
def _shear(u, v, w):
    return 2 * w.shear * ddot(sym_grad(u), sym_grad(v))


@BilinearForm
def _dilatation(u, v, w):
    return w.lam * div(u) * div(v)


@BilinearForm
def _coupling(u, q, w):
    return q * div(u)


@BilinearForm
def _compliance(p, q, w):
    return w.inverse_lambda * p * q


def _stiffness(mesh, moduli_MPa, poisson, formulation):
    """The system matrix and the displacement basis."""
    if formulation not in FORMULATIONS:
        raise ValueError(f"unknown formulation {formulation!r}; known: {FORMULATIONS}")
    displacement = Basis(mesh, ElementVector(ElementTriP2()), intorder=_INTORDER)
    constant = displacement.with_element(ElementTriP0())
    shear_MPa, inverse_lambda = materials.lame_MPa(moduli_MPa, poisson)
    shear_matrix = asm(_shear, displacement, shear=constant.interpolate(shear_MPa))
    if formulation == "displacement":
        if poisson >= 0.5:
            raise ValueError("the displacement formulation needs nu < 0.5; use 'mixed'")
        dilatation = asm(_dilatation, displacement, lam=constant.interpolate(1 / inverse_lambda))
        return (shear_matrix + dilatation).tocsr(), displacement
    pressure = Basis(mesh, ElementTriP1(), intorder=_INTORDER)
    coupling = asm(_coupling, displacement, pressure)
    compliance = asm(
        _compliance,
        pressure,
        inverse_lambda=pressure.with_element(ElementTriP0()).interpolate(inverse_lambda),
    )
    return bmat([[shear_matrix, coupling.T], [coupling, -compliance]], "csr"), displacement


def _outer_layer(mesh, geometry, material):
    """Which triangles form the outer layer; checks the mesh was made for this layer."""
    outer = np.zeros(mesh.t.shape[1], dtype=bool)
    if material.layer_thickness_mm is None:
        return outer
    if mesh.subdomains is None or "outer" not in mesh.subdomains:
        raise ValueError("a two-layer material needs a mesh with an outer layer (finger_mesh)")
    outer[mesh.subdomains["outer"]] = True
    deepest_mm = geometry.depth_below_skin_mm(*mesh.p[:, np.unique(mesh.t[:, outer])]).max()
    if abs(deepest_mm - material.layer_thickness_mm) > _LAYER_TOLERANCE_MM:
        raise ValueError(
            f"the mesh's outer layer is {deepest_mm:.3f} mm thick, the material's "
            f"{material.layer_thickness_mm} mm: mesh it with the material's thickness"
        )
    return outer


def _component_dofs(dofs, component):
    return np.concatenate([dofs.nodal[component], dofs.facet[component]])


def solve_contact(mesh, geometry, material, wedge: Wedge, depth_mm: float, formulation="mixed"):
    """Push the wedge ``depth_mm`` into the skin and solve for the deflection and the force.

    Parameters
    ----------
    mesh
        A half mesh with boundaries ``surface``, ``symmetry`` and ``clamped``
        (:func:`lineload.elastic.mesh.finger_mesh` or ``box_mesh``).
    geometry
        The :class:`FingerSection` or :class:`HalfSpaceBox` the mesh was made from.
    material
        :class:`~lineload.elastic.materials.Homogeneous` or ``TwoLayer``.
    wedge
        The rigid wedge.
    depth_mm
        How far the wedge's edge goes below the resting skin (mm, > 0).
    formulation
        ``"mixed"`` (Taylor-Hood, any nu <= 1/2) or ``"displacement"`` (nu < 1/2).

    Returns
    -------
    ContactSolution
    """
    return solve_depths(mesh, geometry, material, wedge, [depth_mm], formulation)[0]


def solve_depths(mesh, geometry, material, wedge: Wedge, depths_mm, formulation="mixed"):
    """Push the wedge to each depth in turn, factorising the system once for all of them.

    The system and the skin's compliance at the candidate nodes do not depend on the depth, so
    a series of depths (as in a trial series, or a library) costs one factorisation; the
    candidates are those of the deepest, which include every shallower depth's.

    Parameters
    ----------
    mesh, geometry, material, wedge, formulation
        As for :func:`solve_contact`.
    depths_mm
        The depths (mm, each > 0).

    Returns
    -------
    list of ContactSolution
        One per depth, in the order given.
    """
    depths_mm = np.asarray(depths_mm, dtype=float).ravel()
    if depths_mm.size == 0 or not np.all(depths_mm > 0):
        raise ValueError(f"the wedge's depths must be positive, not {depths_mm.tolist()} mm")
    moduli_MPa = material.moduli_MPa(_outer_layer(mesh, geometry, material))
    system, basis = _stiffness(mesh, moduli_MPa, material.poisson, formulation)
    clamped = basis.get_dofs("clamped").all()
    axis = _component_dofs(basis.get_dofs("symmetry"), "u^1")
    skin = _component_dofs(basis.get_dofs("surface"), "u^2")
    skin_x, skin_z = basis.doflocs[:, skin]
    # a node can touch only where the wedge's underside reaches below its resting height
    # (the skin beside a line load goes down, not up); the margin leaves room for a bulge
    deepest_mm = depths_mm.max()
    candidate = wedge.underside_mm(skin_x, deepest_mm) - skin_z < _CANDIDATE_MARGIN * deepest_mm
    touchable, touch_x = skin[candidate], skin_x[candidate]
    free = np.setdiff1d(np.arange(system.shape[0]), np.union1d(clamped, axis))
    if np.intersect1d(free, touchable).size != touchable.size:
        raise ValueError("a node of the skin under the wedge is clamped: is the mesh too coarse?")
    factor = splu(system[free][:, free].tocsc())
    # the skin's compliance at the candidate nodes: their displacement under unit forces there
    unit_forces = np.zeros((free.size, touchable.size))
    unit_forces[np.searchsorted(free, touchable), np.arange(touchable.size)] = 1.0
    response = factor.solve(unit_forces)
    compliance = response[np.searchsorted(free, touchable)]
    loaded = _loaded_side(geometry, skin_z)
    order = np.argsort(skin_x[loaded])
    corner = (np.arange(skin.size) < basis.get_dofs("surface").nodal["u^2"].size)[loaded][order]
    if not (corner[::2].all() and not corner[1::2].any()):
        raise RuntimeError("the skin's nodes do not alternate corner, midpoint: is x monotone?")
    solutions = []
    for depth_mm in depths_mm:
        gap_all_mm = wedge.underside_mm(skin_x, depth_mm) - skin_z
        push, active, passes = _active_set(compliance, gap_all_mm[candidate], depth_mm)
        solution = np.zeros(system.shape[0])
        solution[free] = -response[:, active] @ push[active]
        overlap_mm = solution[skin] - gap_all_mm
        if overlap_mm.max() > 1e-6 * depth_mm:
            raise RuntimeError(
                f"the skin passes {overlap_mm.max():.2g} mm into the wedge at "
                f"{skin_x[np.argmax(overlap_mm)]:.3f} mm from it, outside the nodes taken as "
                "candidates for contact: widen the candidates' margin"
            )
        solutions.append(
            ContactSolution(
                distance_mm=skin_x[loaded][order],
                deflection_mm=-solution[skin[loaded]][order],
                force_per_length_N_per_mm=float(2 * push.sum()),
                contact_half_width_mm=float(touch_x[active].max(initial=0.0)),
                passes=passes,
                elements=mesh.t.shape[1],
            )
        )
    return solutions


def _active_set(compliance, gap_mm, depth_mm):
    """The wedge's nodal pushes (>= 0) that keep every candidate node at or below the wedge.

    Parameters
    ----------
    compliance
        Upward displacement of each candidate node per unit upward force at each (mm/N per mm).
    gap_mm
        How far each node may rise before it meets the wedge (negative: it must go down).
    depth_mm
        The wedge's depth, the scale of the tolerance.

    Returns
    -------
    push, active, passes
        The downward nodal forces (N/mm, zero where free), the touching nodes, passes taken.
    """
    tolerance_mm = 1e-9 * depth_mm
    active = gap_mm < 0
    push = np.zeros(gap_mm.size)
    for passes in range(1, _MAX_ACTIVE_SET_PASSES + 1):
        push = np.zeros(gap_mm.size)
        if active.any():
            # touching nodes sit on the wedge: -C_aa push_a = gap_a
            push[active] = np.linalg.solve(compliance[np.ix_(active, active)], -gap_mm[active])
        rise_mm = -compliance[:, active] @ push[active]
        scale = max(np.abs(push).max(initial=0.0), 1e-300)
        keeps = active & (push >= -1e-10 * scale)
        enters = ~active & (rise_mm > gap_mm + tolerance_mm)
        updated = keeps | enters
        if np.array_equal(updated, active):
            return push, active, passes
        active = updated
    raise RuntimeError(
        f"the contact did not settle in {_MAX_ACTIVE_SET_PASSES} active-set passes "
        f"(depth {depth_mm} mm)"
    )


def _loaded_side(geometry, skin_z_mm):
    """Which skin nodes belong to the profile: the upper half of the finger, the box's top."""
    if isinstance(geometry, HalfSpaceBox):
        return np.ones(np.shape(skin_z_mm), dtype=bool)
    return np.asarray(skin_z_mm) > -geometry.height_mm / 2


def solve_finger(
    section: FingerSection,
    material,
    depth_mm: float,
    wedge: Wedge | None = None,
    grade: float = GRADE,
    formulation: str = "mixed",
    grid_line_mm: float | None = None,
):
    """Mesh the finger's section and push the wedge in: one call, defaults stated.

    Parameters
    ----------
    section, material, depth_mm, wedge, formulation
        As for :func:`solve_contact` (``wedge`` defaults to :class:`Wedge`'s defaults).
    grade
        The mesh's grade (:func:`lineload.elastic.mesh.graded`).
    grid_line_mm
        The depth of the mesh's grid line below the skin: the two-layer material's thickness
        (and only that for it), 1 mm by default for a homogeneous finger. Give a homogeneous
        finger the layered one's thickness to mesh the two alike.

    Returns
    -------
    ContactSolution
    """
    if not depth_mm < section.pad_thickness_mm:
        raise ValueError(
            f"a wedge {depth_mm} mm deep would reach the bone {section.pad_thickness_mm} mm "
            "below the skin"
        )
    wedge = Wedge() if wedge is None else wedge
    if grid_line_mm is None:
        grid_line_mm = material.layer_thickness_mm or _HOMOGENEOUS_GRID_LINE_MM
    mesh = meshing.finger_mesh(
        section, grid_line_mm, FINEST_PER_TIP_RADIUS * wedge.tip_radius_mm, grade
    )
    return solve_contact(mesh, section, material, wedge, depth_mm, formulation)


def solve_half_space(
    box: HalfSpaceBox,
    material,
    depth_mm: float,
    wedge: Wedge | None = None,
    grade: float = GRADE,
    formulation: str = "mixed",
):
    """Mesh the box and push the wedge in (the Flamant check's model)."""
    wedge = Wedge() if wedge is None else wedge
    mesh = meshing.box_mesh(box, FINEST_PER_TIP_RADIUS * wedge.tip_radius_mm, grade)
    return solve_contact(mesh, box, material, wedge, depth_mm, formulation)
