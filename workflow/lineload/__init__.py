"""Line-load fingertip deflection: models, fits and helpers.

A small, Snakemake-free package behind the workflow that reproduces
Srinivasan (1989), "Surface deflection of primate fingertip under line load".
Every function works on numpy arrays or pandas DataFrames and carries its
units in its argument names (``distance_mm``, ``depth_mm``, ``L_mm``).

Modules
-------
models
    The waterbed membrane (small-slope parabola and exact circular arc) and
    the modified Boussinesq half-space.
fitting
    Least-squares fits of the three models with goodness-of-fit measures.
averaging
    Unit conversion and left/right averaging of digitised profiles.
validation
    Checks of the raw-data contract with file/line/column messages.
synthetic
    The seeded generator of the shipped synthetic reconstruction.
"""

__version__ = "0.1.0"
