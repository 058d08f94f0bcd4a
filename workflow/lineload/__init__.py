"""Line-load fingertip deflection: the science behind the workflow, without Snakemake.

A package behind the workflow that reproduces Srinivasan (1989), "Surface deflection
of primate fingertip under line load".  Every function works on numpy arrays or pandas
DataFrames and carries its units in its argument names (``distance_mm``, ``depth_mm``,
``L_mm``).  Importing the package imports nothing else (the workflow reads parts of it
while it plans a run).  ``docs/architecture.md`` describes the layout.

The ground floor
----------------
paper
    The paper's numbers, each written once.
models
    The waterbed membrane (small-slope parabola and exact arc) and the modified
    Boussinesq half-space.
bending, bending_exact
    The tensioned skin with bending stiffness, small-slope and finite-slope.
noise, priors
    The digitising errors measured from the data, and the priors they rest on.
averaging
    Left/right averaging of the converted profiles.
mechanics
    The membrane's tension and stiffness from recorded forces.
trials
    What a trial is and how every table names it.
io
    Reading and writing the human-readable files.
distributions
    The normal, t and chi-square functions the claims and the mechanics use.

The wings
---------
rawdata
    The data contract's checks; readings and photographs to tissue millimetres.
fitting
    The batch engine, each family's solver and the registry of model families.
claims
    Each claim of the paper as a rule with a verdict, and the registry of claims.
elastic
    A plane-strain finite-element fingertip (homogeneous or layered).
simulation
    The seeded synthetic reconstruction and the calibration studies.
figures
    The registry of figures and their drawing functions.
publishing
    Tables, the article's facts, the report's pages, provenance, crate and bundle.
runtime
    What Snakemake needs while it plans a run (standard library only).
"""

__version__ = "0.1.0"
