"""One build per results folder.

Snakemake's own lock lives in the working folder's ``.snakemake``: two builds started
from different working folders onto one results folder are not stopped by it, and
delete each other's outputs.  This lock lives in the results folder itself
(:data:`LOCK_NAME`), so it holds whatever the working folder, and says who holds it
(process id, host, working folder, start time).

It is an advisory lock of the operating system (``flock``) on that file, held by the
build's main process for as long as it runs: a build that is killed, even with
SIGKILL, lets go of it with its process, and the next build takes it over; the file
left behind only tells who held it last.  A file system without such locks (some
network mounts) leaves the build unlocked, as before.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import socket
import time

__all__ = ["LOCK_NAME", "acquire", "held_message", "lock_path", "release", "this_build"]

#: The lock's file in the results folder.
LOCK_NAME = ".lineload-build.lock"


def lock_path(results_dir):
    """The lock file of a results folder."""
    return os.path.join(results_dir, LOCK_NAME)


def this_build(targets=()):
    """Who this build is: process id, host, working folder, start time (UTC) and targets.

    Parameters
    ----------
    targets : iterable of str, optional
        What the build was asked for (Snakemake's ``workflow.dag_settings.targets``;
        none for the default target), written into the lock file for whoever finds it.

    Returns
    -------
    dict
    """
    return {
        "pid": os.getpid(),
        "host": socket.gethostname(),
        "cwd": os.getcwd(),
        "started": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()),
        "targets": sorted(map(str, targets)),
    }


def held_message(results_dir, holder):
    """The line a build refused by the lock prints: who holds the folder, and what to do.

    Parameters
    ----------
    results_dir : str
        The results folder (as configured).
    holder : dict or None
        What the lock file says of its holder (:func:`this_build`); None if unreadable.

    Returns
    -------
    str
    """
    if holder:
        who = (
            f"process {holder.get('pid')} on {holder.get('host')}, started "
            f"{holder.get('started')} in {holder.get('cwd')}"
        )
    else:
        who = "a build that has not yet said who it is"
    return (
        f"config, key 'results': another build is writing into {results_dir!r} ({who}); "
        "expected one build per results folder: wait for it to end, or give this one "
        "another folder (--config results=...). The lock is let go when that process "
        f"ends; if it runs on another machine and is gone, remove {lock_path(results_dir)}"
    )


def _holder(fd):
    """What the lock file open as ``fd`` says of its holder, or None."""
    try:
        os.lseek(fd, 0, os.SEEK_SET)
        return json.loads(os.read(fd, 65536).decode("utf-8"))
    except (OSError, ValueError):
        return None


def _same_file(fd, path):
    """Whether ``path`` still names the file open as ``fd`` (not removed and remade)."""
    try:
        here, there = os.fstat(fd), os.stat(path)
    except OSError:
        return False
    return (here.st_dev, here.st_ino) == (there.st_dev, there.st_ino)


def acquire(results_dir, me=None, attempts=5):
    """Take the results folder's lock for this process, or say who holds it.

    Makes the results folder if needed.  A lock file whose holder is gone (killed) is
    taken over: the operating system let go of its lock with the process.

    Parameters
    ----------
    results_dir : str
        The results folder.
    me : dict, optional
        Who this build is (:func:`this_build` by default), written into the file.
    attempts : int, optional
        How often to try when the file is removed and made again meanwhile.

    Returns
    -------
    tuple
        ``(fd, None)``: the open, locked file (keep it open; :func:`release` at the
        end), or ``(None, message)`` when another build holds the folder, or
        ``(None, None)`` where the file system has no locks.
    """
    os.makedirs(results_dir, exist_ok=True)
    path = lock_path(results_dir)
    me = me or this_build()
    for _ in range(attempts):
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = _holder(fd)
            os.close(fd)
            return None, held_message(results_dir, holder)
        except OSError:  # a file system without locks: run unlocked, as before
            os.close(fd)
            with contextlib.suppress(OSError):
                os.unlink(path)
            return None, None
        if _same_file(fd, path):  # else its holder removed it as we opened it: again
            os.ftruncate(fd, 0)
            os.lseek(fd, 0, os.SEEK_SET)
            os.write(fd, (json.dumps(me, sort_keys=True) + "\n").encode("utf-8"))
            return fd, None
        os.close(fd)
    return None, held_message(results_dir, None)


def release(fd, results_dir):
    """Let go of the lock taken by :func:`acquire` and remove its file.

    Parameters
    ----------
    fd : int or None
        From :func:`acquire` (None: nothing to do).
    results_dir : str
    """
    if fd is None:
        return
    path = lock_path(results_dir)
    try:
        if _same_file(fd, path):  # removed while still locked: no one else holds it
            os.unlink(path)
    except OSError:
        pass
    finally:
        os.close(fd)
