"""Plausibility of magnitudes: depths, deflections and lengths a fingertip can have.

A table can keep to its schema and still be wrong by a unit: a depth of 750 is almost
surely 750 µm written where millimetres belong, a deflection a thousand times the depth
micrometres, one a magnification smaller than the depth readings already in tissue mm.
Each check refuses such values with the likely cause; each limit is the config's
``input_checks`` (defaults from the config schema, the one source:
:func:`plausibility_defaults`).  :func:`check_thin_trials` refuses a trial with too few
readings near the wedge to fit.
"""

from __future__ import annotations

import math

from lineload.rawdata.errors import _more, collecting
from lineload.runtime.lazy import lazy_import

# numpy when first used, as in the rest of the raw-data check (lazy.py)
np = lazy_import("numpy")

__all__ = [
    "check_deflection_near_wedge",
    "check_depth_range",
    "check_reach",
    "check_thin_trials",
    "plausibility_defaults",
]


def plausibility_defaults():
    """The plausibility limits' defaults: the config schema's ``input_checks``."""
    from lineload.io import config_defaults

    return config_defaults("input_checks")


def _as_columns(table):
    """Columns and line numbers of a table from :func:`read_table` or :func:`read_columns`."""
    if isinstance(table, tuple):
        return table[0], np.asarray(table[1])
    return table, table.index.to_numpy()


def _unit_hint(value_mm, low_mm, high_mm, magnification=None):
    """A likely cause for a depth outside [low, high] mm.

    A unit is suggested only for a value outside the default range too (a depth
    just beyond a lab's own narrower limits is no unit mistake), and only when
    converting it lands inside the range.
    """
    defaults = plausibility_defaults()
    default_low, default_high = defaults["depth_min_mm"], defaults["depth_max_mm"]

    def inside(v):
        return low_mm <= v <= high_mm

    if value_mm > max(high_mm, default_high):
        if inside(value_mm / 1000):
            return f"it looks like micrometres ({value_mm:g} µm = {value_mm / 1000:g} mm)"
        if magnification and inside(value_mm / magnification):
            return (
                f"it looks like a length on the x{magnification:g} enlargement "
                f"({value_mm / magnification:g} mm of tissue); depth_mm is in tissue mm"
            )
    if value_mm < min(low_mm, default_low) and inside(value_mm * 1000):
        return f"it looks like metres ({value_mm:g} m = {value_mm * 1000:g} mm)"
    return "depth_mm is the depth of the wedge in tissue mm"


def check_depth_range(table, path, low_mm, high_mm, magnification=None, problems=None):
    """Refuse depths outside a plausible range (in mm), naming a likely unit mistake.

    A fingertip is indented by tenths of a millimetre to a few millimetres; a
    depth of 750 is almost surely 750 µm written where millimetres belong.

    Parameters
    ----------
    table : pandas.DataFrame or tuple
        A profile or outline from :func:`read_table`, or the ``(columns, lines)``
        of :func:`read_columns` (``depth_mm`` typed).
    path : str
        File name used in the message.
    low_mm, high_mm : float
        The plausible range (config ``input_checks``: ``depth_min_mm``,
        ``depth_max_mm``).
    magnification : float, optional
        The subject's enlargement, to recognise a depth read on the photograph.
    problems : Problems, optional
        Collector to add the problem to; without one, it is raised.

    Raises
    ------
    InputError
        Without a collector: the first depth outside the range (and how many
        more lines are), with a likely cause.
    """
    with collecting(problems) as found:
        columns, lines = _as_columns(table)
        depth_mm = np.asarray(columns["depth_mm"], dtype=float)
        with np.errstate(invalid="ignore"):
            bad = (depth_mm < low_mm) | (depth_mm > high_mm)
        if bad.any():
            lines = [int(n) for n in lines]
            i = int(np.argmax(bad))
            found.error(
                path,
                lines[i],
                "depth_mm",
                f"expected a depth between {low_mm:g} and {high_mm:g} mm "
                f"(config input_checks: depth_min_mm, depth_max_mm), got {depth_mm[i]:g}; "
                + _unit_hint(float(depth_mm[i]), low_mm, high_mm, magnification)
                + _more(lines, bad, "lines with a depth outside that range"),
            )


def _ratio_hint(ratio, magnification):
    """A likely cause for a deflection next to the wedge ``ratio`` times the depth."""
    if ratio <= 0:
        if ratio < 0:
            return (
                "the deflections look upward positive; deflection_image_mm is downward "
                "positive (the skin under the wedge goes down by about the depth)"
            )
        return "the readings show no indentation next to the wedge"

    def near(value, target):
        return abs(math.log(value / target)) < math.log(1.5)

    if near(ratio, 1000):
        return "the deflections look like micrometres; give them in mm on the enlargement"
    if near(ratio, 1 / 1000):
        return "the deflections look like metres; give them in mm on the enlargement"
    if magnification != 1 and near(ratio, 1 / magnification):
        return (
            "the readings look like tissue mm already: then the subject's magnification "
            f"in subjects.csv should be 1, not {magnification:g}"
        )
    fitting = magnification * ratio
    return (
        f"check the subject's magnification in subjects.csv ({magnification:g}; "
        f"about {fitting:.2g} would match) and the unit of the readings"
    )


def check_deflection_near_wedge(profile, path, magnification, factor, problems=None):
    """Refuse a profile whose deflection next to the wedge is far from the stated depth.

    The skin under the wedge goes down with it, so the readings nearest the
    wedge, converted to tissue mm (image mm / magnification), show a deflection
    close to the depth.  For each depth, the reading nearest the wedge on each
    side is converted and the sides averaged; a mean more than ``factor`` times
    larger or smaller than the depth points to a wrong unit, magnification or
    sign.

    Parameters
    ----------
    profile : pandas.DataFrame or tuple
        A profile without contract problems, from :func:`read_table` or
        :func:`read_columns`.
    path : str
        File name used in the message.
    magnification : float
        The subject's enlargement (> 0).
    factor : float
        Tolerance (> 1; config ``input_checks: deflection_factor``).
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.

    Raises
    ------
    InputError
        Without a collector: one line for the file, at the nearest reading of
        the first depth that fails (naming the other depths that fail too).
    """
    with collecting(problems) as found:
        columns, lines = _as_columns(profile)
        depth_mm = np.asarray(columns["depth_mm"], dtype=float)
        distance = np.asarray(columns["distance_image_mm"], dtype=float)
        deflection = np.asarray(columns["deflection_image_mm"], dtype=float)
        side = np.asarray(columns["side"], dtype=object)
        failed = []  # (depth, rows of the nearest readings, mean deflection in mm)
        for depth in np.unique(depth_mm):
            nearest = []
            for which in ("left", "right"):
                rows = np.flatnonzero((depth_mm == depth) & (side == which))
                if rows.size:
                    nearest.append(rows[np.argmin(distance[rows])])
            nearest.sort(key=lambda k: lines[k])
            mean_mm = float(np.mean(deflection[nearest])) / magnification
            if not 1 / factor <= mean_mm / depth <= factor:
                failed.append((float(depth), nearest, mean_mm))
        if not failed:
            return
        depth, nearest, mean_mm = failed[0]
        ratio = mean_mm / depth
        sides = "mean of left and right" if len(nearest) == 2 else f"{side[nearest[0]]} only"
        at_mm = float(np.mean(distance[nearest])) / magnification
        also = ""
        if len(failed) > 1:
            also = f" (so do depths {', '.join(f'{d:g}' for d, _, _ in failed[1:])} mm)"
        found.error(
            path,
            int(lines[nearest[0]]),
            "deflection_image_mm",
            f"at depth {depth:g} mm the readings nearest the wedge ({at_mm:.3g} mm from it, "
            f"{sides}) show {mean_mm:.4g} mm of deflection after dividing by the "
            f"magnification {magnification:g}, {ratio:.3g} times the depth{also}; expected "
            f"within a factor of {factor:g} of the depth (config input_checks: "
            "deflection_factor); " + _ratio_hint(ratio, magnification),
        )


def _reach_hint(value_mm, reach_max_mm):
    """A likely cause for a length of ``value_mm`` of tissue beyond ``reach_max_mm``."""
    if value_mm / 1000 <= reach_max_mm:
        return f"it looks like micrometres ({value_mm:g} µm = {value_mm / 1000:g} mm)"
    return "a fingertip is a few tens of millimetres across"


def check_reach(table, path, magnification, reach_max_mm, deflection_factor=None, problems=None):
    """Refuse lengths no fingertip has: readings or outline points too far from the wedge.

    Every coordinate on the enlargement, divided by the magnification, must lie
    within ``reach_max_mm`` of tissue of the wedge: the distances and
    deflections of a profile, the ``x`` and ``z`` of an outline.  With
    ``deflection_factor``, a profile's deflections must also stay within that
    factor of their depth, above or below: the skin moves most under the wedge,
    by about the depth, and less everywhere else.

    Parameters
    ----------
    table : pandas.DataFrame or tuple
        A profile or outline from :func:`read_table` or :func:`read_columns`
        (``depth_mm`` within its range).
    path : str
        File name used in the message.
    magnification : float
        The subject's enlargement (> 0).
    reach_max_mm : float
        Config ``input_checks: reach_max_mm``.
    deflection_factor : float, optional
        Config ``input_checks: deflection_factor`` (profiles only).
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.

    Raises
    ------
    InputError
        Without a collector: the first value of each column out of range (and
        how many more lines are), with a likely cause.
    """
    with collecting(problems) as found:
        columns, lines = _as_columns(table)
        lines = [int(n) for n in lines]
        names = [c for c in ("distance_image_mm", "x_image_mm", "z_image_mm") if c in columns]
        limit = {name: reach_max_mm for name in names}
        if deflection_factor is not None:
            names.append("deflection_image_mm")
            depth_mm = np.asarray(columns["depth_mm"], dtype=float)
            limit["deflection_image_mm"] = np.minimum(deflection_factor * depth_mm, reach_max_mm)
        for name in names:
            value_mm = np.asarray(columns[name], dtype=float) / magnification
            with np.errstate(invalid="ignore"):
                bad = np.abs(value_mm) > limit[name]
            if not bad.any():
                continue
            i = int(np.argmax(bad))
            read = f"got {value_mm[i] * magnification:g} on the x{magnification:g} enlargement"
            if name == "deflection_image_mm" and limit[name][i] < reach_max_mm:
                expected = (
                    f"expected a deflection of at most {deflection_factor:g} times the depth "
                    f"({limit[name][i]:g} mm of tissue at {depth_mm[i]:g} mm; config "
                    f"input_checks: deflection_factor), {read} = {value_mm[i]:.4g} mm of "
                    "tissue; the skin moves most under the wedge, by about the depth"
                )
            else:
                expected = (
                    f"expected at most {reach_max_mm:g} mm of tissue from the wedge (config "
                    f"input_checks: reach_max_mm), {read} = {value_mm[i]:.4g} mm of tissue; "
                    + _reach_hint(abs(float(value_mm[i])), reach_max_mm)
                )
            found.error(
                path, lines[i], name, expected + _more(lines, bad, "lines out of that range")
            )


def check_thin_trials(profile, path, magnification, window_mm, min_points, problems=None):
    """Refuse a trial with too few readings near the wedge to fit.

    The fits use the left-right mean at every distance read on either side
    with ``0 < distance <= window_mm`` (tissue mm).  A trial with fewer than
    ``min_points`` such distances is refused: one or two points would give an
    L, an interval and a misfit that look like any other.

    Parameters
    ----------
    profile : pandas.DataFrame or tuple
        A profile without contract problems (:func:`read_table` or
        :func:`read_columns`).
    path : str
        File name used in the message.
    magnification : float
        The subject's enlargement (> 0).
    window_mm : float
        Config ``fit_window_mm``.
    min_points : int
        Config ``min_points_in_window``.
    problems : Problems, optional
        Collector to add the problem to; without one, it is raised.

    Raises
    ------
    InputError
        Without a collector: one line for the file, at the first reading of the
        first thin depth (naming the other thin depths).
    """
    from lineload.averaging import DISTANCE_TOLERANCE_MM

    with collecting(problems) as found:
        columns, lines = _as_columns(profile)
        depth_mm = np.asarray(columns["depth_mm"], dtype=float)
        distance_mm = np.asarray(columns["distance_image_mm"], dtype=float) / magnification
        thin = []  # (depth, points, first row)
        for depth in np.unique(depth_mm):
            rows = np.flatnonzero(depth_mm == depth)
            near = np.sort(
                distance_mm[rows][(distance_mm[rows] > 0) & (distance_mm[rows] <= window_mm)]
            )
            points = int(near.size and 1 + np.count_nonzero(np.diff(near) > DISTANCE_TOLERANCE_MM))
            if points < min_points:
                thin.append((float(depth), points, int(rows[np.argmin(lines[rows])])))
        if not thin:
            return
        depth, points, row = thin[0]
        also = ""
        if len(thin) > 1:
            also = f" (so do depths {', '.join(f'{d:g}' for d, _, _ in thin[1:])} mm)"
        found.error(
            path,
            int(lines[row]),
            "distance_image_mm",
            f"at depth {depth:g} mm {points} distance{'s' if points != 1 else ''} within "
            f"{window_mm:g} mm of the wedge were read{also}; expected at least {min_points} "
            "(config min_points_in_window, fit_window_mm): fewer cannot give the fits' "
            "numbers; read the profile more finely near the wedge, or leave the depth out",
        )


def _check_contact_lengths(subjects, path, reach_max_mm, problems):
    """Refuse a contact length of wedge edge longer than any fingertip is wide."""
    if "contact_length_mm" not in subjects:
        return
    for line, value in zip(subjects.index, subjects["contact_length_mm"], strict=True):
        if value == value and value > reach_max_mm:  # NaN: an empty optional cell
            problems.error(
                path,
                int(line),
                "contact_length_mm",
                f"expected a contact length of at most {reach_max_mm:g} mm (config "
                f"input_checks: reach_max_mm), got {value:g}; "
                + _reach_hint(float(value), reach_max_mm),
            )
