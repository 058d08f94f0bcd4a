"""Checks of the raw-data contract, with messages that point at the bad cell.

Each table of the contract (``subjects.csv``, ``profiles/<subject>.csv``,
``outlines/<subject>.csv``, the optional ``forces.csv``) has a JSON schema
describing one row.  The column rules of that schema (required columns,
``type``, ``enum``, ``pattern``, ``minimum``/``exclusiveMinimum``/``maximum``)
are applied here to whole columns at once, so that thousands of files validate
in seconds, and every failure is reported as one line naming the file, the
line (the header is line 1) and the column, with what was expected and what
was found.  Rules that span rows (unique ids, duplicate readings, a profile
file for each subject, one force per trial) are checked here too, since a row
schema cannot say them, and so are the plausibility rules on magnitudes
(:func:`check_depth_range`, :func:`check_deflection_near_wedge`,
:func:`check_reach`, :func:`check_forces`), each with its limit in the config's
``input_checks`` (defaults from the config schema, the one source), and the
rule that a trial has enough readings to fit (:func:`check_thin_trials`).

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

import codecs
import contextlib
import csv
import math
import os
import re

from lineload.runtime.lazy import lazy_import

# numpy when first used: Snakemake reads the subject sheet at start-up with this module
# (lineload.runtime.startup), where numpy may not be installed (snakemake --lint; lazy.py)
np = lazy_import("numpy")

__all__ = [
    "MAX_REPORTED",
    "InputError",
    "Problems",
    "check_dataset",
    "check_deflection_near_wedge",
    "check_depth_range",
    "check_forces",
    "check_no_duplicate_readings",
    "check_reach",
    "check_subject_files",
    "check_subjects",
    "check_thin_trials",
    "collecting",
    "read_columns",
    "read_forces",
    "read_table",
    "report_lines",
    "unlisted_files",
]

#: Errors printed for one run; beyond them a last line says how many more there are.
MAX_REPORTED = 20


def plausibility_defaults():
    """The plausibility limits' defaults: the config schema's ``input_checks``."""
    from lineload.io import config_defaults

    return config_defaults("input_checks")


#: Separators that spreadsheets write instead of commas, with how messages name them.
OTHER_SEPARATORS = {";": "semicolons (';')", "\t": "tabs", "|": "vertical bars ('|')"}


class InputError(ValueError):
    """Raw input that breaks the data contract; the message says where and why.

    Parameters
    ----------
    problems : str or list of str
        One line per problem (``<file>, line N, column 'c': expected ..., got ...``).
    warnings : list of str, optional
        Lines worth reporting with the errors that do not stop a run by themselves.

    Attributes
    ----------
    problems, warnings : list of str
    """

    def __init__(self, problems, warnings=()):
        self.problems = [problems] if isinstance(problems, str) else list(problems)
        self.warnings = list(warnings)
        super().__init__("\n".join(self.problems))


class Problems:
    """The problems found in one pass over the inputs, in the order they were found.

    Attributes
    ----------
    errors : list of str
        Broken inputs: any of them stops the run.
    warnings : list of str
        Things a user should hear about that do not stop the run (a file no
        subject lists, for instance).
    """

    def __init__(self):
        self.errors = []
        self.warnings = []

    def error(self, path, line, column, message):
        """Add an error at a file, line (or None) and column (None, a name or a list)."""
        self.errors.append(f"{_where(path, line, column)}: {message}")

    def warning(self, path, line, column, message):
        """Add a warning, placed as :meth:`error` places an error."""
        self.warnings.append(f"{_where(path, line, column)}: {message}")

    @contextlib.contextmanager
    def collect(self):
        """Fold in the problems of a check that raises an :class:`InputError`."""
        try:
            yield self
        except InputError as error:
            self.errors.extend(error.problems)
            self.warnings.extend(error.warnings)

    def count(self):
        """Number of errors so far (compare before and after a check to see if it found any)."""
        return len(self.errors)

    def raise_if_any(self):
        """Raise every error found (with the warnings) as one :class:`InputError`."""
        if self.errors:
            raise InputError(self.errors, self.warnings)


@contextlib.contextmanager
def collecting(problems=None):
    """The collector a check adds to: the caller's, or its own that raises at the end.

    Every check function has the same shape::

        def check_something(table, path, problems=None):
            with collecting(problems) as found:
                ...
                found.error(path, line, column, "expected ..., got ...")
    """
    if problems is not None:
        yield problems
        return
    own = Problems()
    yield own
    own.raise_if_any()


def report_lines(error, limit=MAX_REPORTED):
    """The lines to print for a refused run: warnings, then at most ``limit`` errors.

    Parameters
    ----------
    error : InputError
    limit : int, optional

    Returns
    -------
    list of str
        ``Warning: ...`` lines, ``Error: ...`` lines, and when errors were left
        out a last line ``... and N more errors (fix these and run again)``.
    """
    lines = [f"Warning: {text}" for text in error.warnings]
    lines += [f"Error: {text}" for text in error.problems[:limit]]
    hidden = len(error.problems) - limit
    if hidden > 0:
        lines.append(
            f"... and {hidden} more error{'s' if hidden > 1 else ''} not shown "
            "(fix these and run again)"
        )
    return lines


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


#: Longest cell echoed whole in a message; a longer one is cut, with its length said.
SHOWN_CHARACTERS = 60


def _shown(value):
    """A cell as a message quotes it: cut to :data:`SHOWN_CHARACTERS` if longer."""
    if value == "":
        return "an empty cell"
    if len(value) > SHOWN_CHARACTERS:
        return f"{value[:SHOWN_CHARACTERS]!r}... ({len(value)} characters)"
    return repr(value)


def _to_float(text):
    try:
        return float(text)
    except ValueError:
        return np.nan


#: The characters a number in a raw file may be written with: digits, a point, a sign,
#: an exponent, and spaces around it (a space inside stops the reading anyway).  Python
#: (and numpy) would also read "9_9" as 99 and other scripts' digits as ours; a person
#: reads neither so.
_NUMBER_CHARACTERS = frozenset("0123456789.+-eE ")


def _not_plain_numbers(cells):
    """Which cells hold a character a plainly written number does not (None if none)."""
    if _NUMBER_CHARACTERS.issuperset("".join(cells)):  # one pass over the column
        return None
    return np.fromiter(
        (not _NUMBER_CHARACTERS.issuperset(cell) for cell in cells), dtype=bool, count=len(cells)
    )


def _more(lines, bad, what="cells of this column break the same rule"):
    """' (and 3 more ...: lines 7, 9, 12)' for the bad cells after the first; '' if none."""
    others = [lines[i] for i in np.flatnonzero(bad)[1:]]
    if not others:
        return ""
    shown = ", ".join(str(n) for n in others[:3]) + (", ..." if len(others) > 3 else "")
    return f" (and {len(others)} more {what}: lines {shown})"


def _check_column(path, column, cells, lines, rules, found):
    """Apply one column's schema rules; return the typed column.

    ``cells`` holds the column's text in file order and ``lines`` each cell's
    line number.  The first cell that breaks a rule is reported (with how many
    more do); a bad number becomes NaN.  Plain Python and numpy keep this fast:
    thousands of files are read at start-up.
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
            odd = _not_plain_numbers(cells)
            if odd is not None:
                bad |= odd
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
            hint = ""
            if odd is not None and odd[i]:
                hint = " (numbers are read as written with digits, '.', a sign and an exponent:"
                hint += " no digit separators or other characters)"
            found.error(
                path,
                lines[i],
                column,
                f"expected {expected}, got {_shown(cells[i])}{hint}" + _more(lines, bad),
            )
            values[bad] = np.nan
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
        found.error(
            path,
            lines[i],
            column,
            f"expected {', '.join(expected)}, got {_shown(cells[i])}" + _more(lines, bad),
        )
    return np.array(cells, dtype=object)


def _loose(name):
    """A header or file name as a person would read it: no case, spaces, '-' or '_'."""
    return re.sub(r"[\s_\-]+", "", name).lower()


def _other_separator(header_cells):
    """The separator a one-field header line was split by instead of commas, or None."""
    if len(header_cells) != 1:
        return None
    counts = {sep: header_cells[0].count(sep) for sep in OTHER_SEPARATORS}
    sep = max(counts, key=counts.get)
    return sep if counts[sep] else None


def _check_header(shown, header, header_line, schema, found):
    """Required columns present (with near misses shown as found), none named twice."""
    ok = True
    required = schema.get("required", [])
    sep = _other_separator(header)
    if sep is not None and not set(required) & set(header):
        found.error(
            shown,
            header_line,
            None,
            f"expected comma-separated values, found {OTHER_SEPARATORS[sep]} between the "
            "column names; export the sheet as CSV with commas (and decimal points, not "
            "decimal commas)",
        )
        return False
    for column in required:
        if column in header:
            continue
        near = [name for name in header if _loose(name) == _loose(column)]
        if near:
            message = (
                f"missing from the header; found {near[0]!r}, expected {column!r} "
                "(column names are matched exactly: case, spaces and '_' count)"
            )
        else:
            message = "missing from the header; expected columns " + ", ".join(required)
        found.error(shown, header_line, column, message)
        ok = False
    if len(set(header)) != len(header):
        column = next(c for c in header if header.count(c) > 1)
        found.error(shown, header_line, column, "appears twice in the header")
        ok = False
    return ok


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
        with open(path, "rb") as handle:
            start = handle.read(2)
        if start in (codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE):
            _fail(
                shown,
                None,
                None,
                "is UTF-16 text (it starts with UTF-16's byte order mark); expected UTF-8: "
                "save it as 'CSV UTF-8 (comma delimited)'",
            )
        _fail(
            shown,
            None,
            None,
            f"expected UTF-8 text, found a byte that is not ({error.reason} at byte {error.start})",
        )
    except csv.Error as error:
        _fail(shown, reader.line_num, None, f"expected comma-separated values ({error})")
    return rows, numbers, True


def read_columns(path, schema, display_path=None, problems=None):
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
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.

    Returns
    -------
    tuple or None
        ``(columns, lines)``: a dict of column name to numpy array (schema
        columns typed, numbers as float, text as objects; in header order) and
        each row's line number in the file.  With a collector, a bad number is
        NaN; None when the file cannot be read as a table at all (missing,
        empty, not comma-separated, a required column missing, ragged rows).

    Raises
    ------
    InputError
        As :func:`read_table`.
    """
    shown = display_path or os.fspath(path)
    with collecting(problems) as found:
        table = _read_columns(path, schema, shown, found)
    return table


def _drop_empty_nameless(shown, header, header_line, rows, found):
    """The header and rows without the columns that have no name and no value (the empty
    columns a spreadsheet may save after the last one); a nameless column holding a value
    is refused, naming its position.  Returns ``(header, rows, ok)``."""
    keep = []
    for i, name in enumerate(header):
        if name:
            keep.append(i)
            continue
        if any(i < len(row) and row[i].strip() for row in rows):
            found.error(
                shown,
                header_line,
                None,
                f"column {i + 1} has no name in the header but holds values; expected a "
                "name for every column that holds values",
            )
            return header, rows, False
    return (
        [header[i] for i in keep],
        [
            [row[i] for i in keep if i < len(row)] if len(row) == len(header) else row
            for row in rows
        ],
        True,
    )


def _read_columns(path, schema, shown, found):
    if not os.path.isfile(path):
        found.error(shown, None, None, "file not found")
        return None
    plain = _plain_rows(path)
    try:
        rows, lines, strip = plain if plain is not None else _csv_rows(path, shown)
    except InputError as error:  # not UTF-8, or a quote the csv module cannot read
        found.errors.extend(error.problems)
        return None
    if not rows:
        found.error(
            shown,
            None,
            None,
            "file is empty; expected a header line naming the columns "
            + ", ".join(schema.get("required", [])),
        )
        return None
    header, header_line = [cell.strip() for cell in rows[0]], lines[0]
    rows, lines = rows[1:], lines[1:]
    if "" in header:  # columns without a name: empty ones (a sheet's trailing commas) dropped
        header, rows, named = _drop_empty_nameless(shown, header, header_line, rows, found)
        if not named:
            return None
    if not _check_header(shown, header, header_line, schema, found):
        return None
    if not rows:
        found.error(
            shown, None, None, "has a header but no data rows; expected at least one data row"
        )
        return None
    width = len(header)
    if set(map(len, rows)) != {width}:
        ragged = np.array([len(row) != width for row in rows])
        i = int(np.argmax(ragged))
        found.error(
            shown,
            lines[i],
            None,
            f"expected {width} comma-separated fields as in the header, got {len(rows[i])}"
            + _more(lines, ragged, "rows with another number of fields"),
        )
        return None
    properties = schema.get("properties", {})
    columns = {}
    for name, cells in zip(header, zip(*rows, strict=True), strict=True):
        cells = [cell.strip() for cell in cells] if strip else list(cells)
        if name in properties:
            columns[name] = _check_column(shown, name, cells, lines, properties[name], found)
        else:
            columns[name] = np.array(cells, dtype=object)
    return columns, np.array(lines, dtype=np.int64)


def read_table(path, schema, display_path=None, problems=None):
    """Read one contract table and check it against its row schema.

    Parameters
    ----------
    path : str or os.PathLike
        CSV file to read.
    schema : dict
        JSON schema of one row: ``properties`` (column rules) and ``required``.
    display_path : str, optional
        How to name the file in messages (defaults to ``path``).
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.

    Returns
    -------
    pandas.DataFrame or None
        The table with schema columns typed (numbers as float, text as str) and
        any extra columns kept as text.  Its index is each row's line number in
        the file (the header is line 1 unless blank lines precede it), which
        later checks use in their messages.  With a collector, a bad number is
        NaN in the table; None when the file cannot be read as a table at all.

    Raises
    ------
    InputError
        Without a collector: for a missing, empty or header-only file, another
        separator than commas, a missing column, ragged rows, and the first
        cell of each column that breaks a column rule; every problem found in
        the file is in the one error.
    """
    import pandas as pd  # here only: the batch jobs read columns (read_columns) without it

    table = read_columns(path, schema, display_path, problems)
    if table is None:
        return None
    columns, lines = table
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


def _files_in(folder):
    """Names of the regular, non-hidden files directly in a folder (none if missing)."""
    try:
        return sorted(
            entry.name
            for entry in os.scandir(folder)
            if entry.is_file() and not entry.name.startswith(".")
        )
    except (FileNotFoundError, NotADirectoryError):
        return []


#: Sub-folders of the raw-data folder whose files the check reads ("" is the top level).
DATA_FOLDERS = ("", "profiles", "outlines", "images")


def outside(path, root_real):
    """Where ``path`` leads when that is outside the folder ``root_real`` (already resolved
    with ``os.path.realpath``), else None.  Nothing is opened: only links are followed."""
    target = os.path.realpath(path)
    if target == root_real or target.startswith(root_real.rstrip(os.sep) + os.sep):
        return None
    return target


def _outside_message(shown, target, root_shown):
    return (
        f"{shown} leads to {target}, outside the raw-data folder {root_shown}; expected "
        "every input inside it (copy the file in, or link the whole folder), nothing is "
        "read from elsewhere"
    )


def links_outside(raw_dir, raw_dir_shown=None):
    """Every entry of the folders the check reads whose link leads out of the raw folder.

    The raw folder is resolved once (it may itself be a link, as clusters arrange data);
    an entry (a file, a link to a file or to a device such as /dev/zero, or a link
    inside a linked sub-folder) that resolves outside it is listed, never opened.

    Parameters
    ----------
    raw_dir : str
        The raw-data folder.
    raw_dir_shown : str, optional
        How to name it in messages.

    Returns
    -------
    list of str
        One sentence per such entry, naming it and where it leads.
    """
    shown = (raw_dir_shown or raw_dir).rstrip("/") or "/"
    root = os.path.realpath(raw_dir)
    lines = []
    for sub in DATA_FOLDERS:
        folder = os.path.join(raw_dir, sub) if sub else raw_dir
        if sub and os.path.islink(folder) and (target := outside(folder, root)):
            lines.append(_outside_message(f"{shown}/{sub}", target, shown))
            continue
        try:
            entries = sorted(os.scandir(folder), key=lambda e: e.name)
        except OSError:  # missing, not a folder, or a link loop: reported where it is read
            continue
        for entry in entries:
            if entry.is_symlink() and (target := outside(entry.path, root)):
                name = "/".join(p for p in (shown, sub, entry.name) if p)
                lines.append(_outside_message(name, target, shown))
    return lines


#: The names the data contract gives (folder -> its expected entries), for near misses.
CONTRACT_NAMES = {
    "": ("subjects.csv", "profiles", "outlines", "images", "forces.csv", "NOTICE.txt"),
    "images": ("images.csv", "truth.csv"),
}


def _stem(name):
    """A name as a person would read it, and without a plural 's'."""
    loose = _loose(name)
    base, dot, ext = loose.rpartition(".")
    base, ext = (base, dot + ext) if dot else (loose, "")
    return base.rstrip("s") + ext


def near_miss_names(raw_dir, raw_dir_shown=None):
    """Entries of the raw folder named almost as the contract says (``Images`` for
    ``images``, ``image``, ``Subjects.CSV``), where the exact name is missing.

    Returns
    -------
    list of str
        One sentence each: what was found and the name expected.
    """
    shown = (raw_dir_shown or raw_dir).rstrip("/")
    lines = []
    for sub, expected in CONTRACT_NAMES.items():
        folder = os.path.join(raw_dir, sub) if sub else raw_dir
        try:
            present = sorted(os.listdir(folder))
        except OSError:
            continue
        for name in expected:
            if name in present:
                continue
            near = [p for p in present if p != name and _stem(p) == _stem(name)]
            if near:
                where = "/".join(p for p in (shown, sub, near[0]) if p)
                lines.append(
                    f"{where}: expected the name {name!r} (names are matched exactly: case "
                    "and a plural 's' count); rename it"
                )
    return lines


def _near_names(subject, names):
    """Files named like ``<subject>.csv`` up to case, spaces or the extension."""
    stem = _loose(subject)
    return [
        name
        for name in names
        if name != f"{subject}.csv"
        and _loose(os.path.splitext(name)[0]) == stem
        and os.path.splitext(name)[1].lower() in (".csv", ".txt", ".tsv", "")
    ]


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


# ---------------------------------------------------------------- photographs (optional)

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
    rest_path, loaded_path, ppmm, loaded_row, settings, shown, raw_dir, depth_mm, factor
):
    """Why a pair cannot be read, or is no plausible indentation (one line), or None.

    The pair is read as its job reads it, over the same distances, and its readings held
    to the profile files' bounds (:func:`lineload.rawdata.photographs.trial_problem`)."""
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

    try:
        trial = read(*images)
    except ImageError as error:
        if "the wedge was not found" not in str(error):
            return str(error)
        try:  # the resting photograph shows the notch: the two swapped
            read(*images[::-1])
        except ImageError:
            return (
                f"{error}; is the loaded photograph the resting one (copied over it)?"
                if "notch" in str(error)
                else str(error)
            )
        return f"{error}; the resting photograph shows it: are rest and loaded swapped?"
    return trial_problem(trial, depth_mm, factor, names)


# ---------------------------------------------------------------- plausibility of units


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


# ------------------------------------------------------------------ forces (optional)


def check_forces(
    raw_dir,
    schema,
    subjects,
    depths_mm,
    raw_dir_shown=None,
    problems=None,
    force_max_N=None,
    unknown_depths=(),
):
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
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.
    force_max_N : float, optional
        Largest plausible force (config ``input_checks: force_max_N``; the
        schema's default if None).
    unknown_depths : collection of str, optional
        Subjects whose profile was refused: their depths are not known, so a
        force is not checked against them (one mistake, one line).

    Returns
    -------
    pandas.DataFrame or None
        The typed forces (index: line numbers), or None without the file (or,
        with a collector, when it cannot be read as a table).

    Raises
    ------
    InputError
        Without a collector, naming the line and column of each problem: a
        cell that breaks the schema (a force of zero or less, text), a force
        above ``force_max_N``, a subject not in the subject sheet, a depth with
        no profile for that subject, or a second force for the same subject
        and depth.
    """
    path = os.path.join(raw_dir, "forces.csv")
    if not os.path.isfile(path):
        return None
    shown = "/".join([(raw_dir_shown or raw_dir).rstrip("/"), "forces.csv"])
    with collecting(problems) as found:
        forces = read_table(path, schema, shown, found)
        if forces is None:
            return None
        known = set(subjects["subject"])
        id_rule = schema.get("properties", {}).get("subject", {}).get("pattern", "")
        if force_max_N is None:
            force_max_N = plausibility_defaults()["force_max_N"]
        for line, force in zip(forces.index, forces["force_N"], strict=True):
            if force == force and force > force_max_N:
                found.error(shown, line, "force_N", _force_message(force, force_max_N))
        seen = {}
        for line, subject, depth_mm in zip(
            forces.index, forces["subject"], forces["depth_mm"], strict=True
        ):
            if not re.search(id_rule, subject) or depth_mm != depth_mm:
                continue  # a cell the schema refused: reported already
            if subject not in known:
                found.error(
                    shown,
                    line,
                    "subject",
                    f"subject {subject!r} is not in subjects.csv; expected a listed subject",
                )
                continue
            profile_depths = depths_mm.get(subject, [])
            if subject in unknown_depths:
                pass  # its profile's problem is reported already
            elif not any(abs(depth_mm - d) <= 1e-9 * max(1.0, d) for d in profile_depths):
                listed = ", ".join(f"{d:g}" for d in profile_depths)
                found.error(
                    shown,
                    line,
                    "depth_mm",
                    f"no profile of subject {subject!r} at {depth_mm:g} mm; expected a depth of "
                    f"profiles/{subject}.csv ({listed})",
                )
                continue
            key = (subject, round(float(depth_mm), 9))
            if key in seen:
                found.error(
                    shown,
                    line,
                    ["subject", "depth_mm"],
                    f"a second force for {subject!r} at {depth_mm:g} mm (the first is on line "
                    f"{seen[key]}); expected one force per subject and depth",
                )
            seen.setdefault(key, line)
    return forces


def _force_message(force_N, force_max_N):
    """What a force above the plausible limit is likely to be."""
    text = (
        f"expected a force of at most {force_max_N:g} N (config input_checks: force_max_N), "
        f"got {force_N:g}; "
    )
    if force_N / 1000 <= force_max_N:
        return text + f"it looks like millinewtons ({force_N:g} mN = {force_N / 1000:g} N)"
    return text + "force_N is in newtons"


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
    from lineload.io import load_schema

    table = read_table(path, load_schema("forces"))
    return table[["subject", "depth_mm", "force_N"]].reset_index(drop=True)


def _forces_schema():
    """The row schema of ``forces.csv`` (for callers that pass no ``forces`` schema)."""
    from lineload.io import load_schema

    return load_schema("forces")


def _images_schema():
    """The row schema of ``images/images.csv`` (for callers that pass none)."""
    from lineload.io import load_schema

    return load_schema("images")
