"""Remember an input check that passed, so an unchanged dataset is not checked again.

The workflow validates its config and every raw file each time Snakemake reads
the Snakefile: before a build, a dry run or a rerun with nothing to do.  On a
large dataset that check costs more than the rest of the start-up, and it needs
pandas.  This module, which imports only the standard library, lets the
workflow skip it when nothing it depends on has changed.

A check is identified by a fingerprint: the SHA-256 of the config as given, the
code and schemas that do the checking, and the name and bytes of every file in
the raw-data folder (its top level, ``profiles/`` and ``outlines/``).  The
result of a passed check (the config with its defaults filled in and a plain
summary of the dataset) is stored under that fingerprint in a JSON file, with
a digest over both, so that anything but the exact, complete entry written by
:func:`store` is a miss.  A check that fails is never stored, so a broken input
fails on every run.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

__all__ = ["fingerprint", "load", "store"]

#: Sub-folders of the raw-data folder whose files the check reads.
RAW_SUBFOLDERS = ("", "profiles", "outlines")


def _files(folder):
    """Regular files directly inside ``folder``, sorted by name (none if missing)."""
    try:
        entries = sorted(os.scandir(folder), key=lambda entry: entry.name)
    except (FileNotFoundError, NotADirectoryError):
        return []
    return [entry for entry in entries if entry.is_file()]


def fingerprint(config, raw_dir, code_paths):
    """SHA-256 (hex) of everything an input check depends on.

    Parameters
    ----------
    config : dict
        The config as loaded, before validation fills in defaults.
    raw_dir : str or os.PathLike
        The raw-data folder.
    code_paths : iterable of str or os.PathLike
        Source files and schemas that define the check; editing one of them
        changes the fingerprint.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    digest = hashlib.sha256()

    def add(label, data):
        digest.update(f"{label}\0{len(data)}\0".encode())
        digest.update(data)

    add("config", json.dumps(config, sort_keys=True, default=repr).encode())
    for path in code_paths:
        add(f"code:{Path(path).name}", Path(path).read_bytes())
    add("raw", os.fspath(raw_dir).encode())
    for sub in RAW_SUBFOLDERS:
        for entry in _files(os.path.join(raw_dir, sub)):
            with open(entry.path, "rb") as handle:
                add(f"file:{sub}/{entry.name}", handle.read())
    return digest.hexdigest()


def _digest(key, result):
    """SHA-256 of a fingerprint and a result as stored (compact JSON, key order kept)."""
    text = json.dumps(result, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(f"{key}\0{text}".encode()).hexdigest()


def load(cache_path, key):
    """The stored result for ``key``, or None unless the file is an exact, complete match.

    The file must hold exactly a ``fingerprint`` equal to ``key``, a ``result``
    and the ``digest`` :func:`store` computed over both.  A missing or extra
    field, another fingerprint, an edited result, a truncated or unreadable file:
    all are misses, and the check simply runs again.

    Parameters
    ----------
    cache_path : str or os.PathLike
        The JSON file written by :func:`store`.
    key : str
        A fingerprint from :func:`fingerprint`.

    Returns
    -------
    dict or None
    """
    try:
        with open(cache_path, encoding="utf-8") as handle:
            stored = json.load(handle)
        if not isinstance(stored, dict) or set(stored) != {"fingerprint", "digest", "result"}:
            return None
        if stored["fingerprint"] != key or not isinstance(stored["result"], dict):
            return None
        if stored["digest"] != _digest(key, stored["result"]):
            return None
    except (OSError, ValueError, TypeError):
        return None
    return stored["result"]


def store(cache_path, key, result):
    """Write ``result`` under ``key`` with its digest, atomically; a failure to write is ignored.

    The cache only saves time, so a read-only working folder must not stop a
    build: if the file cannot be written, the check simply runs again next time.

    Parameters
    ----------
    cache_path : str or os.PathLike
        Where to write (its folder is created).
    key : str
        A fingerprint from :func:`fingerprint`.
    result : dict
        JSON-serialisable result of the check (no NaN or infinity).
    """
    cache_path = Path(cache_path)
    # Key order is kept: the result lists subjects in subject-sheet order.
    entry = {"fingerprint": key, "digest": _digest(key, result), "result": result}
    text = json.dumps(entry, indent=1, allow_nan=False)
    temporary = None
    try:
        cache_path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=cache_path.parent, prefix=".tmp-")
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            stream.write(text + "\n")
        os.replace(temporary, cache_path)
    except OSError:
        if temporary is not None:
            Path(temporary).unlink(missing_ok=True)
