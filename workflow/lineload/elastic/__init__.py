"""The layered elastic fingertip: a plane-strain finite-element model of the later literature.

Srinivasan and Dandekar (1996) and Dandekar, Raju and Srinivasan (2003) answered the paper's
question with finite elements; this wing builds their kind of model with scikit-fem so a lab can
set it beside the paper's two models. See docs/elastic-finger.md.

Modules
-------
geometry
    The fingertip's section (a pad around a rigid bone) per species, each value with its source
    or stated assumption; the half-space box of the Flamant check.
mesh
    Meshes graded toward the wedge, boundaries named.
materials
    One isotropic solid, or a stiffer outer layer over soft pulp.
wedge
    The rigid wedge's underside: rounded edge, flat faces.
solver
    Mixed (Taylor-Hood) plane-strain elasticity with the wedge in frictionless one-sided contact.
flamant
    The half-space's line-load solution the solver is checked against.
library
    The solution library: profiles over sections, layers, ratios and depths.
table
    The library table's columns, read by the fits without the solver.
"""
