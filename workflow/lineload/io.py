"""Reading schemas and writing reproducible, human-readable tables.

Every file the workflow writes goes through :func:`write_csv` (or
:func:`write_text`): fixed float formatting, ``\\n`` line endings and an
atomic rename, so two builds give identical bytes and a failed step leaves no
half-written file behind.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

__all__ = ["FLOAT_FORMAT", "SCHEMA_DIR", "load_schema", "write_csv", "write_text"]

#: The JSON schemas (YAML) of the config and of each raw-data table.
SCHEMA_DIR = Path(__file__).resolve().parents[1] / "schemas"

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
    import yaml

    with open(SCHEMA_DIR / f"{name}.schema.yaml", encoding="utf-8") as handle:
        return yaml.safe_load(handle)


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
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="\n") as stream:
            stream.write(text)
        # mkstemp creates the file readable by its owner only; give it the usual mode
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


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
