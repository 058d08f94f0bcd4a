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

__all__ = [
    "PACKAGES",
    "file_sha256",
    "git_state",
    "package_versions",
    "provenance_record",
    "to_json",
]

#: Distributions whose versions are recorded (the pinned dependencies that run the build).
PACKAGES = ("snakemake", "numpy", "scipy", "pandas", "matplotlib", "pyyaml")


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
        Folder of the workflow's source (for the git state).

    Returns
    -------
    dict
        ``raw_data`` (folder and SHA-256 per file, keyed by path relative to the
        folder), ``config``, ``python``, ``packages`` and ``git``.
    """
    hashes = {
        Path(path).relative_to(raw_dir).as_posix(): file_sha256(path) for path in sorted(raw_files)
    }
    return {
        "raw_data": {"folder": str(raw_dir), "sha256": dict(sorted(hashes.items()))},
        "config": config,
        "python": platform.python_version(),
        "packages": package_versions(),
        "git": git_state(source_dir),
    }


def to_json(record):
    """Stable JSON text: sorted keys, two-space indent, trailing newline."""
    return json.dumps(record, indent=2, sort_keys=True) + "\n"
