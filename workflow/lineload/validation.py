"""Checks of the raw-data contract, with messages that point at the bad cell.

Each table of the contract (``subjects.csv``, ``profiles/<subject>.csv``,
``outlines/<subject>.csv``) has a JSON schema describing one row.  The column
rules of that schema (required columns, ``type``, ``enum``, ``pattern``,
``minimum``/``exclusiveMinimum``/``maximum``) are applied here to whole
columns at once, so that thousands of files validate in seconds, and every
failure is reported as one :class:`InputError` naming the file, the line
(the header is line 1) and the column, with what was expected and what was
found.  Rules that span rows (unique ids, duplicate readings, a profile file
for each subject) are checked here too, since a row schema cannot say them.
"""

from __future__ import annotations

import csv
import os
import re

import numpy as np

__all__ = [
    "InputError",
    "check_forces",
    "check_no_duplicate_readings",
    "check_subjects",
    "read_columns",
    "read_forces",
    "read_table",
]


class InputError(ValueError):
    """Raw input that breaks the data contract; the message says where and why."""


def _where(path, line, column):
    place = f"{path}, line {line}" if line is not None else f"{path}"
    if column is None:
        return place
    if isinstance(column, (list, tuple)):
        return place + ", columns " + ", ".join(f"'{c}'" for c in column)
    return f"{place}, column '{column}'"


def _fail(path, line, column, message):
    raise InputError(f"{_where(path, line, column)}: {message}")


def _expected_number(rules):
    bounds = []
    if "exclusiveMinimum" in rules:
        bounds.append(f"> {rules['exclusiveMinimum']:g}")
    if "minimum" in rules:
        bounds.append(f">= {rules['minimum']:g}")
    if "maximum" in rules:
        bounds.append(f"<= {rules['maximum']:g}")
    return "a number" + (" " + " and ".join(bounds) if bounds else "")


def _shown(value):
    return "an empty cell" if value == "" else repr(value)


def _to_float(text):
    try:
        return float(text)
    except ValueError:
        return np.nan


def _check_column(path, column, cells, lines, rules):
    """Apply one column's schema rules; return the typed column.

    ``cells`` holds the column's text in file order and ``lines`` each cell's
    line number; the first cell that breaks any rule is reported.  Plain
    Python and numpy keep this fast: thousands of files are read at start-up.
    """
    kind = rules.get("type", "string")
    if isinstance(kind, list):
        kind = next(k for k in kind if k != "null")
    if kind in ("number", "integer"):
        try:
            values = np.array(cells, dtype=float)
        except ValueError:  # some cell is not a number: find which, cell by cell
            values = np.array([_to_float(cell) for cell in cells], dtype=float)
        with np.errstate(invalid="ignore"):
            bad = ~np.isfinite(values)
            if kind == "integer":
                bad |= values != np.round(values)
            if "exclusiveMinimum" in rules:
                bad |= values <= rules["exclusiveMinimum"]
            if "minimum" in rules:
                bad |= values < rules["minimum"]
            if "maximum" in rules:
                bad |= values > rules["maximum"]
        if bad.any():
            i = int(np.argmax(bad))
            expected = _expected_number(rules)
            if kind == "integer":
                expected = expected.replace("a number", "an integer")
            _fail(path, lines[i], column, f"expected {expected}, got {_shown(cells[i])}")
        return values
    bad = np.zeros(len(cells), dtype=bool)
    expected = []
    distinct = set(cells)  # a column repeats few values: each is tested once
    if "enum" in rules:
        allowed = set(rules["enum"])
        if not distinct <= allowed:
            bad |= np.fromiter(
                (cell not in allowed for cell in cells), dtype=bool, count=len(cells)
            )
        expected.append(" or ".join(repr(v) for v in rules["enum"]))
    if "pattern" in rules:
        pattern = re.compile(rules["pattern"])
        if any(pattern.search(cell) is None for cell in distinct):
            bad |= np.fromiter(
                (pattern.search(cell) is None for cell in cells), dtype=bool, count=len(cells)
            )
        expected.append(rules.get("description", f"text matching {rules['pattern']}"))
    if bad.any():
        i = int(np.argmax(bad))
        _fail(path, lines[i], column, f"expected {', '.join(expected)}, got {_shown(cells[i])}")
    return np.array(cells, dtype=object)


#: Characters that stop the plain reading of a CSV file (quoted cells, other line ends,
#: NUL bytes): such files go through the csv module.
_NOT_PLAIN = re.compile(r'["\r\x00]')


#: A line with no cell that is not empty (a blank row).
_BLANK_LINE = re.compile(r"^,*$", re.MULTILINE)


def _plain_rows(path):
    """The non-blank rows of a plain CSV file, each with its line number, or None.

    A file is plain when it is UTF-8 without quotes, carriage returns or NUL
    bytes: then every line is one row and its cells are split at the commas,
    which is what the csv module makes of it, only faster.  Anything else
    returns None and is read by :func:`_csv_rows`.
    """
    with open(path, "rb") as handle:
        data = handle.read()
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return None
    if _NOT_PLAIN.search(text):
        return None
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()  # the end of the last line, not a row
    # without whitespace other than the line ends no cell needs stripping
    strip = any(character.isspace() for character in set(text) - {"\n"})
    if not strip and not _BLANK_LINE.search("\n".join(lines)):
        # no blank row to leave out: every line is a row
        return [line.split(",") for line in lines], list(range(1, len(lines) + 1)), False
    rows, numbers = [], []
    for number, line in enumerate(lines, start=1):
        if strip:
            if not line.replace(",", "").strip():
                continue  # a blank row (every cell empty or spaces)
        elif not line.replace(",", ""):
            continue
        rows.append(line.split(","))
        numbers.append(number)
    return rows, numbers, strip


def _csv_rows(path, shown):
    """The non-blank rows of a CSV file by the csv module, each with the line it starts on."""
    rows, numbers = [], []
    try:
        with open(path, newline="", encoding="utf-8-sig") as handle:
            reader = csv.reader(handle)
            while True:
                start = reader.line_num + 1  # a row may span lines: report where it starts
                row = next(reader, None)
                if row is None:
                    break
                if not any(cell.strip() for cell in row):
                    continue
                rows.append(row)
                numbers.append(start)
    except UnicodeDecodeError as error:
        _fail(
            shown,
            None,
            None,
            f"expected UTF-8 text, found a byte that is not ({error.reason} at byte {error.start})",
        )
    except csv.Error as error:
        _fail(shown, reader.line_num, None, f"expected comma-separated values ({error})")
    return rows, numbers, True


def read_columns(path, schema, display_path=None):
    """Read one contract table and check it against its row schema, as columns.

    :func:`read_table` without the DataFrame: the same checks and messages.

    Parameters
    ----------
    path : str or os.PathLike
        CSV file to read.
    schema : dict
        JSON schema of one row: ``properties`` (column rules) and ``required``.
    display_path : str, optional
        How to name the file in messages (defaults to ``path``).

    Returns
    -------
    tuple
        ``(columns, lines)``: a dict of column name to numpy array (schema
        columns typed, numbers as float, text as objects; in header order) and
        each row's line number in the file.

    Raises
    ------
    InputError
        As :func:`read_table`.
    """
    shown = display_path or os.fspath(path)
    if not os.path.isfile(path):
        _fail(shown, None, None, "file not found")
    found = _plain_rows(path)
    rows, lines, strip = found if found is not None else _csv_rows(path, shown)
    if not rows:
        _fail(
            shown,
            None,
            None,
            "file is empty; expected a header line naming the columns "
            + ", ".join(schema.get("required", [])),
        )
    header, header_line = [cell.strip() for cell in rows[0]], lines[0]
    rows, lines = rows[1:], lines[1:]
    for column in schema.get("required", []):
        if column not in header:
            _fail(
                shown,
                header_line,
                column,
                "missing from the header; expected columns " + ", ".join(schema["required"]),
            )
    if len(set(header)) != len(header):
        column = next(c for c in header if header.count(c) > 1)
        _fail(shown, header_line, column, "appears twice in the header")
    if not rows:
        _fail(shown, None, None, "has a header but no data rows; expected at least one data row")
    width = len(header)
    if set(map(len, rows)) != {width}:
        for row, line in zip(rows, lines, strict=True):
            if len(row) != width:
                _fail(
                    shown,
                    line,
                    None,
                    f"expected {width} comma-separated fields as in the header, got {len(row)}",
                )
    properties = schema.get("properties", {})
    columns = {}
    for name, cells in zip(header, zip(*rows, strict=True), strict=True):
        cells = [cell.strip() for cell in cells] if strip else list(cells)
        if name in properties:
            columns[name] = _check_column(shown, name, cells, lines, properties[name])
        else:
            columns[name] = np.array(cells, dtype=object)
    return columns, np.array(lines, dtype=np.int64)


def read_table(path, schema, display_path=None):
    """Read one contract table and check it against its row schema.

    Parameters
    ----------
    path : str or os.PathLike
        CSV file to read.
    schema : dict
        JSON schema of one row: ``properties`` (column rules) and ``required``.
    display_path : str, optional
        How to name the file in messages (defaults to ``path``).

    Returns
    -------
    pandas.DataFrame
        The table with schema columns typed (numbers as float, text as str) and
        any extra columns kept as text.  Its index is each row's line number in
        the file (the header is line 1 unless blank lines precede it), which
        later checks use in their messages.

    Raises
    ------
    InputError
        For a missing, empty or header-only file, a missing column, or the
        first cell that breaks a column rule.
    """
    import pandas as pd  # here only: the batch jobs read columns (read_columns) without it

    columns, lines = read_columns(path, schema, display_path)
    return pd.DataFrame(columns, index=pd.Index(lines, name="line"))


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


def check_no_duplicate_readings(profile, path, keys=("depth_mm", "side", "distance_image_mm")):
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

    Raises
    ------
    InputError
        Naming both lines and the columns that coincide.
    """
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
        _fail(
            path,
            profile.index[i],
            list(keys),
            f"duplicate reading ({reading}) already given on line {profile.index[first]}; "
            "expected one reading per depth, side and distance",
        )


def check_subjects(subjects, path, profile_dir, profile_dir_shown=None):
    """Rules on the subject sheet that span rows or files.

    Subject ids must be unique, and each listed subject must have its profile
    file ``<profile_dir>/<subject>.csv``.

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

    Raises
    ------
    InputError
    """
    shown_dir = profile_dir_shown or profile_dir
    ids = subjects["subject"]
    duplicated = ids.duplicated().to_numpy()
    if duplicated.any():
        i = int(np.argmax(duplicated))
        first = int(np.argmax((ids == ids.iloc[i]).to_numpy()))
        _fail(
            path,
            ids.index[i],
            "subject",
            f"subject {ids.iloc[i]!r} is already listed on line {ids.index[first]}; "
            "expected unique ids",
        )
    for line, subject in ids.items():
        if not os.path.isfile(os.path.join(profile_dir, f"{subject}.csv")):
            _fail(
                path,
                line,
                "subject",
                f"no profile file for subject {subject!r}; expected {shown_dir}/{subject}.csv",
            )


def check_dataset(raw_dir, schemas, raw_dir_shown=None):
    """Validate a whole raw-data folder before anything is computed.

    Parameters
    ----------
    raw_dir : str
        Folder with ``subjects.csv``, ``profiles/`` and optionally ``outlines/``.
    schemas : dict
        Row schemas keyed ``subjects``, ``profiles`` and ``outlines``.
    raw_dir_shown : str, optional
        How to name the folder in messages (defaults to ``raw_dir``).

    Returns
    -------
    dict
        ``subjects`` (the typed subject sheet), ``depths_mm`` (subject -> sorted
        list of depths) and ``outlines`` (subject -> sorted list of depths with
        an outline file, for listed subjects that have one).

    Raises
    ------
    InputError
        At the first rule broken, naming file, line and column.
    """
    shown = raw_dir_shown or raw_dir

    def here(*parts):
        return os.path.join(raw_dir, *parts), "/".join([shown.rstrip("/"), *parts])

    path, path_shown = here("subjects.csv")
    subjects = read_table(path, schemas["subjects"], path_shown)
    profile_dir, profile_dir_shown = here("profiles")
    check_subjects(subjects, path_shown, profile_dir, profile_dir_shown)
    depths_mm, outlines = {}, {}
    for subject in subjects["subject"]:
        path, path_shown = here("profiles", f"{subject}.csv")
        profile = read_columns(path, schemas["profiles"], path_shown)
        check_no_duplicate_readings(profile, path_shown)
        depths_mm[subject] = sorted(float(d) for d in set(profile[0]["depth_mm"]))
        path, path_shown = here("outlines", f"{subject}.csv")
        if os.path.isfile(path):
            outline, _ = read_columns(path, schemas["outlines"], path_shown)
            outlines[subject] = sorted(float(d) for d in set(outline["depth_mm"]))
    check_forces(raw_dir, schemas.get("forces") or _forces_schema(), subjects, depths_mm, shown)
    return {"subjects": subjects, "depths_mm": depths_mm, "outlines": outlines}


# ------------------------------------------------------------------ forces (optional)


def check_forces(raw_dir, schema, subjects, depths_mm, raw_dir_shown=None):
    """Check the optional ``forces.csv``: typed cells, known trials, one force per trial.

    Parameters
    ----------
    raw_dir : str
        The raw-data folder.
    schema : dict
        Row schema of ``forces.csv`` (``workflow/schemas/forces.schema.yaml``).
    subjects : pandas.DataFrame
        The checked subject sheet (:func:`read_table`).
    depths_mm : dict
        Subject -> depths of its profile file (mm).
    raw_dir_shown : str, optional
        How to name the folder in messages.

    Returns
    -------
    pandas.DataFrame or None
        The typed forces (index: line numbers), or None without the file.

    Raises
    ------
    InputError
        Naming the line and column of the first problem: a cell that breaks the
        schema (a force of zero or less, text), a subject not in the subject
        sheet, a depth with no profile for that subject, or a second force for
        the same subject and depth.
    """
    path = os.path.join(raw_dir, "forces.csv")
    if not os.path.isfile(path):
        return None
    shown = "/".join([(raw_dir_shown or raw_dir).rstrip("/"), "forces.csv"])
    forces = read_table(path, schema, shown)
    known = set(subjects["subject"])
    seen = {}
    for line, subject, depth_mm in zip(
        forces.index, forces["subject"], forces["depth_mm"], strict=True
    ):
        if subject not in known:
            _fail(
                shown,
                line,
                "subject",
                f"subject {subject!r} is not in subjects.csv; expected a listed subject",
            )
        profile_depths = depths_mm.get(subject, [])
        if not any(abs(depth_mm - d) <= 1e-9 * max(1.0, d) for d in profile_depths):
            listed = ", ".join(f"{d:g}" for d in profile_depths)
            _fail(
                shown,
                line,
                "depth_mm",
                f"no profile of subject {subject!r} at {depth_mm:g} mm; expected a depth of "
                f"profiles/{subject}.csv ({listed})",
            )
        key = (subject, round(float(depth_mm), 9))
        if key in seen:
            _fail(
                shown,
                line,
                ["subject", "depth_mm"],
                f"a second force for {subject!r} at {depth_mm:g} mm (the first is on line "
                f"{seen[key]}); expected one force per subject and depth",
            )
        seen[key] = line
    return forces


def read_forces(path):
    """Read a checked ``forces.csv`` as ``subject``, ``depth_mm``, ``force_N``.

    Parameters
    ----------
    path : str or os.PathLike
        A file that passed :func:`check_forces`.

    Returns
    -------
    pandas.DataFrame
        The three columns (any others dropped), in file order, default index.
    """
    from .io import load_schema

    table = read_table(path, load_schema("forces"))
    return table[["subject", "depth_mm", "force_N"]].reset_index(drop=True)


def _forces_schema():
    """The row schema of ``forces.csv`` (for callers that pass no ``forces`` schema)."""
    from .io import load_schema

    return load_schema("forces")
