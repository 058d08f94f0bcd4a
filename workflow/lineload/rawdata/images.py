"""Checks of the raw folder's ``images/``: the sheet ``images.csv`` and the photograph
pairs it names.

Every (subject, depth) needs one resting and one loaded photograph of one size and one
scale; each file must be an image of 8 or 16 bits inside the raw folder.  With the
config's ``digitise`` settings each pair is read as its job will read it, so that a
pair with no edge or no wedge, a copied view (the loaded photograph the resting one) or
swapped views are refused before any job runs.
"""

from __future__ import annotations

import codecs
import csv
import math
import os

from lineload.rawdata.errors import _shown, collecting
from lineload.rawdata.paths import _files_in, _outside_message, outside
from lineload.rawdata.plausibility import check_depth_range, plausibility_defaults
from lineload.rawdata.sheets import OTHER_SEPARATORS, _loose, read_table
from lineload.runtime.lazy import lazy_import

# numpy when first used: Snakemake lists the photographs at start-up with this module
# (photograph_files), where numpy may not be installed (snakemake --lint; lazy.py)
np = lazy_import("numpy")

__all__ = [
    "IMAGE_STATES",
    "NAME_MAX",
    "check_images",
    "image_properties",
    "image_scale_px_per_mm",
    "photograph_files",
    "photographed_subjects",
]


#: The states of a photograph pair, as images.csv names them.
IMAGE_STATES = ("rest", "loaded")


def photograph_files(raw_dir):
    """Subject -> the photographs images/images.csv names for it (paths, in sheet order;
    empty without the file), read as plain text before any check: what each subject's
    digitising job reads.  The raw-data check reports anything wrong with the sheet.

    Read leniently (a BOM, UTF-16, semicolons or tabs, ``File`` for ``file``): a sheet
    saved another way still says which subjects are photographed, so the check names
    what is wrong with it rather than a profile file those subjects never had.  A
    photograph whose path leads out of the raw folder is left out (never opened)."""
    path = os.path.join(raw_dir, "images", "images.csv")
    root = os.path.realpath(raw_dir)
    if not os.path.isfile(path) or outside(path, root):  # (a dataset without photographs)
        return {}
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError:
        return {}
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        text = data.decode("utf-16", errors="replace")
    else:
        text = data.decode("utf-8-sig", errors="replace")
    first = text.split("\n", 1)[0]
    delimiter = max([",", *OTHER_SEPARATORS], key=first.count)
    rows = list(csv.reader(text.splitlines(), delimiter=delimiter))
    header = [_loose(c) for c in rows[0]] if rows else []
    if not {"subject", "file"} <= set(header):
        return {}
    subject, name = header.index("subject"), header.index("file")
    files = {}
    for row in rows[1:]:
        if len(row) > max(subject, name) and row[subject].strip():
            photo = os.path.join(raw_dir, "images", row[name].strip())
            if not outside(photo, root):
                files.setdefault(row[subject].strip(), []).append(photo)
            else:
                files.setdefault(row[subject].strip(), [])
    return files


def photographed_subjects(raw_dir):
    """The subjects images/images.csv names: they have photographs, not a profile file."""
    return set(photograph_files(raw_dir))


def image_scale_px_per_mm(images):
    """Pixels per tissue mm of each row of images.csv: its ``pixels_per_mm``, or its
    scale bar's ``scale_bar_px / scale_bar_mm``; None if the table has neither."""
    if "pixels_per_mm" in images:
        return images["pixels_per_mm"].astype(float)
    if {"scale_bar_px", "scale_bar_mm"} <= set(images.columns):
        return images["scale_bar_px"].astype(float) / images["scale_bar_mm"].astype(float)
    return None


def image_properties(path):
    """Shape and data type of an image file, read from its header (None if unreadable)."""
    import imageio.v3 as iio  # here only: most datasets have no photographs

    try:
        properties = iio.improps(path)
    except Exception:  # any reader's failure: not an image this reader knows
        return None
    return tuple(properties.shape), np.dtype(properties.dtype)


def check_images(
    raw_dir,
    schema,
    subject_ids,
    raw_dir_shown=None,
    problems=None,
    digitise=None,
    plausibility=None,
    read=None,
    diagnose=None,
):
    """Check ``images/images.csv`` and the photographs it names.

    Every (subject, depth) needs one ``rest`` and one ``loaded`` photograph of the same
    size; each file must exist in ``images/`` and be a greyscale or colour image of 8 or
    16 bits; the sheet needs a scale; a subject must be listed in the subject sheet.

    Parameters
    ----------
    raw_dir : str
        The raw-data folder.
    schema : dict
        Row schema of images.csv.
    subject_ids : iterable of str
        The ids of the subject sheet.
    raw_dir_shown : str, optional
        How to name the folder in messages.
    problems : Problems, optional
        Collector; without one, problems are raised.
    digitise : dict, optional
        The config's ``digitise`` settings: each pair is then read as its job will read
        it, so that a photograph without an edge, without a wedge or without skin
        beyond ``reach_mm`` is refused here, before any job runs (reading a pair takes
        a few hundredths of a second); and its readings are held to the bounds of a
        profile file (:func:`lineload.rawdata.photographs.trial_problem`).
    plausibility : dict, optional
        The config's ``input_checks`` (:func:`plausibility_defaults` for any not
        given): the depths' range and the deflection factor.

    read : collection of str, optional
        The subjects whose photographs are opened (their files, pairs and readings
        checked); None for every listed subject.  The other rows are checked as rows
        of the sheet only: the raw-data check reads each batch's photographs in the
        batch's job, and the sheet in the job that gathers them.
    diagnose : callable, optional
        Takes each refused pair's photograph, what the digitiser saw and the refusal,
        and returns the refusal's line (:meth:`lineload.figures.diagnostic.Refusals.note`:
        the check_profiles job draws them into its log folder).

    Returns
    -------
    dict
        Subject -> sorted depths (mm) of its photograph pairs (of the subjects read);
        empty without images.csv.
    """
    shown = (raw_dir_shown or raw_dir).rstrip("/")
    limits = dict(plausibility or {})
    if not {"depth_min_mm", "depth_max_mm", "deflection_factor"} <= set(limits):
        limits = {**plausibility_defaults(), **limits}  # (reads the config schema: slow)
    sheet = os.path.join(raw_dir, "images", "images.csv")
    sheet_shown = f"{shown}/images/images.csv"
    if not os.path.isfile(sheet):
        return {}
    with collecting(problems) as found:
        before = found.count()
        images = read_table(sheet, schema, sheet_shown, found)
        if images is None or found.count() > before:
            return {}
        # depths in tissue mm, as a profile file's (1000 is micrometres)
        check_depth_range(
            images, sheet_shown, limits["depth_min_mm"], limits["depth_max_mm"], None, found
        )
        if found.count() > before:
            return {}
        truth_path = os.path.join(raw_dir, "images", "truth.csv")
        if os.path.isfile(truth_path):  # optional: the truth, where it is known
            from lineload.io import load_schema

            truth = read_table(truth_path, load_schema("truth"), f"{shown}/images/truth.csv", found)
            if truth is not None:
                for line, name in truth["subject"].items():
                    if str(name) not in set(map(str, subject_ids)):
                        found.error(
                            f"{shown}/images/truth.csv",
                            line,
                            "subject",
                            f"subject {name!r} is not in subjects.csv; expected a listed subject",
                        )
                        break
        scale = image_scale_px_per_mm(images)
        if scale is None:
            found.error(
                sheet_shown,
                None,
                None,
                "no scale: expected a column pixels_per_mm, or the columns scale_bar_px and "
                "scale_bar_mm (a scale bar's length in pixels and in tissue mm)",
            )
            return {}
        listed = set(map(str, subject_ids))
        depths, sizes = {}, {}
        for line, row in images.iterrows():
            subject, state, name = str(row["subject"]), str(row["state"]), str(row["file"])
            if subject not in listed:
                found.error(
                    sheet_shown,
                    line,
                    "subject",
                    f"subject {subject!r} is not in subjects.csv; expected a listed subject",
                )
                continue
            key = (subject, float(row["depth_mm"]))
            if state in sizes.setdefault(key, {}):
                found.error(
                    sheet_shown,
                    line,
                    "state",
                    f"a second {state} photograph of {subject} at {key[1]:g} mm; expected "
                    "one rest and one loaded photograph per depth",
                )
                continue
            if read is not None and subject not in read:
                continue
            path = os.path.join(raw_dir, "images", name)
            if problem := _photograph_file_problem(path, name, shown, raw_dir):
                found.error(sheet_shown, line, "file", problem)
                continue
            properties = image_properties(path)
            if properties is None:
                found.error(
                    sheet_shown,
                    line,
                    "file",
                    f"{shown}/images/{name} cannot be read as an image; expected a PNG or TIFF",
                )
                continue
            shape, dtype = properties
            grey = len(shape) == 2 or (len(shape) == 3 and shape[2] in (3, 4))
            if not grey or dtype not in (np.dtype(np.uint8), np.dtype(np.uint16)):
                found.error(
                    sheet_shown,
                    line,
                    "file",
                    f"{shown}/images/{name} is {'x'.join(map(str, shape))} of {dtype}; "
                    "expected a greyscale or colour image of 8 or 16 bits",
                )
                continue
            if "tip_x_px" in images and not float(row["tip_x_px"]) < shape[1]:
                found.error(
                    sheet_shown,
                    line,
                    "tip_x_px",
                    f"the tip at pixel column {float(row['tip_x_px']):g} is outside the image, "
                    f"which is {shape[1]} pixels wide",
                )
            sizes[key][state] = (line, shape[:2], path, float(scale.loc[line]), row)
        for (subject, depth), states in sizes.items():
            missing = [s for s in IMAGE_STATES if s not in states]
            if not states:  # both photographs refused: each has its line already
                continue
            if missing:
                line = next(iter(states.values()))[0]
                found.error(
                    sheet_shown,
                    line,
                    "state",
                    f"no {missing[0]} photograph of {subject} at {depth:g} mm; expected one rest "
                    "and one loaded photograph per depth",
                )
                continue
            (rest_line, rest_shape, rest_path, rest_ppmm, _) = states["rest"]
            (line, loaded_shape, loaded_path, ppmm, loaded_row) = states["loaded"]
            if not math.isclose(rest_ppmm, ppmm, rel_tol=1e-6):
                found.error(
                    sheet_shown,
                    rest_line,
                    "pixels_per_mm" if "pixels_per_mm" in images else "scale_bar_px",
                    f"the resting photograph of {subject} at {depth:g} mm is at "
                    f"{rest_ppmm:g} pixels per mm, the loaded one (line {line}) at {ppmm:g}; "
                    "expected one scale for the pair (the digitiser registers them pixel "
                    "for pixel): a zoomed view, or a scale copied from another row?",
                )
                continue
            if rest_shape != loaded_shape:
                found.error(
                    sheet_shown,
                    line,
                    "file",
                    f"the loaded photograph of {subject} at {depth:g} mm is "
                    f"{loaded_shape[0]} x {loaded_shape[1]} pixels, the rest one "
                    f"{rest_shape[0]} x {rest_shape[1]}; expected the same size (one camera)",
                )
                continue
            if digitise is not None:
                problem = _digitising_problem(
                    rest_path,
                    loaded_path,
                    ppmm,
                    loaded_row,
                    digitise,
                    shown,
                    raw_dir,
                    depth,
                    limits["deflection_factor"],
                    diagnose,
                )
                if problem:
                    found.error(sheet_shown, line, "file", problem)
                    continue
            depths.setdefault(subject, []).append(depth)
        return {subject: sorted(d) for subject, d in depths.items()}


#: The longest file name most file systems allow (bytes of one path component).
NAME_MAX = 255


def _photograph_file_problem(path, name, shown, raw_dir):
    """Why a photograph the sheet names cannot be read, from its name and header, or None."""
    from lineload.rawdata.photographs import photograph_problem

    longest = max(name.replace("\\", "/").split("/"), key=lambda part: len(part.encode()))
    if len(longest.encode()) > NAME_MAX:
        return (
            f"the file name {_shown(longest)} is {len(longest.encode())} bytes long; "
            f"expected at most {NAME_MAX} (the longest name a file system allows)"
        )
    if target := outside(path, os.path.realpath(raw_dir)):
        return _outside_message(f"{shown}/images/{name}", target, shown)
    if not os.path.isfile(path):
        if os.path.exists(path):
            return f"{shown}/images/{name} is not a regular file; expected the photograph"
        near = [
            other
            for other in _files_in(os.path.dirname(path))
            if other.lower() == os.path.basename(path).lower()
        ]
        hint = f" (there is {near[0]!r}: names differ in case)" if near else ""
        return f"no file {shown}/images/{name}{hint}; expected the photograph"
    return photograph_problem(path, f"{shown}/images/{name}")


def _digitising_problem(
    rest_path,
    loaded_path,
    ppmm,
    loaded_row,
    settings,
    shown,
    raw_dir,
    depth_mm,
    factor,
    diagnose=None,
):
    """Why a pair cannot be read, or is no plausible indentation (one line), or None.

    The pair is read as its job reads it, over the same distances, and its readings held
    to the profile files' bounds (:func:`lineload.rawdata.photographs.trial_problem`).
    ``diagnose`` (:meth:`lineload.figures.diagnostic.Refusals.note`), when given, takes
    each refusal with the photograph and what the digitiser saw, and returns its line."""
    from lineload.rawdata.photographs import (
        ImageError,
        digitise_photographs,
        read_photograph,
        trial_problem,
    )
    from lineload.rawdata.readings import reading_distances_mm

    paths = (rest_path, loaded_path)
    names = [path.replace(raw_dir.rstrip("/"), shown, 1) for path in paths]
    grid = reading_distances_mm(settings["reach_mm"], settings["first_mm"])
    try:
        images = [read_photograph(path, name) for path, name in zip(paths, names, strict=True)]
    except ImageError as error:
        return str(error)

    def read(rest, loaded):
        return digitise_photographs(
            rest, loaded, ppmm, grid, settings, tip_x_px=loaded_row.get("tip_x_px"), names=names
        )

    def refused(message, seen):
        if diagnose is None or seen is None:
            return message
        return diagnose(images[seen.get("failed", 1)], seen, message)

    try:
        trial = read(*images)
    except ImageError as error:
        seen = getattr(error, "seen", None)
        if "the wedge was not found" not in str(error):
            return refused(str(error), seen)
        try:  # the resting photograph shows the notch: the two swapped
            read(*images[::-1])
        except ImageError:
            return refused(
                f"{error}; is the loaded photograph the resting one (copied over it)?"
                if "notch" in str(error)
                else str(error),
                seen,
            )
        return refused(
            f"{error}; the resting photograph shows it: are rest and loaded swapped?", seen
        )
    problem = trial_problem(trial, depth_mm, factor, names)
    return refused(problem, trial.seen) if problem else None


def _images_schema():
    """The row schema of ``images/images.csv`` (for callers that pass none)."""
    from lineload.io import load_schema

    return load_schema("images")
