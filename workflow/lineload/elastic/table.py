"""The solution library's table: its columns, and its distances read back from them.

Kept apart from :mod:`lineload.elastic.library` (which solves) so that the fits read the
table without importing the finite-element solver: the default build's job that fits the
library depends on this layout, not on the solver's code.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "DEFLECTION_DECIMALS",
    "DEFLECTION_PREFIX",
    "KEY_COLUMNS",
    "SIZE_DECIMALS",
    "column_of",
    "grid_distances_mm",
    "library_columns",
]

#: The columns that say which profile a row is, then its force.
KEY_COLUMNS = (
    "species",
    "section",
    "length_mm",
    "height_mm",
    "bone_length_mm",
    "bone_height_mm",
    "pad_thickness_mm",
    "layer_thickness_mm",
    "modulus_ratio",
    "depth_mm",
    "force_per_length_per_pulp_modulus_mm",
    "elements",
)
#: A deflection column is ``deflection_at_<distance>_mm``.
DEFLECTION_PREFIX = "deflection_at_"
#: Decimals of the deflections written (mm): 1 nm, far below the mesh's micrometres.
DEFLECTION_DECIMALS = 6
#: Decimals of the sizes written (mm).
SIZE_DECIMALS = 4


def column_of(distance_mm):
    """The deflection column of a distance (mm)."""
    return f"{DEFLECTION_PREFIX}{distance_mm:.{SIZE_DECIMALS}f}_mm"


def library_columns(distances_mm):
    """The library's columns for a distance grid."""
    return [*KEY_COLUMNS, *(column_of(x) for x in distances_mm)]


def grid_distances_mm(columns):
    """The distances (mm) of a library table's deflection columns, in column order."""
    return np.array(
        [
            float(c[len(DEFLECTION_PREFIX) : -len("_mm")])
            for c in columns
            if c.startswith(DEFLECTION_PREFIX)
        ]
    )
