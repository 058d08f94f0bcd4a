"""Unit conversion and side averaging as they were at commit 37aa67d (pandas, per depth).

Kept as an independent reference for the column-wise code in lineload.averaging:
the functions unchanged except for docstrings removed.  It uses no lineload code.
"""

import numpy as np
import pandas as pd

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
    values = np.full(grid_mm.shape, np.nan)
    source = np.full(grid_mm.shape, "none", dtype=object)
    if distance_mm.size == 0:
        return (values, source)
    order = np.argsort(distance_mm, kind="stable")
    distance_mm, deflection_mm = (distance_mm[order], deflection_mm[order])
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
    return (values, source)


def average_sides(converted):
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
