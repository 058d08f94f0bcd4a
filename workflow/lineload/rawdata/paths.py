"""Where the raw files are: links that lead out of the raw folder, and near-miss names.

Nothing here opens a file: folders are listed and links followed, so Snakemake can call
these while it plans a run (standard library only).
"""

from __future__ import annotations

import os

from lineload.rawdata.sheets import _loose

__all__ = ["CONTRACT_NAMES", "DATA_FOLDERS", "links_outside", "near_miss_names", "outside"]


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
