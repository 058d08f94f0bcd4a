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
    "OUTLINE_COLUMNS",
    "average_columns",
    "average_sides",
    "average_subjects",
    "outline_to_tissue_mm",
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
        :func:`lineload.rawdata.validation.read_columns`): ``depth_mm``, ``side``,
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


def _readings_before(reading_group, reading_mm, grid_group, grid_mm, counting_equal):
    """For each grid point, how many readings of all groups up to its own lie below it.

    Readings of earlier groups all count; of its own group those below it, and with
    ``counting_equal`` those equal to it (``searchsorted`` right, else left): one
    sort of readings and points together.
    """
    groups = np.concatenate([reading_group, grid_group])
    values = np.concatenate([reading_mm, grid_mm])
    reading_tag, grid_tag = (0, 1) if counting_equal else (1, 0)
    tags = np.concatenate([np.full(reading_mm.size, reading_tag), np.full(grid_mm.size, grid_tag)])
    order = np.lexsort((tags, values, groups))
    is_reading = order < reading_mm.size
    before = np.cumsum(is_reading) - is_reading
    position = np.empty(order.size, dtype=np.intp)
    position[order] = np.arange(order.size)
    return before[position[reading_mm.size :]]


def _sides_on_grid(grid_group, grid_mm, reading_group, reading_mm, value_mm, n_groups):
    """:func:`_side_on_grid` for every group (subject and depth) of one side at once.

    The readings come sorted by group and distance.  Each step rounds as numpy
    does in the one-group version: the nearest reading by ``searchsorted``
    (index - 1 of the first being the last, as a negative index is), and the
    interpolation as ``numpy.interp`` computes it (the bracketing reading found by
    counting, the value itself at a reading or at the last one).
    """
    values = np.full(grid_mm.shape, np.nan)
    source = np.full(grid_mm.shape, "none", dtype=object)
    counts = np.bincount(reading_group, minlength=n_groups)
    starts = np.cumsum(counts) - counts
    points = np.flatnonzero(counts[grid_group] > 0)
    if not points.size:
        return values, source
    v = grid_mm[points]
    count, start = counts[grid_group[points]], starts[grid_group[points]]
    below = _readings_before(reading_group, reading_mm, grid_group[points], v, False) - start
    index = np.clip(below, 0, count - 1)
    previous = np.where(index > 0, index - 1, count - 1)
    nearest = np.where(
        np.abs(reading_mm[start + previous] - v) < np.abs(reading_mm[start + index] - v),
        previous,
        index,
    )
    measured = np.abs(reading_mm[start + nearest] - v) <= DISTANCE_TOLERANCE_MM
    inside = (v >= reading_mm[start]) & (v <= reading_mm[start + count - 1])
    # numpy.interp: j the last reading at or below the point
    j = _readings_before(reading_group, reading_mm, grid_group[points], v, True) - start - 1
    j = np.clip(j, 0, count - 1)
    at_reading = inside & ((j == count - 1) | (reading_mm[start + j] == v))
    between = np.flatnonzero(inside & ~at_reading)
    interpolated = np.where(at_reading, value_mm[start + j], np.nan)
    if between.size:
        lo = start[between] + j[between]
        hi = lo + 1
        slope = (value_mm[hi] - value_mm[lo]) / (reading_mm[hi] - reading_mm[lo])
        x = v[between]
        result = slope * (x - reading_mm[lo]) + value_mm[lo]
        again = np.isnan(result)  # as numpy.interp: from the other end, then the level
        if again.any():
            other = slope * (x - reading_mm[hi]) + value_mm[hi]
            level = np.isnan(other) & (value_mm[lo] == value_mm[hi])
            result = np.where(again, np.where(level, value_mm[lo], other), result)
        interpolated[between] = result
    picked = np.where(measured, value_mm[start + nearest], interpolated)
    values[points] = np.where(measured | inside, picked, np.nan)
    source[points[inside]] = "interpolated"
    source[points[measured]] = "measured"
    return values, source


def _average(part, converted):
    """Side averages of the rows of ``converted``, grouped by ``part`` and depth."""
    depth_mm = np.asarray(converted["depth_mm"], dtype=float)
    rows = np.flatnonzero(~np.isnan(depth_mm))  # as groupby, which leaves out a missing depth
    if not rows.size:
        return {name: np.array([], dtype=object) for name in AVERAGED_COLUMNS}
    part, depth_mm = part[rows], depth_mm[rows]
    side = np.asarray(converted["side"], dtype=object)[rows]
    distance_mm = np.asarray(converted["distance_mm"], dtype=float)[rows]
    deflection_mm = np.asarray(converted["deflection_mm"], dtype=float)[rows]
    subject = np.asarray(converted["subject"], dtype=object)[rows]
    # groups: by part, then by depth; rows keep their order within a group (stable)
    by_group = np.lexsort((depth_mm, part))
    new = np.ones(rows.size, dtype=bool)
    new[1:] = (part[by_group][1:] != part[by_group][:-1]) | (
        depth_mm[by_group][1:] != depth_mm[by_group][:-1]
    )
    group = np.empty(rows.size, dtype=np.intp)
    group[by_group] = np.cumsum(new) - 1
    first_row = by_group[new]  # the first row of each group, as groupby's iloc[0]
    n_groups = first_row.size
    # the grid of each group: its distances, sorted, those within the tolerance merged
    by_distance = np.lexsort((distance_mm, group))
    sorted_group, sorted_mm = group[by_distance], distance_mm[by_distance]
    keep = np.ones(rows.size, dtype=bool)
    keep[1:] = (sorted_group[1:] != sorted_group[:-1]) | (
        np.diff(sorted_mm) > DISTANCE_TOLERANCE_MM
    )
    grid_group, grid_mm = sorted_group[keep], sorted_mm[keep]
    sides = {}
    for name in ("left", "right"):
        # this side's readings by group and distance; ties keep their order (stable)
        readings = np.flatnonzero(side == name)
        readings = readings[np.lexsort((distance_mm[readings], group[readings]))]
        sides[name] = _sides_on_grid(
            grid_group,
            grid_mm,
            group[readings],
            distance_mm[readings],
            deflection_mm[readings],
            n_groups,
        )
    (left, left_source), (right, right_source) = sides["left"], sides["right"]
    both = np.column_stack([left, right])
    n_sides = np.sum(np.isfinite(both), axis=1)
    return {
        "subject": subject[first_row][grid_group],
        "depth_mm": depth_mm[first_row][grid_group],
        "distance_mm": grid_mm,
        "left_mm": left,
        "right_mm": right,
        "left_source": left_source,
        "right_source": right_source,
        "deflection_mm": np.nansum(both, axis=1) / n_sides,
        "n_sides": n_sides,
    }


def average_columns(converted):
    """:func:`average_sides` as a dict of numpy arrays (no DataFrame).

    All depths and both sides are done together (no loop over depths), with the
    arithmetic of the one-depth version.

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
    return _average(np.zeros(len(converted["depth_mm"]), dtype=np.intp), converted)


def average_subjects(converted):
    """:func:`average_columns` of many subjects in one pass, one after the other.

    Parameters
    ----------
    converted : sequence of mapping
        Each subject's columns, as :func:`tissue_columns` gives them.

    Returns
    -------
    dict of numpy.ndarray
        The columns :data:`AVERAGED_COLUMNS`: the first subject's rows, then the
        second's, ... (what concatenating :func:`average_columns` of each gives).
    """
    if not converted:
        return _average(np.zeros(0, dtype=np.intp), {name: [] for name in CONVERTED_COLUMNS})
    part = np.repeat(np.arange(len(converted)), [len(c["depth_mm"]) for c in converted])
    names = ("subject", "depth_mm", "side", "distance_mm", "deflection_mm")
    joined = {name: np.concatenate([np.asarray(c[name]) for c in converted]) for name in names}
    return _average(part, joined)


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
    import pandas as pd  # here only: the batch job works on columns

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
