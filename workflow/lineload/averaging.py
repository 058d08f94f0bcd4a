"""Unit conversion and left/right averaging of digitised profiles.

Raw readings are taken on photographic enlargements; dividing by the
magnification gives tissue millimetres.  The two sides of the wedge are then
averaged at equal distances, which cancels small errors from a load that is
not quite normal to the skin.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = [
    "AVERAGED_COLUMNS",
    "CONVERTED_COLUMNS",
    "OUTLINE_COLUMNS",
    "average_sides",
    "outline_to_tissue_mm",
    "to_tissue_mm",
]

#: Distances closer than this (mm) are taken as the same reading position.
DISTANCE_TOLERANCE_MM = 1e-9

CONVERTED_COLUMNS = [
    "subject",
    "depth_mm",
    "side",
    "distance_image_mm",
    "deflection_image_mm",
    "magnification",
    "distance_mm",
    "deflection_mm",
]

AVERAGED_COLUMNS = [
    "subject",
    "depth_mm",
    "distance_mm",
    "left_mm",
    "right_mm",
    "left_source",
    "right_source",
    "deflection_mm",
    "n_sides",
]


def to_tissue_mm(profile, subject, magnification):
    """Convert readings on the enlargement to tissue millimetres.

    Parameters
    ----------
    profile : pandas.DataFrame
        Validated readings with ``depth_mm``, ``side``, ``distance_image_mm`` and
        ``deflection_image_mm``.
    subject : str
        Subject id, copied into every row.
    magnification : float
        Enlargement factor of the photographs (> 0).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`CONVERTED_COLUMNS`, sorted by depth, side and distance.
        The image-unit readings are kept beside the tissue values.
    """
    if not magnification > 0:
        raise ValueError(f"magnification must be > 0, got {magnification!r}")
    out = pd.DataFrame(
        {
            "subject": subject,
            "depth_mm": profile["depth_mm"].astype(float).to_numpy(),
            "side": profile["side"].to_numpy(),
            "distance_image_mm": profile["distance_image_mm"].astype(float).to_numpy(),
            "deflection_image_mm": profile["deflection_image_mm"].astype(float).to_numpy(),
            "magnification": float(magnification),
        }
    )
    out["distance_mm"] = out["distance_image_mm"] / magnification
    out["deflection_mm"] = out["deflection_image_mm"] / magnification
    return out.sort_values(["depth_mm", "side", "distance_mm"], kind="stable").reset_index(
        drop=True
    )[CONVERTED_COLUMNS]


def _side_on_grid(grid_mm, distance_mm, deflection_mm):
    """Values of one side on the common grid, and where each came from."""
    values = np.full(grid_mm.shape, np.nan)
    source = np.full(grid_mm.shape, "none", dtype=object)
    if distance_mm.size == 0:
        return values, source
    order = np.argsort(distance_mm, kind="stable")
    distance_mm, deflection_mm = distance_mm[order], deflection_mm[order]
    index = np.clip(np.searchsorted(distance_mm, grid_mm), 0, distance_mm.size - 1)
    nearest = np.where(
        np.abs(distance_mm[index - 1] - grid_mm) < np.abs(distance_mm[index] - grid_mm),
        index - 1,
        index,
    )
    measured = np.abs(distance_mm[nearest] - grid_mm) <= DISTANCE_TOLERANCE_MM
    inside = (grid_mm >= distance_mm[0]) & (grid_mm <= distance_mm[-1])
    values[inside] = np.interp(grid_mm[inside], distance_mm, deflection_mm)
    values[measured] = deflection_mm[nearest[measured]]
    source[inside] = "interpolated"
    source[measured] = "measured"
    return values, source


def average_sides(converted):
    """Average the left and right sides of each depth at equal distances.

    For each depth the distances read on either side form a common grid.  A
    side's value at a grid distance is its own reading where it has one, a
    linear interpolation between its neighbouring readings where the distance
    lies within its range, and missing otherwise.  The mean is taken over the
    sides present, and ``n_sides`` records how many there were (2, or 1 for a
    one-sided value kept as it is).

    Parameters
    ----------
    converted : pandas.DataFrame
        Output of :func:`to_tissue_mm` (one subject).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`AVERAGED_COLUMNS`, one row per depth and distance,
        sorted by depth then distance.  ``left_source`` and ``right_source``
        are ``measured``, ``interpolated`` or ``none``.
    """
    frames = []
    for depth_mm, group in converted.groupby("depth_mm", sort=True):
        sides = {}
        for side in ("left", "right"):
            rows = group[group["side"] == side]
            sides[side] = (
                rows["distance_mm"].to_numpy(dtype=float),
                rows["deflection_mm"].to_numpy(dtype=float),
            )
        all_distances = np.sort(group["distance_mm"].to_numpy(dtype=float))
        keep = np.concatenate([[True], np.diff(all_distances) > DISTANCE_TOLERANCE_MM])
        grid_mm = all_distances[keep]
        left, left_source = _side_on_grid(grid_mm, *sides["left"])
        right, right_source = _side_on_grid(grid_mm, *sides["right"])
        both = np.column_stack([left, right])
        n_sides = np.sum(np.isfinite(both), axis=1)
        mean = np.nansum(both, axis=1) / n_sides
        frames.append(
            pd.DataFrame(
                {
                    "subject": group["subject"].iloc[0],
                    "depth_mm": depth_mm,
                    "distance_mm": grid_mm,
                    "left_mm": left,
                    "right_mm": right,
                    "left_source": left_source,
                    "right_source": right_source,
                    "deflection_mm": mean,
                    "n_sides": n_sides,
                }
            )
        )
    if not frames:
        return pd.DataFrame(columns=AVERAGED_COLUMNS)
    return pd.concat(frames, ignore_index=True)[AVERAGED_COLUMNS]


OUTLINE_COLUMNS = [
    "subject",
    "depth_mm",
    "state",
    "x_image_mm",
    "z_image_mm",
    "magnification",
    "x_mm",
    "z_mm",
]


def outline_to_tissue_mm(outline, subject, magnification):
    """Convert a traced outline (Figure 1) from the enlargement to tissue millimetres.

    Parameters
    ----------
    outline : pandas.DataFrame
        Validated points with ``depth_mm``, ``state``, ``x_image_mm`` and ``z_image_mm``.
    subject : str
        Subject id, copied into every row.
    magnification : float
        Enlargement factor of the photographs (> 0).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`OUTLINE_COLUMNS`, the image-unit values kept beside the tissue
        ones, sorted by depth, state and x so that each outline can be drawn as a line.
    """
    if not magnification > 0:
        raise ValueError(f"magnification must be > 0, got {magnification!r}")
    out = pd.DataFrame(
        {
            "subject": subject,
            "depth_mm": outline["depth_mm"].astype(float).to_numpy(),
            "state": outline["state"].to_numpy(),
            "x_image_mm": outline["x_image_mm"].astype(float).to_numpy(),
            "z_image_mm": outline["z_image_mm"].astype(float).to_numpy(),
            "magnification": float(magnification),
        }
    )
    out["x_mm"] = out["x_image_mm"] / magnification
    out["z_mm"] = out["z_image_mm"] / magnification
    out = out.sort_values(["depth_mm", "state", "x_mm"], kind="stable")
    return out.reset_index(drop=True)[OUTLINE_COLUMNS]
