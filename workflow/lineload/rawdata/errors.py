"""The raw-data check's error type, its collector and how problems are worded.

Standard library only: Snakemake imports this module when it reads the subject sheet at
start-up (:mod:`lineload.runtime.startup`, ``workflow/rules/common.smk``), where numpy may
not be installed (``snakemake --lint``; ``tests/test_lint_light.py``).

Every check function takes an optional ``problems`` collector (:class:`Problems`) and
adds one line per problem to it with ``problems.error(path, line, column, message)`` (or
``.warning``, for what is worth saying but does not stop a run).  Called without one, a
check collects its own problems (:func:`collecting`) and raises them together as one
:class:`InputError` at its end.  :func:`report_lines` turns the collected problems into
the lines printed for the user, at most :data:`MAX_REPORTED` errors.
"""

from __future__ import annotations

import contextlib

__all__ = [
    "MAX_REPORTED",
    "SHOWN_CHARACTERS",
    "InputError",
    "Problems",
    "collecting",
    "report_lines",
]


#: Errors printed for one run; beyond them a last line says how many more there are.
MAX_REPORTED = 20


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


#: Longest cell echoed whole in a message; a longer one is cut, with its length said.
SHOWN_CHARACTERS = 60


def _shown(value):
    """A cell as a message quotes it: cut to :data:`SHOWN_CHARACTERS` if longer."""
    if value == "":
        return "an empty cell"
    if len(value) > SHOWN_CHARACTERS:
        return f"{value[:SHOWN_CHARACTERS]!r}... ({len(value)} characters)"
    return repr(value)


def _more(lines, bad, what="cells of this column break the same rule"):
    """' (and 3 more ...: lines 7, 9, 12)' for the bad cells after the first; '' if none.

    ``lines`` holds each cell's line number and ``bad`` (a sequence of booleans, a numpy
    array as often as not) says which cells break the rule."""
    others = [line for line, is_bad in zip(lines, bad, strict=True) if is_bad][1:]
    if not others:
        return ""
    shown = ", ".join(str(n) for n in others[:3]) + (", ..." if len(others) > 3 else "")
    return f" (and {len(others)} more {what}: lines {shown})"
