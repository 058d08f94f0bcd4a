"""Unit conversion and left/right averaging of digitised profiles.

Raw readings are taken on photographic enlargements; dividing by the
magnification gives tissue millimetres.  The two sides of the wedge are then
averaged at equal distances, which cancels small errors from a load that is
not quite normal to the skin.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "AVERAGED_COLUMNS",
    "CONVERTED_COLUMNS",
    "average_columns",
    "average_sides",
    "tissue_columns",
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


def tissue_columns(profile, subject, magnification):
    """:func:`to_tissue_mm` as a dict of numpy arrays (no DataFrame).

    Parameters
    ----------
    profile : mapping
        Column name to values (a DataFrame, or the columns of
        :func:`lineload.validation.read_columns`): ``depth_mm``, ``side``,
        ``distance_image_mm`` and ``deflection_image_mm``.
    subject : str
        Subject id, copied into every row.
    magnification : float
        Enlargement factor of the photographs (> 0).

    Returns
    -------
    dict of numpy.ndarray
        The columns :data:`CONVERTED_COLUMNS`, in that order, rows sorted by
        depth, side and distance (a stable sort: ties keep the file order).
    """
    if not magnification > 0:
        raise ValueError(f"magnification must be > 0, got {magnification!r}")
    depth_mm = np.asarray(profile["depth_mm"], dtype=float)
    side = np.asarray(profile["side"], dtype=object)
    distance_image_mm = np.asarray(profile["distance_image_mm"], dtype=float)
    deflection_image_mm = np.asarray(profile["deflection_image_mm"], dtype=float)
    distance_mm = distance_image_mm / magnification
    deflection_mm = deflection_image_mm / magnification
    side_rank = np.unique(side, return_inverse=True)[1].reshape(-1) if side.size else side
    order = np.lexsort((distance_mm, side_rank, depth_mm))
    return {
        "subject": np.full(depth_mm.size, subject, dtype=object),
        "depth_mm": depth_mm[order],
        "side": side[order],
        "distance_image_mm": distance_image_mm[order],
        "deflection_image_mm": deflection_image_mm[order],
        "magnification": np.full(depth_mm.size, float(magnification)),
        "distance_mm": distance_mm[order],
        "deflection_mm": deflection_mm[order],
    }


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
    import pandas as pd  # here only: the batch job works on columns (tissue_columns)

    return pd.DataFrame(tissue_columns(profile, subject, magnification))


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


def average_columns(converted):
    """:func:`average_sides` as a dict of numpy arrays (no DataFrame).

    Parameters
    ----------
    converted : mapping
        Column name to values, as :func:`tissue_columns` (or
        :func:`to_tissue_mm`) gives them for one subject.

    Returns
    -------
    dict of numpy.ndarray
        The columns :data:`AVERAGED_COLUMNS`, in that order.
    """
    depth_all = np.asarray(converted["depth_mm"], dtype=float)
    keep = ~np.isnan(depth_all)  # as groupby, which leaves out a missing depth
    order = np.flatnonzero(keep)[np.argsort(depth_all[keep], kind="stable")]
    depth_mm = depth_all[order]
    side = np.asarray(converted["side"], dtype=object)[order]
    distance_mm = np.asarray(converted["distance_mm"], dtype=float)[order]
    deflection_mm = np.asarray(converted["deflection_mm"], dtype=float)[order]
    subject = np.asarray(converted["subject"], dtype=object)[order]
    starts = np.flatnonzero(np.r_[True, depth_mm[1:] != depth_mm[:-1]]) if order.size else []
    parts = []
    for start, stop in zip(starts, [*starts[1:], order.size], strict=True):
        # one depth: its rows in their original order
        sides = {}
        for name in ("left", "right"):
            rows = start + np.flatnonzero(side[start:stop] == name)
            sides[name] = (distance_mm[rows], deflection_mm[rows])
        all_distances = np.sort(distance_mm[start:stop])
        grid_mm = all_distances[np.r_[True, np.diff(all_distances) > DISTANCE_TOLERANCE_MM]]
        left, left_source = _side_on_grid(grid_mm, *sides["left"])
        right, right_source = _side_on_grid(grid_mm, *sides["right"])
        both = np.column_stack([left, right])
        n_sides = np.sum(np.isfinite(both), axis=1)
        parts.append(
            (
                np.full(grid_mm.size, subject[start], dtype=object),
                np.full(grid_mm.size, depth_mm[start]),
                grid_mm,
                left,
                right,
                left_source,
                right_source,
                np.nansum(both, axis=1) / n_sides,
                n_sides,
            )
        )
    if not parts:
        return {name: np.array([], dtype=object) for name in AVERAGED_COLUMNS}
    return {
        name: np.concatenate(values)
        for name, values in zip(AVERAGED_COLUMNS, zip(*parts, strict=True), strict=True)
    }


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
    import pandas as pd  # here only: the batch job works on columns (average_columns)

    columns = average_columns(converted)
    if not len(columns["depth_mm"]):
        return pd.DataFrame(columns=AVERAGED_COLUMNS)
    return pd.DataFrame(columns)
