"""The commit a checkout is at, read from its ``.git`` files: no ``git`` process.

Snakemake reads the rules on every start (a rerun with nothing to do, too); the
bundle's file name carries the commit, and starting ``git`` for it cost more than
reading the three small files that say it.  Standard library only.
"""

from __future__ import annotations

import os
import re
import subprocess

__all__ = ["head_commit"]

_SHA = re.compile(r"[0-9a-f]{40}([0-9a-f]{24})?")


def _git_dir(directory):
    """The git folder of the checkout holding ``directory`` (its ``.git``, or where a
    worktree's ``.git`` file points), looked for upwards as git does; None if none."""
    folder = os.path.abspath(directory)
    while not os.path.exists(os.path.join(folder, ".git")):
        if os.path.dirname(folder) == folder:
            return None
        folder = os.path.dirname(folder)
    dot_git = os.path.join(folder, ".git")
    if os.path.isdir(dot_git):
        return dot_git
    with open(dot_git, encoding="utf-8") as handle:
        line = handle.readline().strip()
    if not line.startswith("gitdir:"):
        raise OSError(f"{dot_git}: not a gitdir link")
    return os.path.join(folder, line.split(":", 1)[1].strip())


def _ref(git_dir, common_dir, name):
    """The commit a ref names: its own file, else its line in packed-refs; None if neither."""
    for folder in (git_dir, common_dir):
        try:
            with open(os.path.join(folder, name), encoding="utf-8") as handle:
                return handle.read().strip()
        except (FileNotFoundError, NotADirectoryError):
            continue
    try:
        with open(os.path.join(common_dir, "packed-refs"), encoding="utf-8") as handle:
            for line in handle:
                sha, _, ref = line.strip().partition(" ")
                if ref == name:
                    return sha
    except FileNotFoundError:
        pass
    return None


def head_commit(directory):
    """The commit checked out where ``directory`` lies, or None outside a git checkout.

    Reads ``HEAD`` and the ref it names (loose or packed; a worktree's through its
    ``commondir``); anything else (a symbolic ref to a symbolic ref, an unusual layout)
    is asked of ``git rev-parse HEAD``.

    Parameters
    ----------
    directory : str or os.PathLike

    Returns
    -------
    str or None
        The full hexadecimal commit id.
    """
    directory = os.fspath(directory)
    try:
        git_dir = _git_dir(directory)
        if git_dir is None:
            return None
        common_dir = git_dir
        if os.path.isfile(os.path.join(git_dir, "commondir")):
            with open(os.path.join(git_dir, "commondir"), encoding="utf-8") as handle:
                common_dir = os.path.join(git_dir, handle.read().strip())
        with open(os.path.join(git_dir, "HEAD"), encoding="utf-8") as handle:
            head = handle.read().strip()
        sha = _ref(git_dir, common_dir, head[4:].strip()) if head.startswith("ref:") else head
        if sha and _SHA.fullmatch(sha):
            return sha
    except OSError:
        pass
    try:
        return subprocess.run(
            ["git", "-C", directory, "rev-parse", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None
