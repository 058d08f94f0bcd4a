"""What a build was made from: input hashes, settings, software, source version.

Nothing here records a time, so the provenance file of two builds from the same
inputs, settings, software and commit is byte-identical.
"""

from __future__ import annotations

import hashlib
import json
import platform
import subprocess
from importlib import metadata
from pathlib import Path

from lineload.runtime.startup import portable_path

__all__ = [
    "PACKAGES",
    "file_sha256",
    "git_state",
    "package_versions",
    "provenance_record",
    "to_json",
    "verify",
    "verify_main",
]

#: Distributions whose versions are recorded (the pinned dependencies that run the build).
PACKAGES = ("snakemake", "numpy", "scipy", "pandas", "matplotlib", "pyyaml", "typst", "rocrate")


def file_sha256(path):
    """SHA-256 of a file's bytes, as 64 hex digits."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def package_versions(names=PACKAGES):
    """Installed version of each distribution (``None`` if absent), without importing it."""
    versions = {}
    for name in names:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    return versions


def git_state(directory):
    """Commit checked out in ``directory`` and whether tracked files differ from it.

    Returns ``{"commit": None, "dirty": None}`` outside a git work tree or
    without git.  Untracked and ignored files (such as the results) do not
    count as changes.
    """

    def git(*args):
        return subprocess.run(
            ["git", "-C", str(directory), *args], capture_output=True, text=True, check=True
        ).stdout.strip()

    try:
        commit = git("rev-parse", "HEAD")
        dirty = bool(git("status", "--porcelain", "--untracked-files=no"))
    except (OSError, subprocess.CalledProcessError):
        return {"commit": None, "dirty": None}
    return {"commit": commit, "dirty": dirty}


def provenance_record(raw_dir, raw_files, config, source_dir):
    """Everything needed to say what a build was made from.

    Parameters
    ----------
    raw_dir : str
        Raw-data folder, as configured.
    raw_files : list of str
        Every raw input file (paths inside ``raw_dir``).
    config : dict
        The configuration in force (after defaults).
    source_dir : str
        Folder of the workflow's source (for the git state; not recorded).

    Returns
    -------
    dict
        ``raw_data``: the folder (relative to the working folder when inside it,
        else its name: no absolute path), ``folder_sha256`` (over every file's
        name and hash, so a folder outside the working folder is still named by
        its content) and ``sha256`` per file, keyed by path relative to the
        folder; ``config``, ``python``, ``packages`` and ``git``.
    """
    hashes = {
        Path(path).relative_to(raw_dir).as_posix(): file_sha256(path) for path in sorted(raw_files)
    }
    hashes = dict(sorted(hashes.items()))
    listing = "".join(f"{digest}  {name}\n" for name, digest in hashes.items())
    return {
        "raw_data": {
            "folder": portable_path(raw_dir),
            "folder_sha256": hashlib.sha256(listing.encode()).hexdigest(),
            "sha256": hashes,
        },
        "config": config,
        "python": platform.python_version(),
        "packages": package_versions(),
        "git": git_state(source_dir),
    }


def to_json(record):
    """Stable JSON text: sorted keys, two-space indent, trailing newline."""
    return json.dumps(record, indent=2, sort_keys=True) + "\n"


def verify(record, raw_dir=None):
    """Re-hash the raw files a provenance record names and say which do not match.

    Parameters
    ----------
    record : dict
        A provenance record (:func:`provenance_record`, as read from the JSON file).
    raw_dir : str or os.PathLike, optional
        Where the raw files are now; defaults to the folder the record names
        (relative to the current folder; a folder that was outside the
        working folder is recorded by name only, so give it here).

    Returns
    -------
    list of str
        One line per problem: a file missing, a file whose bytes differ, or a file in
        the folder's ``subjects.csv``, ``profiles/`` or ``outlines/`` that the record
        does not list.  Empty when everything matches.
    """
    folder = Path(raw_dir if raw_dir is not None else record["raw_data"]["folder"])
    recorded = record["raw_data"]["sha256"]
    problems = []
    for name, digest in sorted(recorded.items()):
        path = folder / name
        if not path.is_file():
            problems.append(f"missing: {path}")
        elif file_sha256(path) != digest:
            problems.append(f"differs from the record: {path}")
    present = [folder / "subjects.csv", folder / "NOTICE.txt"]
    present += sorted((folder / "profiles").glob("*.csv")) + sorted(
        (folder / "outlines").glob("*.csv")
    )
    for path in present:
        name = path.relative_to(folder).as_posix()
        if path.is_file() and name not in recorded:
            problems.append(f"not in the record: {path}")
    return problems


def verify_main(argv=None):
    """Command line: ``lineload-verify results/provenance.json [--raw FOLDER]``.

    Prints one line per raw file that does not match the record and exits with 1,
    or says that all match and exits with 0.
    """
    import argparse
    import sys

    parser = argparse.ArgumentParser(
        prog="lineload-verify",
        description="Re-hash the raw files named in a provenance record and list any that differ.",
    )
    parser.add_argument("record", help="a provenance.json written by the workflow")
    parser.add_argument("--raw", help="the raw-data folder (default: the one the record names)")
    args = parser.parse_args(argv)
    try:
        with open(args.record, encoding="utf-8") as handle:
            record = json.load(handle)
        problems = verify(record, args.raw)
    except (OSError, ValueError, KeyError) as error:
        print(f"Error: {args.record}: not a readable provenance record ({error})", file=sys.stderr)
        return 2
    for line in problems:
        print(line)
    if problems:
        print(f"{len(problems)} problem(s): these raw files are not the ones the results came from")
        return 1
    print(f"all {len(record['raw_data']['sha256'])} raw files match {args.record}")
    return 0
