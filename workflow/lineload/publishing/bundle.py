"""A build as one archive others can cite and check: the bundle's zip and its checksums.

The zip holds the results a reader needs, the raw data with their contract and the
workflow's source with its pinned requirements, and a ``SHA256SUMS`` file anyone can
check after unpacking (``sha256sum -c SHA256SUMS``) without installing anything.  Two
bundles of the same files are byte-identical: members in name order, every time stamp
the release date of the citation file (never the clock), fixed permissions, and no
other metadata.
"""

from __future__ import annotations

import datetime
import hashlib
import zipfile
from pathlib import PurePosixPath

from lineload.io import replaced_atomically
from lineload.publishing.provenance import file_sha256

__all__ = ["CHECKSUMS", "bundle_name", "checksums_text", "write_bundle"]

#: Name of the checksum file inside the bundle (the format of GNU ``sha256sum``).
CHECKSUMS = "SHA256SUMS"


def bundle_name(name, version, commit):
    """The bundle's file name: ``<name>-<version>-<short commit>.zip``.

    Parameters
    ----------
    name, version : str
        The software's name and version (from ``CITATION.cff``).
    commit : str or None
        The git commit built; ``None`` outside a git checkout (then ``nocommit``).
    """
    return f"{name}-{version}-{commit[:7] if commit else 'nocommit'}.zip"


def checksums_text(members):
    """``SHA256SUMS`` of the members: ``<sha256>  <name>`` per line, in name order.

    Parameters
    ----------
    members : dict
        Name in the bundle (POSIX, relative) -> path of the file to read, or its bytes.
    """
    return "".join(f"{_sha256(members[name])}  {name}\n" for name in sorted(members))


def _sha256(member):
    """SHA-256 of a member: a file's, or of the bytes given."""
    if isinstance(member, bytes):
        return hashlib.sha256(member).hexdigest()
    return file_sha256(member)


def _content(member):
    if isinstance(member, bytes):
        return member
    with open(member, "rb") as handle:
        return handle.read()


def _member_name(name):
    """Check a name for the zip: relative, POSIX, no '..' (the archive unpacks in place)."""
    path = PurePosixPath(name)
    if path.is_absolute() or ".." in path.parts or not path.parts or name == CHECKSUMS:
        raise ValueError(f"{name!r} cannot be a member of the bundle")
    return path.as_posix()


def write_bundle(members, destination, date):
    """Write the bundle: every member, then ``SHA256SUMS``, reproducibly.

    Parameters
    ----------
    members : dict
        Name in the bundle -> path of the file it copies, or the member's bytes.
    destination : str or os.PathLike
        The zip to write (it appears complete, or not at all).
    date : str
        ISO date (``YYYY-MM-DD``) stamped on every member (the citation file's
        ``date-released``).

    Returns
    -------
    str
        The text of ``SHA256SUMS``.
    """
    members = {_member_name(name): path for name, path in members.items()}
    day = datetime.date.fromisoformat(date)
    stamp = (day.year, day.month, day.day, 0, 0, 0)
    sums = checksums_text(members)

    def entry(name):
        info = zipfile.ZipInfo(name, date_time=stamp)
        info.compress_type = zipfile.ZIP_DEFLATED
        info.external_attr = 0o100644 << 16  # a regular file, rw-r--r--
        info.create_system = 3  # Unix, whichever system writes it
        return info

    with replaced_atomically(destination) as temporary:
        with zipfile.ZipFile(temporary, "w") as archive:
            for name in sorted(members):
                archive.writestr(entry(name), _content(members[name]), compresslevel=9)
            archive.writestr(entry(CHECKSUMS), sums.encode(), compresslevel=9)
    return sums
