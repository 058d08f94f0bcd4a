"""What the workflow needs when Snakemake starts: the config, the subject sheet, the file list.

Snakemake reads the Snakefile on every start (a dry run, a rerun with nothing to
do, every cluster job), so what runs then must stay cheap: this module reads the
config and the subject sheet, and lists the raw folder, but never reads a
profile's bytes and never imports pandas.  Checking every raw file is the job of
the rule ``check_raw_data`` (``workflow/scripts/check_raw_data.py``).

It also says how a folder is named in what the workflow writes: relative to the
working folder when it lies inside it, else by its name alone
(:func:`portable_path`), so that moving or re-cloning the checkout changes no
job's params and no output.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import sys
from pathlib import Path

__all__ = [
    "RAW_SUBFOLDERS",
    "abort",
    "abort_inputs",
    "absent_folders",
    "data_folder",
    "folder_problem",
    "list_raw_files",
    "notice_text",
    "planned_folders",
    "portable_config",
    "portable_path",
    "read_subject_sheet",
    "remove_written",
    "schema_message",
    "where_to_look",
]

#: Sub-folders of the raw-data folder whose files the check reads ("" is the top level).
from lineload.rawdata.validation import DATA_FOLDERS as RAW_SUBFOLDERS


def abort(message):
    """Print one line for the user and stop with a non-zero exit, no traceback.

    Parameters
    ----------
    message : str
        What is wrong and where; printed after ``Error: ``.

    Raises
    ------
    SystemExit
        Always, with status 1.
    """
    sys.stderr.write(f"Error: {message}\n")
    raise SystemExit(1)


def abort_inputs(error):
    """Print every problem of an input error (one line each) and stop.

    Parameters
    ----------
    error : lineload.rawdata.validation.InputError

    Raises
    ------
    SystemExit
        Always, with status 1.
    """
    from lineload.rawdata.validation import report_lines

    sys.stderr.write("".join(f"{line}\n" for line in report_lines(error)))
    raise SystemExit(1)


def schema_message(error, what):
    """One line from a ``snakemake.utils.validate`` failure (a jsonschema error inside).

    Parameters
    ----------
    error : Exception
        The WorkflowError raised by ``validate``; its ``__context__`` is
        jsonschema's ValidationError when the data broke the schema.
    what : str
        How to name the validated thing (``config``).

    Returns
    -------
    str
        ``<what>, key '<path>': <message>``, with the allowed keys for an
        unknown key and the schema's description where there is one.
    """
    inner = error.__context__
    if not hasattr(inner, "absolute_path"):
        return f"{what}: {error}"
    where = "/".join(str(p) for p in inner.absolute_path)
    message = inner.message
    if inner.validator == "additionalProperties":
        allowed = ", ".join(sorted(inner.schema.get("properties", {})))
        message = f"{message}; expected only the keys {allowed}"
    elif "description" in inner.schema:
        message = f"{message} ({inner.schema['description'].rstrip('.')})"
    return f"{what}, key '{where}': {message}" if where else f"{what}: {message}"


#: The longest name of one file or folder most file systems allow (bytes), and the
#: longest path (Linux's PATH_MAX).
NAME_MAX = 255
PATH_MAX = 4096

#: The config's keys that name folders.
PATH_KEYS = ("raw_data", "results")


def _non_finite(value, where=()):
    """(key path, value) of the first NaN or infinity in a nested config, or None."""
    if isinstance(value, dict):
        items = value.items()
    elif isinstance(value, list | tuple):
        items = enumerate(value)
    else:
        if isinstance(value, float) and not math.isfinite(value):
            return where, value
        return None
    for key, item in items:
        if found := _non_finite(item, (*where, str(key))):
            return found
    return None


def path_problem(key, path):
    """What is wrong with the length of a configured path, or None.

    Parameters
    ----------
    key : str
        The config key (for the message).
    path : str
        Its value.

    Returns
    -------
    str or None
        One sentence naming the key, the over-long name and the limit.
    """
    for part in Path(path).parts:
        if len(os.fsencode(part)) > NAME_MAX:
            shown = part if len(part) <= 40 else f"{part[:30]}... ({len(part)} characters)"
            return (
                f"config, key '{key}': the name {shown!r} is {len(os.fsencode(part))} bytes "
                f"long; expected at most {NAME_MAX} (the longest name a file system allows)"
            )
    if len(os.fsencode(os.path.abspath(path))) > PATH_MAX:
        return (
            f"config, key '{key}': the path is {len(os.fsencode(os.path.abspath(path)))} "
            f"bytes long; expected at most {PATH_MAX} (the longest path Linux allows)"
        )
    return None


def config_problem(config):
    """What the schema check cannot see in a validated config, or None.

    A NaN passes every bound of a JSON schema (it compares false with everything), and
    an infinity passes a lower bound: both are refused here, naming the key; so is a
    folder whose name or path is longer than a file system allows.

    Parameters
    ----------
    config : dict
        The config, after ``snakemake.utils.validate``.

    Returns
    -------
    str or None
        One sentence in the form of :func:`schema_message`.
    """
    if found := _non_finite(config):
        where, value = found
        return (
            f"config, key '{'/'.join(where)}': {value} is not a finite number; "
            "expected a number (NaN and infinities are not values a setting can take)"
        )
    for key in PATH_KEYS:
        if isinstance(config.get(key), str) and (problem := path_problem(key, config[key])):
            return problem
    return None


def data_folder(path, repository):
    """The raw-data folder: as given, or the same relative path inside the workflow's repository.

    Parameters
    ----------
    path : str
        ``raw_data`` from the config.
    repository : str or os.PathLike
        The folder that holds ``workflow/`` (for a run with ``-s`` or
        ``--directory`` elsewhere, where the relative path is not found).

    Returns
    -------
    str
        ``path`` when it is absolute, exists, or has no counterpart in the
        repository; else the counterpart.
    """
    own = Path(repository) / path
    if Path(path).is_absolute() or Path(path).exists() or not own.is_dir():
        return path
    return str(own)


def folder_problem(raw_dir, results_dir):
    """What is wrong with where the raw data and the results lie, or None.

    The workflow writes only under the results folder and only reads the raw folder:
    the results may not be a file system's root or the home folder (every output would
    land among everything else there), the raw folder itself or inside it (derived files
    would mix with the data and be read as data), nor hold the raw folder (Snakemake
    would find the raw files among its own outputs), and it must be a folder the
    workflow can write (checked before anything is written).

    Parameters
    ----------
    raw_dir, results_dir : str
        The config's ``raw_data`` and ``results`` (relative to the working folder).

    Returns
    -------
    str or None
        One sentence naming the config key, the folder and what was expected.
    """
    raw, results = Path(raw_dir).resolve(), Path(results_dir).resolve()
    for folder, name in ((Path(results.anchor), "the root of the file system"),
                         (Path.home().resolve(), "the home folder")):  # fmt: skip
        if results == folder:
            return (
                f"config, key 'results': {results_dir!r} is {name}; "
                "expected a folder of its own for the outputs (e.g. results)"
            )
    if results == raw or raw in results.parents:
        where = "is the raw-data folder" if results == raw else "lies inside the raw-data folder"
        return (
            f"config, key 'results': {results_dir!r} {where} {raw_dir!r}; expected a "
            "folder outside it (the raw folder is only read, never written)"
        )
    if results in raw.parents:
        return (
            f"config, key 'raw_data': {raw_dir!r} lies inside the results folder "
            f"{results_dir!r}; expected the raw data outside the folder the workflow writes"
        )
    # the folder, or the nearest one above it that exists, must take new files
    existing = next(folder for folder in (results, *results.parents) if folder.exists())
    if not existing.is_dir() or not os.access(existing, os.W_OK | os.X_OK):
        why = (
            "is a file"
            if not existing.is_dir()
            else "cannot be written (read-only or no permission)"
        )
        return (
            f"config, key 'results': {results_dir!r} cannot be made, {str(existing)!r} {why}; "
            "expected a folder you can write to (--config results=...)"
        )
    return None


def read_subject_sheet(raw_dir, schema):
    """The subject sheet, checked against its row schema, as plain values.

    Only ``subjects.csv`` is read (numpy, no pandas).  Rules that span files
    (a profile for each subject, unique ids) are the raw-data check's.

    Parameters
    ----------
    raw_dir : str
        The raw-data folder, as the messages should name it.
    schema : dict
        The row schema of ``subjects.csv``.

    Returns
    -------
    dict of str to dict
        Subject id -> ``species``, ``magnification``, ``label`` (the optional
        ``label`` column, else the id) and ``contact_length_mm`` (None without
        that column), in sheet order; of ids listed twice, the first.

    Raises
    ------
    lineload.rawdata.validation.InputError
        Every problem of the sheet, one line each naming line and column.
    """
    from lineload.rawdata.validation import read_columns

    path = f"{raw_dir.rstrip('/')}/subjects.csv"
    try:
        columns, _ = read_columns(path, schema)
    except ModuleNotFoundError as missing:
        if missing.name != "numpy":
            raise
        # Snakemake without the workflow's environment (snakemake --lint where only
        # Snakemake is installed): the sheet as written; no job can run there, and the
        # raw-data check, which every job waits for, checks it in full
        columns = _plain_columns(path)
    rows = len(columns["subject"])
    labels = columns.get("label", [None] * rows)
    contact = columns.get("contact_length_mm", [None] * rows)
    subjects = {}
    for subject, species, magnification, label, length in zip(
        columns["subject"],
        columns["species"],
        columns["magnification"],
        labels,
        contact,
        strict=True,
    ):
        label = label.strip() if isinstance(label, str) else ""
        subjects.setdefault(
            str(subject),
            {
                "species": str(species),
                "magnification": float(magnification),
                "label": label or str(subject),
                "contact_length_mm": None if length is None else float(length),
            },
        )
    return subjects


def _plain_columns(path):
    """Column name -> its cells as written (standard library only; nothing checked)."""
    import csv

    with open(path, newline="", encoding="utf-8-sig") as handle:
        rows = list(csv.DictReader(handle))
    return {name: [row[name] for row in rows] for name in (rows[0] if rows else {})}


def list_raw_files(raw_dir):
    """Every regular file the raw-data check reads, by name; no file is opened.

    Parameters
    ----------
    raw_dir : str
        The raw-data folder.

    Returns
    -------
    dict
        ``all``: the path of every file at the top level, in ``profiles/``,
        ``outlines/`` and ``images/`` (sorted; a stray file is there too, so that
        its appearance reruns the check that warns about it); ``profiles`` and
        ``outlines``: file name -> path of the ``.csv`` files of each folder;
        ``images``: file name -> path of every file of ``images/``;
        ``forces`` and ``notice``: the path of ``forces.csv`` and
        ``NOTICE.txt``, or None.
    """
    from lineload.rawdata.validation import links_outside

    if away := links_outside(raw_dir):  # nothing is read from outside the dataset
        more = f" (and {len(away) - 1} more such links)" if len(away) > 1 else ""
        abort(away[0] + more)
    found = {"all": []}
    for sub in RAW_SUBFOLDERS:
        folder = os.path.join(raw_dir, sub) if sub else raw_dir
        try:
            names = sorted(e.name for e in os.scandir(folder) if _is_file(e))
        except (FileNotFoundError, NotADirectoryError):
            names = []
        except OSError as error:  # e.g. a symbolic link that leads back to itself
            abort(f"{folder}: the folder cannot be read ({error.strerror}); expected a folder")
        paths = {name: "/".join(p for p in (raw_dir.rstrip("/"), sub, name) if p) for name in names}
        found["all"] += paths.values()
        if sub == "images":  # the sheet and the photographs it names
            found[sub] = paths
        elif sub:
            found[sub] = {n: p for n, p in paths.items() if n.endswith(".csv")}
        else:
            found["forces"] = paths.get("forces.csv")
            found["notice"] = paths.get("NOTICE.txt")
    return found


def _is_file(entry):
    """Whether a folder entry is a file; a link that cannot be followed stops the run."""
    try:
        return entry.is_file()
    except OSError as error:  # a symbolic link loop, a file that vanished while listing
        abort(
            f"{entry.path}: cannot be followed ({error.strerror}); expected a file, or "
            "nothing: remove the link"
        )


def file_metadata(paths, raw_dir):
    """Size and modification time (ns) of each raw file, keyed by its path in the folder.

    The raw-data check records these for the files it checked
    (:func:`restored_files` compares them at the next start).

    Parameters
    ----------
    paths : iterable of str
        Files under ``raw_dir``.
    raw_dir : str

    Returns
    -------
    dict
        ``relative path -> [size, mtime_ns]``.
    """
    found = {}
    for path in paths:
        info = os.stat(path)
        found[os.path.relpath(path, raw_dir)] = [info.st_size, info.st_mtime_ns]
    return found


def check_record(log_path):
    """Where the raw-data check records the files it checked: beside its log.

    Not a declared output or log (Snakemake would create or remove it with the
    job): written only by a check that passes, read by :func:`restored_files`.
    """
    return os.path.join(os.path.dirname(log_path), "check_raw_data.files.json")


def restored_files(paths, raw_dir, record_path, checked_path):
    """Raw files that changed since the last check but look older than its results.

    Snakemake reruns a job when an input is newer than its outputs.  A file
    put back with its old time (``cp -p``, ``rsync -t``, a backup) is not, so
    the results would silently stay those of the other bytes.  Such a file
    differs in size or modification time from what the last check recorded,
    yet is no newer than the check's summary.

    Parameters
    ----------
    paths : iterable of str
        The raw files now (:func:`list_raw_files`'s ``all``).
    raw_dir : str
    record_path : str
        What the last successful check recorded (:func:`file_metadata`, JSON).
    checked_path : str
        The check's summary: its time is when the check ran.

    Returns
    -------
    list of str
        The paths of such files; empty without a record or a summary.
    """
    try:
        with open(record_path, encoding="utf-8") as handle:
            record = json.load(handle)
        checked_ns = os.stat(checked_path).st_mtime_ns
    except (OSError, ValueError):
        return []
    now = file_metadata(paths, raw_dir)
    return [
        os.path.join(raw_dir, name)
        for name, (size, mtime_ns) in now.items()
        if name in record and record[name] != [size, mtime_ns] and mtime_ns <= checked_ns
    ]


def notice_text(configured, notice_path):
    """The footer of figures and tables: as configured, else the first line of NOTICE.txt.

    Parameters
    ----------
    configured : str or None
        ``data_notice`` from the config.
    notice_path : str or None
        The raw folder's ``NOTICE.txt``, None without one.

    Returns
    -------
    str
        Empty for no footer.
    """
    if configured is not None:
        return configured
    if notice_path is None:
        return ""
    try:
        lines = Path(notice_path).read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as error:
        abort(
            f"{notice_path}: byte {error.start + 1} is not UTF-8 text "
            f"({error.object[error.start : error.start + 1]!r}); expected the notice as "
            "UTF-8: save the file with that encoding (or set data_notice in the config)"
        )
    return lines[0].strip() if lines else ""


def portable_path(path, workdir="."):
    """How the workflow names a folder in what it writes: no absolute path.

    Parameters
    ----------
    path : str or os.PathLike
    workdir : str or os.PathLike, optional
        The working folder (the current folder by default).

    Returns
    -------
    str
        The path relative to ``workdir`` when it lies inside it (``.`` for the
        folder itself), else the folder's name alone; what is in it is named by
        content hashes where it matters (the provenance record).
    """
    absolute = Path(os.path.abspath(path))
    base = Path(os.path.abspath(workdir))
    if absolute == base or base in absolute.parents:
        return absolute.relative_to(base).as_posix() or "."
    return absolute.name


def portable_config(config, workdir="."):
    """The config with its folders named by :func:`portable_path`, for params and outputs.

    Parameters
    ----------
    config : dict
    workdir : str or os.PathLike, optional

    Returns
    -------
    dict
        A copy; ``raw_data`` and ``results`` portable, every other key as given.
    """
    portable = dict(config)
    for key in ("raw_data", "results"):
        if isinstance(portable.get(key), str):
            portable[key] = portable_path(portable[key], workdir)
    return portable


def planned_folders(paths, root):
    """The folders under ``root`` (``root`` included) that would hold the given files.

    A path with wildcards (``results/fits/{batch}.csv``) counts up to its first
    wildcard: the folder that holds the wildcard part is planned, any folder named by a
    wildcard is not (only a job that runs makes one).

    Parameters
    ----------
    paths : iterable of str
        File paths or patterns (outputs, logs, benchmarks).
    root : str or os.PathLike
        The results folder.

    Returns
    -------
    set of pathlib.Path
        Absolute folders, ``root`` and the folders between it and each file.
    """
    root = Path(os.path.abspath(root))
    folders = {root}
    for path in filter(None, map(str, paths)):
        fixed = path.split("{", 1)[0]
        folder = Path(os.path.abspath(fixed if path != fixed else os.path.dirname(path)))
        if "{" in path and not fixed.endswith(("/", os.sep)):
            folder = folder.parent  # "fits/M{x}" names files in fits/
        if folder != root and root not in folder.parents:
            continue  # not under the results folder: never the run's to remove
        while folder != root:
            folders.add(folder)
            folder = folder.parent
    return folders


def absent_folders(folders):
    """Those of ``folders`` that do not exist yet (taken before anything is written)."""
    return sorted(folder for folder in folders if not folder.is_dir())


def remove_written(paths, folders):
    """Remove the files a refused run wrote, and the empty folders it made.

    Only what this run made is removed: the files it wrote (``paths``) and, deepest
    first, those of the folders it was about to write into that did not exist when it
    started (``folders``, from :func:`absent_folders`) and are empty now.  A folder
    that existed before the run, or holds anything, is kept, whatever lies around it.

    Parameters
    ----------
    paths : iterable of str
        Files written by this run (none now: the jobs' values are params, not files).
    folders : iterable of pathlib.Path
        Folders that did not exist when this run started.
    """
    for path in paths:
        Path(path).unlink(missing_ok=True)
    for folder in sorted(folders, key=lambda folder: -len(folder.parts)):
        with contextlib.suppress(OSError):  # not empty, or gone: kept as it is
            os.rmdir(folder)


def where_to_look(documents, report, built=()):
    """After a build: what it was asked for, and where the reader's documents are.

    Parameters
    ----------
    documents : list of (str, str)
        What each is and its path; only those that exist are named.
    report : str
        Path of the HTML report ``snakemake --report`` would write.
    built : list of (str, str), optional
        What the run's targets made (:func:`named_targets`), named first.

    Returns
    -------
    str
        Lines to print.
    """
    lines = ["", "Where to look:"]
    shown = [(what, path) for what, path in built if Path(path).exists()]
    lines += [f"  this run built {what}: {path}" for what, path in shown]
    lines += [
        f"  {what}: {path}"
        for what, path in documents
        if Path(path).is_file() and path not in {p for _, p in shown}
    ]
    lines.append(f"  the HTML report: snakemake --report {report}")
    return "\n".join(lines)


def named_targets(asked, targets):
    """What the targets asked for make, in the order of ``targets``.

    Parameters
    ----------
    asked : collection of str
        The targets of this run (Snakemake's ``workflow.dag_settings.targets``: rule
        names and files; empty for the default target).
    targets : dict
        Target (a rule's name) -> list of (what, path) it makes.

    Returns
    -------
    list of (str, str)
    """
    return [made for name, makes in targets.items() if name in asked for made in makes]


def report_argument(argv):
    """The file ``snakemake --report [FILE]`` writes (``report.html`` without one), or None.

    Parameters
    ----------
    argv : list of str
        The command line (``sys.argv``).

    Returns
    -------
    str or None
    """
    for i, word in enumerate(argv):
        if word.startswith("--report="):
            return word.split("=", 1)[1]
        if word == "--report":
            following = argv[i + 1] if i + 1 < len(argv) else ""
            return following if following and not following.startswith("-") else "report.html"
    return None


def say_where_the_report_is(path, started_ns=0):
    """After ``snakemake --report``: one line with the report's full path, if this run
    wrote it (a report older than ``started_ns``, left by an earlier run, is not named)."""
    if os.path.isfile(path) and os.stat(path).st_mtime_ns >= started_ns:
        sys.stderr.write(f"The report: {os.path.abspath(path)} (open it in a web browser)\n")
