"""Where a profile is read: the paper's reading grid (Methods), in tissue millimetres.

The paper read the net vertical displacement every 0.05 mm out to 0.5 mm from the
wedge, then every 0.25-0.5 mm.  The grid here is that one: every 0.05 mm to 0.5 mm,
every 0.25 mm to 3 mm, then every 0.5 mm.  The digitiser reads photographs on it, the
raw-data check reads each photograph pair on it, and the generator of the synthetic
data places its readings on it; none of them owns it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["GRID_TICK_MM", "reading_distances_mm", "reading_ticks"]

#: Spacing of the reading positions, tissue mm: the finest step of the grid.
GRID_TICK_MM = 0.05
#: Reading grid in ticks of 0.05 mm: every tick to 0.5 mm, every 5 ticks
#: (0.25 mm) to 3 mm, then every 10 ticks (0.5 mm).
FINE_END_TICKS, MEDIUM_END_TICKS = 10, 60
MEDIUM_STEP_TICKS, COARSE_STEP_TICKS = 5, 10


def reading_distances_mm(extent_mm, first_mm=0.05):
    """Distances at which one side is read, in tissue mm.

    Every 0.05 mm up to 0.5 mm, every 0.25 mm up to 3 mm, then every 0.5 mm,
    keeping the positions strictly inside the deformed region, and a last
    reading at its edge.  Readings closer to the wedge than ``first_mm`` are
    lost to glare.

    Parameters
    ----------
    extent_mm : float
        Edge of the deformed region (mm; rounded to the 0.05 mm grid).
    first_mm : float, optional
        First readable distance (mm), 0.05 or 0.1 in the shipped data.

    Returns
    -------
    numpy.ndarray
        Increasing distances (mm), the last one equal to the edge.
    """
    return reading_ticks(extent_mm, first_mm) * GRID_TICK_MM


def reading_ticks(extent_mm, first_mm):
    """Reading positions as integer multiples of 0.05 mm (see :func:`reading_distances_mm`)."""
    edge = round(extent_mm / GRID_TICK_MM)
    first = round(first_mm / GRID_TICK_MM)
    if edge < 1:
        raise ValueError(f"extent must be at least {GRID_TICK_MM} mm, got {extent_mm}")
    fine = np.arange(1, FINE_END_TICKS + 1)
    medium = np.arange(FINE_END_TICKS + MEDIUM_STEP_TICKS, MEDIUM_END_TICKS + 1, MEDIUM_STEP_TICKS)
    coarse = np.arange(MEDIUM_END_TICKS + COARSE_STEP_TICKS, edge, COARSE_STEP_TICKS)
    ticks = np.concatenate([fine, medium, coarse])
    ticks = ticks[(ticks >= first) & (ticks < edge)]
    return np.append(ticks, edge)
