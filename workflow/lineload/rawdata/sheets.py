"""Reading one contract table: its bytes, its header and each column against its schema.

A sheet is read as a lab's spreadsheet saves it: UTF-8 with or without a byte order
mark, quoted cells, blank rows and the empty columns a spreadsheet adds after the last
one are accepted; UTF-16, semicolons or tabs instead of commas, a header whose column
names differ only in case or spaces, ragged rows and numbers written with other
characters are refused with a line that names the file, the line and the column.  The
column rules of the table's row schema (``type``, ``enum``, ``pattern``,
``minimum``/``exclusiveMinimum``/``maximum``) are applied to whole columns at once, so
that thousands of files are read in seconds.
"""

from __future__ import annotations

import codecs
import csv
import os
import re

from lineload.rawdata.errors import InputError, _fail, _more, _shown, collecting
from lineload.runtime.lazy import lazy_import

# numpy when first used: Snakemake reads the subject sheet at start-up with this module
# (lineload.runtime.startup), where numpy may not be installed (snakemake --lint; lazy.py)
np = lazy_import("numpy")

__all__ = ["OTHER_SEPARATORS", "read_columns", "read_table"]


#: Separators that spreadsheets write instead of commas, with how messages name them.
OTHER_SEPARATORS = {";": "semicolons (';')", "\t": "tabs", "|": "vertical bars ('|')"}


def _expected_number(rules):
    bounds = []
    if "exclusiveMinimum" in rules:
        bounds.append(f"> {rules['exclusiveMinimum']:g}")
    if "minimum" in rules:
        bounds.append(f">= {rules['minimum']:g}")
    if "maximum" in rules:
        bounds.append(f"<= {rules['maximum']:g}")
    return "a number" + (" " + " and ".join(bounds) if bounds else "")


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
