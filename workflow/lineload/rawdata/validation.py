"""Checks of the raw-data contract, with messages that point at the bad cell.

Each table of the contract (``subjects.csv``, ``profiles/<subject>.csv``,
``outlines/<subject>.csv``, the optional ``forces.csv`` and ``images/images.csv``) has
a JSON schema describing one row; every failure is reported as one line naming the
file, the line (the header is line 1) and the column, with what was expected and what
was found.  This module holds the rules that span rows or files, which a row schema
cannot say (unique ids, duplicate readings, a profile file for each subject, one force
per trial), and :func:`check_dataset`, which runs every check on a raw folder.  The
rest of the check lives beside it, one idea per module, and is re-exported here:

- :mod:`lineload.rawdata.errors`: :class:`InputError`, the :class:`Problems`
  collector, :func:`report_lines` (standard library only);
- :mod:`lineload.rawdata.sheets`: reading one table against its row schema
  (:func:`read_columns`, :func:`read_table`: encodings, separators, headers, cells);
- :mod:`lineload.rawdata.plausibility`: magnitudes a fingertip can have
  (:func:`check_depth_range`, :func:`check_deflection_near_wedge`,
  :func:`check_reach`, :func:`check_thin_trials`), each with its limit in the config's
  ``input_checks`` (defaults from the config schema, the one source);
- :mod:`lineload.rawdata.forces`: the optional ``forces.csv`` (:func:`check_forces`,
  :func:`read_forces`);
- :mod:`lineload.rawdata.images`: ``images/images.csv`` and its photograph pairs
  (:func:`check_images`, :func:`photograph_files`);
- :mod:`lineload.rawdata.paths`: links that lead out of the raw folder and names
  that nearly match the contract's (:func:`links_outside`, :func:`near_miss_names`).

All problems of a run in one pass
---------------------------------
Every check function takes an optional ``problems`` collector
(:class:`Problems`) and adds one line per problem to it with
``problems.error(path, line, column, message)`` (or ``.warning``, for what is
worth saying but does not stop a run).  Called without one, a check collects
its own problems and raises them together as one :class:`InputError` at its
end.  :func:`check_dataset` passes one collector through every check of a
raw folder, so a lab sees every broken file at once; a new check adds its
problems the same way (a check that raises an :class:`InputError` instead is
folded in too, by :meth:`Problems.collect`).  :func:`report_lines` turns the
collected problems into the lines printed for the user, at most
:data:`MAX_REPORTED` errors.
"""

from __future__ import annotations

import os
import re

from lineload.rawdata.errors import (
    MAX_REPORTED,
    InputError,
    Problems,
    _more,
    collecting,
    report_lines,
)
from lineload.rawdata.forces import _forces_schema, check_forces, read_forces
from lineload.rawdata.images import (
    _images_schema,
    check_images,
    image_properties,
    image_scale_px_per_mm,
    photograph_files,
    photographed_subjects,
)
from lineload.rawdata.paths import (
    DATA_FOLDERS,
    _files_in,
    _near_names,
    links_outside,
    near_miss_names,
    outside,
)
from lineload.rawdata.plausibility import (
    _check_contact_lengths,
    check_deflection_near_wedge,
    check_depth_range,
    check_reach,
    check_thin_trials,
    plausibility_defaults,
)
from lineload.rawdata.sheets import read_columns, read_table
from lineload.runtime.lazy import lazy_import

# numpy when first used: Snakemake reads the subject sheet at start-up through this
# package (lineload.runtime.startup), where numpy may not be installed (lazy.py)
np = lazy_import("numpy")

__all__ = [
    "DATA_FOLDERS",
    "MAX_REPORTED",
    "InputError",
    "Problems",
    "check_dataset",
    "check_deflection_near_wedge",
    "check_depth_range",
    "check_forces",
    "check_images",
    "check_no_duplicate_readings",
    "check_reach",
    "check_subject_files",
    "check_subjects",
    "check_thin_trials",
    "collecting",
    "image_properties",
    "image_scale_px_per_mm",
    "links_outside",
    "near_miss_names",
    "outside",
    "photograph_files",
    "photographed_subjects",
    "plausibility_defaults",
    "read_columns",
    "read_forces",
    "read_table",
    "report_lines",
    "unlisted_files",
]


def _may_repeat(columns, keys):
    """Whether two rows could agree in every key column (numpy, no pandas).

    Rows are sorted on the keys and neighbours compared, NaN counting as equal
    to NaN and -0.0 to 0.0 as pandas counts them; a column numpy cannot sort
    answers True, leaving the decision to pandas.
    """
    arrays = []
    for key in keys:
        values = np.asarray(columns[key])
        if values.dtype.kind != "f":
            try:
                values = np.unique(values, return_inverse=True)[1].reshape(-1)
            except TypeError:
                return True
        arrays.append(values)
    if arrays[0].size < 2:
        return False
    order = np.lexsort(arrays[::-1])
    same = np.ones(order.size - 1, dtype=bool)
    for values in arrays:
        ordered = values[order]
        equal = ordered[1:] == ordered[:-1]
        if ordered.dtype.kind == "f":
            equal |= np.isnan(ordered[1:]) & np.isnan(ordered[:-1])
        same &= equal
    return bool(same.any())


def check_no_duplicate_readings(
    profile, path, keys=("depth_mm", "side", "distance_image_mm"), problems=None
):
    """Refuse a reading given twice (same depth, side and distance).

    Parameters
    ----------
    profile : pandas.DataFrame or tuple
        Output of :func:`read_table` for one profile file (rows in file order),
        or the ``(columns, lines)`` of :func:`read_columns`.
    path : str
        File name used in the message.
    keys : tuple of str
        Columns that identify a reading.
    problems : Problems, optional
        Collector to add the problem to; without one, it is raised.

    Raises
    ------
    InputError
        Without a collector: naming both lines of the first duplicate and the
        columns that coincide (and how many more readings repeat).
    """
    with collecting(problems) as found:
        _check_no_duplicates(profile, path, keys, found)


def _check_no_duplicates(profile, path, keys, found):
    columns = profile[0] if isinstance(profile, tuple) else profile
    if not _may_repeat(columns, keys):
        return
    import pandas as pd  # only to name a duplicate, as it always has

    if isinstance(profile, tuple):
        profile = pd.DataFrame(profile[0], index=pd.Index(profile[1], name="line"))
    duplicated = profile.duplicated(subset=list(keys), keep="first").to_numpy()
    if duplicated.any():
        i = int(np.argmax(duplicated))
        row = profile.iloc[i]
        same = (profile[list(keys)] == row[list(keys)]).all(axis=1).to_numpy()
        first = int(np.argmax(same))
        reading = ", ".join(
            f"{k}={row[k]:g}" if isinstance(row[k], float) else f"{k}={row[k]}" for k in keys
        )
        found.error(
            path,
            profile.index[i],
            list(keys),
            f"duplicate reading ({reading}) already given on line {profile.index[first]}; "
            "expected one reading per depth, side and distance"
            + _more(list(profile.index), duplicated, "repeated readings"),
        )


def check_subjects(
    subjects,
    path,
    profile_dir,
    profile_dir_shown=None,
    problems=None,
    id_pattern=None,
    photographed=(),
):
    """Rules on the subject sheet that span rows or files.

    Subject ids must be unique, and each listed subject must have its profile
    file ``<profile_dir>/<subject>.csv``.  When it has none but a file is named
    like it up to case, spaces or extension (``S-01.CSV``, ``s-01.csv``,
    ``S-01.txt``), the message shows that file beside the expected name.

    Parameters
    ----------
    subjects : pandas.DataFrame
        Output of :func:`read_table` for ``subjects.csv``.
    path : str
        Name of the subject sheet in messages.
    profile_dir : str
        Folder of the profile files.
    profile_dir_shown : str, optional
        How to name that folder in messages.
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.
    id_pattern : re.Pattern, optional
        The schema's rule for ids: an id that breaks it is the schema's to report
        (it names no file), so no profile file is looked for.
    photographed : collection of str, optional
        Subjects with photographs in images/images.csv instead of a profile file (one
        with both is refused: which would be its readings?).

    Raises
    ------
    InputError
        Without a collector.
    """
    shown_dir = profile_dir_shown or profile_dir
    names = _files_in(profile_dir)
    with collecting(problems) as found:
        ids = subjects["subject"]
        duplicated = ids.duplicated().to_numpy()
        for i in np.flatnonzero(duplicated):
            first = int(np.argmax((ids == ids.iloc[i]).to_numpy()))
            found.error(
                path,
                ids.index[i],
                "subject",
                f"subject {ids.iloc[i]!r} is already listed on line {ids.index[first]}; "
                "expected unique ids",
            )
        # one line for every subject without its file: the first, and how many more
        missing = [
            (line, subject)
            for line, subject in ids[~duplicated].items()
            if (id_pattern is None or id_pattern.search(subject))
            and subject not in photographed
            and not os.path.isfile(os.path.join(profile_dir, f"{subject}.csv"))
        ]
        for line, subject in ids[~duplicated].items():
            if subject in photographed and os.path.isfile(
                os.path.join(profile_dir, f"{subject}.csv")
            ):
                found.error(
                    path,
                    line,
                    "subject",
                    f"subject {subject!r} has both a profile file ({shown_dir}/{subject}.csv) "
                    "and photographs (images/images.csv); expected one or the other",
                )
        if missing:
            line, subject = missing[0]
            message = f"no profile file for subject {subject!r}; expected {shown_dir}/{subject}.csv"
            near = _near_names(subject, names)
            if near:
                message += (
                    f", found {shown_dir}/{near[0]} (file names are matched exactly: "
                    "rename it, with the extension .csv in lower case)"
                )
            lines = [n for n, _ in missing]
            message += _more(lines, np.ones(len(lines), dtype=bool), "subjects without one")
            found.error(path, line, "subject", message)


def unlisted_files(folder, folder_shown, subjects, sheet_shown, what, problems):
    """Warn about files of a folder that no listed subject reads.

    A file named like a listed subject's file up to case, spaces or extension
    is named as such (it would otherwise be mistaken for that subject's data).

    Parameters
    ----------
    folder : str
        ``profiles/`` or ``outlines/`` of the raw folder.
    folder_shown : str
        How to name the folder in messages.
    subjects : iterable of str
        The ids listed in the subject sheet.
    sheet_shown : str
        How to name the subject sheet in messages.
    what : str
        ``profile`` or ``outline``.
    problems : Problems
        Collector the warnings are added to.
    """
    subjects = [str(s) for s in subjects]
    expected = {f"{s}.csv" for s in subjects}
    names = _files_in(folder)
    for name in names:
        if name in expected:
            continue
        owner = next((s for s in subjects if name in _near_names(s, [name])), None)
        if owner is not None:
            if what == "profile" and f"{owner}.csv" not in names:
                continue  # already an error: the subject's own file is missing
            message = (
                f"named like the {what} of subject {owner!r} but not exactly "
                f"{folder_shown}/{owner}.csv, so it is not read"
            )
        else:
            stem = os.path.splitext(name)[0]
            message = f"no subject {stem!r} in {sheet_shown} reads this {what} file; it is ignored"
        problems.warning(f"{folder_shown}/{name}", None, None, message)


# ---------------------------------------------------------------- a whole raw folder


def check_subject_files(
    raw_dir, schemas, subjects, magnifications, found, limits, window=None, raw_dir_shown=None
):
    """Check the profile and outline files of some subjects (all, or one batch's).

    Parameters
    ----------
    raw_dir : str
        The raw-data folder.
    schemas : dict
        Row schemas keyed ``profiles`` and ``outlines``.
    subjects : list of str
        Subjects with a profile file, in sheet order.
    magnifications : dict
        Subject -> magnification of the subject sheet.
    found : Problems
        Collector the problems are added to.
    limits : dict
        The plausibility limits (:func:`plausibility_defaults` with the config's).
    window : tuple, optional
        ``(fit_window_mm, min_points_in_window)``; thin trials not checked if None.
    raw_dir_shown : str, optional
        How to name the folder in messages (defaults to ``raw_dir``).

    Returns
    -------
    tuple
        ``depths_mm`` (subject -> sorted depths of its profile), ``outlines``
        (subject -> sorted depths of its outline, where it has one) and ``refused``
        (the set of subjects whose profile has a problem).
    """
    shown = raw_dir_shown or raw_dir

    def here(*parts):
        return os.path.join(raw_dir, *parts), "/".join([shown.rstrip("/"), *parts])

    depths_mm, outlines = {}, {}
    refused = set()  # subjects whose profile has a problem: their depths are not known
    for subject in subjects:
        magnification = float(magnifications[subject])
        if not magnification > 0:  # refused on the sheet already
            magnification = None
        path, path_shown = here("profiles", f"{subject}.csv")
        before = found.count()
        profile = read_columns(path, schemas["profiles"], path_shown, found)
        if profile is None:
            refused.add(subject)
            continue
        if found.count() == before:  # keys a cell rule refused would repeat as NaN
            check_no_duplicate_readings(profile, path_shown, problems=found)
        check_depth_range(
            profile,
            path_shown,
            limits["depth_min_mm"],
            limits["depth_max_mm"],
            magnification,
            found,
        )
        depths_mm[subject] = sorted(float(d) for d in set(profile[0]["depth_mm"]) if d == d)
        if found.count() > before:
            refused.add(subject)
        if found.count() == before and magnification:  # only a profile that is otherwise fine
            check_deflection_near_wedge(
                profile, path_shown, magnification, limits["deflection_factor"], found
            )
        if found.count() == before and magnification:  # then every reading, not the nearest
            check_reach(
                profile,
                path_shown,
                magnification,
                limits["reach_max_mm"],
                limits["deflection_factor"],
                found,
            )
        if found.count() == before and magnification and window is not None:
            check_thin_trials(profile, path_shown, magnification, *window, problems=found)
        path, path_shown = here("outlines", f"{subject}.csv")
        if os.path.isfile(path):
            outline = read_columns(path, schemas["outlines"], path_shown, found)
            if outline is not None:
                check_depth_range(
                    outline,
                    path_shown,
                    limits["depth_min_mm"],
                    limits["depth_max_mm"],
                    magnification,
                    found,
                )
                if magnification:
                    check_reach(
                        outline, path_shown, magnification, limits["reach_max_mm"], None, found
                    )
                outlines[subject] = sorted(float(d) for d in set(outline[0]["depth_mm"]) if d == d)
    return depths_mm, outlines, refused


def check_dataset(
    raw_dir,
    schemas,
    raw_dir_shown=None,
    plausibility=None,
    window=None,
    digitise=None,
    checked=None,
):
    """Validate a whole raw-data folder before anything is computed.

    Every file is checked, and every problem found is reported together.

    Parameters
    ----------
    raw_dir : str
        Folder with ``subjects.csv``, ``profiles/`` and optionally ``outlines/``
        and ``forces.csv``.
    schemas : dict
        Row schemas keyed ``subjects``, ``profiles``, ``outlines`` and
        (optionally) ``forces``.
    raw_dir_shown : str, optional
        How to name the folder in messages (defaults to ``raw_dir``).
    plausibility : dict, optional
        The config's ``input_checks`` (:func:`plausibility_defaults` for any not
        given).
    window : tuple, optional
        ``(fit_window_mm, min_points_in_window)`` of the config: a trial with
        fewer distinct distances within the window is refused
        (:func:`check_thin_trials`); not checked if None.
    digitise : dict, optional
        The config's ``digitise`` settings: each photograph pair is read once here
        (:func:`check_images`); not if None.
    checked : dict, optional
        The profiles and outlines already checked, batch by batch
        (:func:`check_subject_files` on every listed subject, in sheet order, merged):
        ``depths_mm``, ``outlines``, ``refused`` and their ``errors`` and
        ``warnings``, taken as they are instead of reading those files here; and
        ``photographs``, subject -> depths of its photograph pairs that passed
        (:func:`check_images` with ``read``), whose photographs are then not opened here.

    Returns
    -------
    dict
        ``subjects`` (the typed subject sheet), ``depths_mm`` (subject -> sorted
        list of depths), ``outlines`` (subject -> sorted list of depths with
        an outline file, for listed subjects that have one) and ``warnings``
        (lines about files that are not read).

    Raises
    ------
    InputError
        Holding every problem found (``problems``, one line each, naming file,
        line and column) and the warnings.
    """
    shown = raw_dir_shown or raw_dir
    limits = {**plausibility_defaults(), **(plausibility or {})}
    found = Problems()
    found.errors += links_outside(raw_dir, shown)  # refused before anything is opened
    found.raise_if_any()
    found.errors += near_miss_names(raw_dir, shown)

    def here(*parts):
        return os.path.join(raw_dir, *parts), "/".join([shown.rstrip("/"), *parts])

    sheet_path, sheet_shown = here("subjects.csv")
    subjects = read_table(sheet_path, schemas["subjects"], sheet_shown, found)
    if subjects is None:
        found.raise_if_any()
    profile_dir, profile_dir_shown = here("profiles")
    id_pattern = re.compile(schemas["subjects"]["properties"]["subject"]["pattern"])
    photographed = photographed_subjects(raw_dir)
    image_depths = {}
    if os.path.isfile(os.path.join(raw_dir, "images", "images.csv")):  # however it is saved
        image_depths = check_images(
            raw_dir,
            schemas.get("images") or _images_schema(),
            subjects["subject"],
            shown,
            found,
            digitise,
            limits,
            # checked batch by batch: the photographs were read there, the sheet is read here
            read=None if checked is None else (),
        )
    if checked is not None:
        image_depths.update(checked.get("photographs", {}))
    check_subjects(
        subjects, sheet_shown, profile_dir, profile_dir_shown, found, id_pattern, photographed
    )
    magnifications = dict(zip(subjects["subject"], subjects["magnification"], strict=True))
    listed = [
        s
        for s in dict.fromkeys(subjects["subject"])
        if id_pattern.search(s) and os.path.isfile(os.path.join(profile_dir, f"{s}.csv"))
    ]
    if checked is None:
        depths_mm, outlines, refused = check_subject_files(
            raw_dir, schemas, listed, magnifications, found, limits, window, shown
        )
    else:  # checked batch by batch (the same function), in the same order
        depths_mm, outlines = dict(checked["depths_mm"]), dict(checked["outlines"])
        refused = set(checked["refused"])
        found.errors.extend(checked["errors"])
        found.warnings.extend(checked["warnings"])
    depths_mm.update(image_depths)  # photographed subjects: the depths of their pairs
    _check_contact_lengths(subjects, sheet_shown, limits["reach_max_mm"], found)
    forces_schema = schemas.get("forces") or _forces_schema()
    with found.collect():  # (a check that raises is folded in the same way)
        check_forces(
            raw_dir,
            forces_schema,
            subjects,
            depths_mm,
            shown,
            problems=found,
            force_max_N=limits["force_max_N"],
            # a refused profile, a missing one, an id no file can have: reported already
            unknown_depths=refused | (set(subjects["subject"]) - set(listed) - set(image_depths)),
        )
    sheet_ids = [str(s) for s in subjects["subject"]]
    for folder in ("profiles", "outlines"):
        folder_path, folder_shown = here(folder)
        unlisted_files(folder_path, folder_shown, sheet_ids, sheet_shown, folder.rstrip("s"), found)
    found.raise_if_any()
    return {
        "subjects": subjects,
        "depths_mm": depths_mm,
        "outlines": outlines,
        "warnings": found.warnings,
    }
