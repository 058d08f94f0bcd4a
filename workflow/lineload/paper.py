"""Numbers stated in Srinivasan (1989), each once, with where the paper gives it.

These are the paper's statements that the workflow recomputes or draws, not
tuning thresholds: a rule compares what the data give with them.  Thresholds
that belong to the analysis (noise, tolerances) live in the config.
"""

from __future__ import annotations

__all__ = [
    "DEFORMED_EXTENT_MM",
    "DEPTHS_MM",
    "EXAMPLE_DEPTH_MM",
    "FORCE_RANGE_N",
    "L_RANGE_MM",
    "MAGNIFICATION",
    "MAX_SHIFT_FRACTION",
    "REACH_MM",
    "SPECIES",
]

#: The two species studied, in the order the paper presents them (Figs 6, 7).
SPECIES = ("monkey", "human")

#: Indentation depths of Figs 6 and 7 (mm); Methods, "Experimental procedure".
DEPTHS_MM = (0.5, 1.0, 1.5, 2.0)

#: Depth of the example profiles of Fig. 2 (mm); Fig. 2 caption.
EXAMPLE_DEPTH_MM = 1.0

#: Enlargement of the photographs the readings were taken on; Methods.
MAGNIFICATION = 20.0

#: Distance from the wedge (mm) over which the skin is deformed, per species;
#: Results, first paragraph.
DEFORMED_EXTENT_MM = {"monkey": (3.0, 7.0), "human": (6.0, 12.0)}

#: Fitted membrane half-width L (mm); Results, "Comparison of theoretical and
#: experimental results".
L_RANGE_MM = (10.0, 15.0)

#: Bound on the horizontal shift at X = L/3, |U| / X; same paragraph.
MAX_SHIFT_FRACTION = 0.08

#: Distance from the load (mm) within which the waterbed is said to fit well;
#: Abstract and Discussion, second paragraph.
REACH_MM = 3.0

#: Steady-state force on the wedge (N) over the depths used; Methods.
FORCE_RANGE_N = (0.3, 1.0)
