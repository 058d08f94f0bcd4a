"""Reading schemas and writing reproducible, human-readable tables.

Every file the workflow writes goes through :func:`write_csv`, :func:`write_rows`,
:func:`write_columns` or :func:`write_text` (the two without pandas, and the
synthetic raw data, format their cells and leave the lines to :func:`csv_text`):
fixed float formatting, ``\\n`` line endings and an atomic rename, so two builds
give identical bytes and a failed step leaves no half-written file behind.
"""

from __future__ import annotations

import contextlib
import copy
import csv
import errno
import functools
import io
import json
import math
import numbers
import os
import re
import signal
import sys
import tempfile
import traceback
import warnings
from pathlib import Path

__all__ = [
    "FLOAT_FORMAT",
    "SCHEMA_DIR",
    "OutputError",
    "concatenate_csv",
    "config_defaults",
    "csv_text",
    "format_cell",
    "json_text",
    "load_schema",
    "output_to",
    "read_json",
    "read_rows",
    "read_trials",
    "replaced_atomically",
    "write_columns",
    "write_csv",
    "write_json_if_changed",
    "write_rows",
    "write_text",
]

#: The JSON schemas (YAML) of the config and of each raw-data table: workflow/schemas in
#: a checkout (where Snakemake's validate reads them too), the package's own copy when it
#: is installed (pip install ., pyproject.toml maps them into the package as
#: lineload/schemas).
SCHEMA_DIR = next(
    (
        folder
        for folder in (
            Path(__file__).resolve().parent / "schemas",
            Path(__file__).resolve().parents[1] / "schemas",
        )
        if folder.is_dir()
    ),
    Path(__file__).resolve().parents[1] / "schemas",
)

#: The process's file-creation mask (read once: os.umask can only be read by setting it).
_UMASK = os.umask(0o022)
os.umask(_UMASK)

#: Ten significant digits: exact enough to recompute any number downstream.
FLOAT_FORMAT = "%.10g"


def load_schema(name):
    """Load ``workflow/schemas/<name>.schema.yaml`` as a dict.

    Parameters
    ----------
    name : str
        ``config``, ``subjects``, ``profiles`` or ``outlines``.

    Returns
    -------
    dict
    """
    return copy.deepcopy(_parsed_schema(name))


@functools.cache
def _parsed_schema(name):
    """A schema parsed once per process, by libyaml where PyYAML has it.

    The config schema took 105 ms to parse in pure Python and 11 ms with libyaml (the
    same dict); the claims' settings read it twice.
    """
    import yaml

    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    with open(SCHEMA_DIR / f"{name}.schema.yaml", encoding="utf-8") as handle:
        return yaml.load(handle, Loader=loader)  # a safe loader, C or Python


def config_defaults(section):
    """The defaults the config schema gives the keys of one section (the one source).

    Parameters
    ----------
    section : str
        A top-level key of the config with ``properties``, e.g. ``claims``.

    Returns
    -------
    dict
        Key to default, for the keys that have one.
    """
    properties = load_schema("config")["properties"][section]["properties"]
    return {key: spec["default"] for key, spec in properties.items() if "default" in spec}


def read_results_csv(path):
    """Read a table the workflow wrote, keeping subject ids as text.

    Ids such as ``01`` or ``7`` would otherwise come back as numbers and stop
    matching the subject sheet.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    return pd.read_csv(path, dtype={"subject": str})


def write_text(text, path):
    """Write text atomically (temporary file in the same folder, then rename).

    Parameters
    ----------
    text : str
        Content; written as UTF-8 with ``\\n`` line endings.
    path : str or os.PathLike
        Destination; parent folders are created.
    """
    with replaced_atomically(path) as temporary:
        with open(temporary, "w", encoding="utf-8", newline="\n") as stream:
            stream.write(text)


def write_csv(frame, path, columns=None):
    """Write a DataFrame as CSV with fixed formatting, atomically.

    Parameters
    ----------
    frame : pandas.DataFrame
        Table to write (the index is not written).
    path : str or os.PathLike
        Destination.
    columns : list of str, optional
        Column order; defaults to the frame's.
    """
    text = frame.to_csv(
        index=False, columns=columns, float_format=FLOAT_FORMAT, lineterminator="\n"
    )
    write_text(text, path)


def format_cell(value):
    """One CSV cell as :func:`write_csv` (pandas with FLOAT_FORMAT) writes a column of its type.

    Parameters
    ----------
    value : None, bool, int, float, str or numpy scalar
        NaN and None give an empty cell; integers are written whole; other
        numbers with :data:`FLOAT_FORMAT`.

    Returns
    -------
    str
    """
    kind = type(value)
    if kind is float:  # the common cases first
        return "" if value != value else FLOAT_FORMAT % value
    if kind is str:
        return value
    if value is None:
        return ""
    if isinstance(value, bool) or getattr(getattr(value, "dtype", None), "kind", "") == "b":
        return str(bool(value))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        value = float(value)
        return "" if math.isnan(value) else FLOAT_FORMAT % value
    return str(value)


def write_rows(rows, columns, path):
    """Write dict rows as CSV, byte for byte as :func:`write_csv` would, without pandas.

    The per-subject fit jobs use it: they run once per subject, and importing
    pandas would cost them more than the fits themselves.

    Parameters
    ----------
    rows : iterable of dict
        One dict per row; a key missing from a row gives an empty cell.
    columns : list of str
        Column order (the header).
    path : str or os.PathLike
        Destination.
    """
    rows = list(rows)
    cells = [[format_cell(row.get(column)) for row in rows] for column in columns]
    write_text(csv_text(columns, cells), path)


#: Characters that make the csv module quote a cell (delimiter, quote, line ends).
_QUOTED = re.compile(r'[,"\r\n]')


def csv_text(names, cells, may_quote=None):
    """CSV text of cells already formatted, byte for byte as the csv module writes them.

    The one place the workflow's CSV writers (:func:`write_rows`,
    :func:`write_columns`, the synthetic raw data) turn cells into lines: ``,``
    between cells, ``\\n`` after every line, a cell quoted only where the csv
    module quotes it (a comma, quote or line end in it; an empty cell alone on
    its line).  When no cell needs that, the lines are plain joins, which is
    much faster for large tables.

    Parameters
    ----------
    names : sequence of str
        The header, one name per column.
    cells : sequence of sequence of str
        One sequence of cells per column, all of the same length.
    may_quote : sequence of sequence of str, optional
        The columns of ``cells`` that may hold a cell to quote (the caller knows
        that the others, numbers, never do); default every column.

    Returns
    -------
    str
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(names)
    may_quote = cells if may_quote is None else may_quote
    if len(names) > 1 and not any(_QUOTED.search("\x00".join(column)) for column in may_quote):
        # no cell the csv module would quote (nor is an empty cell in a row of
        # several): plain joins give its bytes
        rows = list(map(",".join, zip(*cells, strict=True)))
        if rows:
            buffer.write("\n".join(rows))
            buffer.write("\n")
    else:
        writer.writerows(zip(*cells, strict=True))
    return buffer.getvalue()


def _column_cells(values):
    """The cells of one column as :func:`write_csv` writes a column of that dtype."""
    import numpy as np  # here: the table-joining job imports no numpy

    kind = getattr(values, "dtype", None)
    kind = kind.kind if kind is not None else "O"
    if kind == "f" and values.size > 16 and not np.any(np.signbit(values) & (values == 0)):
        # a column of few distinct numbers (depths, distances) is formatted once per
        # number (-0.0, which unique would merge with 0.0, is written "-0": not here)
        distinct, index = np.unique(values, return_inverse=True)
        if 2 * distinct.size < values.size:
            text = np.array(_column_cells(distinct), dtype=object)
            return text[index.reshape(-1)].tolist()
    values = values.tolist()
    if kind == "f":
        return ["" if value != value else FLOAT_FORMAT % value for value in values]
    if kind in "iub":
        return [str(value) for value in values]
    return [value if type(value) is str else format_cell(value) for value in values]


def write_columns(columns, path, names=None):
    """Write columns of numpy arrays as CSV, byte for byte as :func:`write_csv` would.

    Floats get :data:`FLOAT_FORMAT` (NaN an empty cell), integers and booleans
    their text, text columns their strings; a column is formatted in one pass,
    without a DataFrame.

    Parameters
    ----------
    columns : mapping of str to numpy.ndarray
        Equal-length columns; text columns as object arrays of str.
    path : str or os.PathLike
        Destination.
    names : list of str, optional
        Column order (the header); defaults to the mapping's.
    """
    names = list(columns) if names is None else list(names)
    cells = [_column_cells(columns[name]) for name in names]
    text_cells = [  # numbers are never quoted
        column
        for name, column in zip(names, cells, strict=True)
        if getattr(getattr(columns[name], "dtype", None), "kind", "O") not in "fiub"
    ]
    write_text(csv_text(names, cells, text_cells), path)


def read_rows(path):
    """The rows of a small CSV table as dicts of text, without pandas.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    list of dict
        One dict per row, column name to the cell's text.
    """
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def read_trials(path, extra=()):
    """The trials of an averaged-profile table, without pandas.

    Parameters
    ----------
    path : str or os.PathLike
        A table written by rule ``prepare_profiles`` (columns ``subject``,
        ``depth_mm``, ``distance_mm`` and ``deflection_mm`` at least).
    extra : sequence of str, optional
        Further numeric columns to return after the deflections (e.g.
        ``("left_mm", "right_mm", "n_sides")``); an empty cell is NaN.

    Returns
    -------
    dict
        ``subject -> {depth_mm: (distance_mm, deflection_mm, *extra)}``, float
        arrays in file order; depths in increasing order, subjects in order of
        first appearance.

    Raises
    ------
    ValueError
        If a needed column is missing.
    """
    import numpy as np  # here: the table-joining job imports no numpy

    needed = ("subject", "depth_mm", "distance_mm", "deflection_mm", *extra)
    with open(path, newline="", encoding="utf-8") as handle:
        header = next(csv.reader(handle), [])
    missing = [name for name in needed if name not in header]
    if missing:
        raise ValueError(f"{path}: expected the columns {', '.join(missing)}")
    subject_column, *numeric_columns = (header.index(name) for name in needed)
    # numpy's C reader: a batch of a thousand subjects has ~10^5 rows
    read = functools.partial(
        np.loadtxt, path, delimiter=",", quotechar='"', skiprows=1, encoding="utf-8"
    )
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "loadtxt: input contained no data")
        subjects = read(usecols=subject_column, dtype=str, ndmin=1)
        numbers = np.column_stack(
            [
                _numbers(read, numeric_columns[:3]),
                *([_numbers(read, numeric_columns[3:])] if extra else []),
            ]
        )
    if not subjects.size:  # a header without rows
        return {}
    names, first, code = np.unique(subjects, return_index=True, return_inverse=True)
    # subjects in order of first appearance, depths increasing, rows in file order
    names = names[np.argsort(first)]
    appearance = np.argsort(np.argsort(first))[code.reshape(-1)]
    order = np.argsort(numbers[:, 0], kind="stable")
    order = order[np.argsort(appearance[order], kind="stable")]
    appearance, numbers = appearance[order], numbers[order]
    depth, *values = numbers.T
    starts = np.flatnonzero(
        np.r_[True, (np.diff(appearance) != 0) | (np.diff(depth) != 0)]
    ).tolist()
    trials = {}
    for start, stop in zip(starts, [*starts[1:], depth.size], strict=True):
        subject = str(names[appearance[start]])
        trials.setdefault(subject, {})[float(depth[start])] = tuple(
            np.ascontiguousarray(column[start:stop]) for column in values
        )
    return trials


def _numbers(read, columns):
    """Numeric columns read by ``read`` (a partial :func:`numpy.loadtxt`); a blank is NaN."""

    try:
        return read(usecols=columns, ndmin=2)
    except ValueError:
        # an empty cell (e.g. a side not read): read again with blanks made NaN (a
        # converter per cell, 4 times faster than reading text and converting it)
        return read(usecols=columns, ndmin=2, converters=_float_or_nan)


def _float_or_nan(text):
    """A cell's number, NaN for a blank cell."""
    return float(text) if text.strip() else float("nan")


def json_text(data):
    """JSON as the workflow writes it: two-space indent, key order kept, newline at the end.

    Parameters
    ----------
    data : JSON-serialisable object
        No NaN or infinity (they are not JSON).

    Returns
    -------
    str
    """
    return json.dumps(data, indent=2, ensure_ascii=False, allow_nan=False) + "\n"


def write_json_if_changed(data, path):
    """Write JSON unless the file already holds exactly that text; say whether it wrote.

    A file rewritten only when its content changes keeps its modification time,
    so a job that takes it as input reruns exactly when the values in it change.

    Parameters
    ----------
    data : JSON-serialisable object
    path : str or os.PathLike

    Returns
    -------
    bool
        True if the file was (re)written.
    """
    text = json_text(data)
    try:
        if Path(path).read_text(encoding="utf-8") == text:
            return False
    except (OSError, UnicodeDecodeError):
        pass
    write_text(text, path)
    return True


def read_json(path):
    """Read a JSON file written by :func:`write_json_if_changed` or :func:`json_text`.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    object
    """
    with open(path, encoding="utf-8") as handle:
        return json.load(handle)


@contextlib.contextmanager
def output_to(log_path):
    """Send a job's printed output and any traceback to its log file; exit cleanly on SIGTERM.

    A job stopped with SIGTERM (as a killed build stops its jobs) would otherwise end
    at once, without Python's clean-up, and could leave a temporary file of
    :func:`replaced_atomically` behind; here the signal raises SystemExit instead, so
    every ``finally`` and ``except`` runs first.

    Parameters
    ----------
    log_path : str or os.PathLike
        The job's log (created or overwritten).

    Yields
    ------
    io.TextIOBase
        The open log.
    """
    Path(log_path).parent.mkdir(parents=True, exist_ok=True)
    signal.signal(signal.SIGTERM, _exit_on_sigterm)
    with (
        open(log_path, "w", encoding="utf-8") as log,
        contextlib.redirect_stdout(log),
        contextlib.redirect_stderr(log),
    ):
        try:
            yield log
        except OSError as error:
            writing = isinstance(error, OutputError)
            hint = (_WRITE_HINTS if writing else _OTHER_HINTS).get(error.errno)
            with contextlib.suppress(OSError):  # a full disk may refuse the log too
                traceback.print_exc()
            if hint is None:
                raise
            # a sentence where the user looks, not a traceback: what, where, what to do
            where = _destination(error.filename2 or error.filename or "a file")
            verb = "write" if writing else "open"
            sys.__stderr__.write(f"Error: could not {verb} {where}: {error.strerror}; {hint}\n")
            raise SystemExit(1) from None
        except BaseException:
            traceback.print_exc()
            raise


class OutputError(OSError):
    """An output could not be written: the error of the write, naming the output."""


def _destination(path):
    """The file a temporary of :func:`replaced_atomically` stands for (else ``path``)."""
    found = _TEMPORARY.fullmatch(os.path.basename(str(path)))
    return os.path.join(os.path.dirname(str(path)), found.group(1)) if found else str(path)


#: The name mkstemp gives a temporary of replaced_atomically: ``.<name>.<random>.tmp``.
_TEMPORARY = re.compile(r"\.(.+)\.[A-Za-z0-9_]+\.tmp")

#: What to do when a job cannot write its output, by errno.
_WRITE_HINTS = {
    errno.ENOSPC: "the disk is full: free some space and run the same command again",
    errno.EDQUOT: "your disk quota is used up: free some space and run the same command again",
    errno.EROFS: "the results folder is on a read-only disk: choose another (--config results=...)",
    errno.EACCES: "no permission to write there: choose a results folder you can write to "
    "(--config results=...)",
    errno.EPERM: "no permission to write there: choose a results folder you can write to "
    "(--config results=...)",
    errno.EISDIR: "a folder stands where the file belongs: remove or rename it, then run again",
}
#: The same for an error that is not an output's (a file read, say): no advice about
#: the results folder, which it need not concern.
_OTHER_HINTS = {
    errno.ENOSPC: _WRITE_HINTS[errno.ENOSPC],
    errno.EDQUOT: _WRITE_HINTS[errno.EDQUOT],
    errno.EACCES: "no permission: check the permissions of the file and its folders",
    errno.EPERM: "no permission: check the permissions of the file and its folders",
    errno.EISDIR: "a folder stands where a file belongs: remove or rename it, then run again",
}


def concatenate_csv(paths, output):
    """Concatenate CSV tables with the same header, in the given order, without pandas.

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        Tables written by this package (at least one).
    output : str or os.PathLike
        Destination, written atomically.

    Returns
    -------
    int
        Number of data rows written.

    Raises
    ------
    ValueError
        If a table's header differs from the first one's.
    """
    header, n_rows = None, 0
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    for path in paths:
        with open(path, newline="", encoding="utf-8") as handle:
            reader = csv.reader(handle)
            this_header = next(reader, [])
            if header is None:
                header = this_header
                writer.writerow(header)
            elif this_header != header:
                raise ValueError(f"{path}: columns differ from {paths[0]}")
            for row in reader:
                writer.writerow(row)
                n_rows += 1
    write_text(buffer.getvalue(), output)
    return n_rows


def _exit_on_sigterm(signum, frame):
    raise SystemExit(128 + signum)


@contextlib.contextmanager
def replaced_atomically(path):
    """A temporary path beside ``path`` that replaces it when the block succeeds.

    A writer that is killed or fails halfway leaves the old file (or none), never a
    partial one: the new bytes appear under ``path`` in one rename.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; its folder is created.

    Yields
    ------
    str
        The temporary path to write to.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(
            dir=path.parent, prefix=f".{path.name}.", suffix=".tmp"
        )
    except OSError as error:
        raise OutputError(error.errno, error.strerror, str(path)) from error
    os.close(handle)
    try:
        yield temporary
        # mkstemp creates the file readable by its owner only; give it the usual mode
        os.chmod(temporary, 0o666 & ~_UMASK)
        os.replace(temporary, path)
    except OSError as error:
        Path(temporary).unlink(missing_ok=True)
        # a full disk names no file (write() knows none): this output is the one
        raise OutputError(error.errno, error.strerror, str(path)) from error
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
