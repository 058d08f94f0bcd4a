"""Stopping a build cleanly on SIGTERM.

Snakemake's own SIGTERM handler takes a lock that its main thread may already hold
(while it selects or finishes jobs), and then a killed build never returns.  Its
Ctrl-C path has no such lock, but it waits for the running jobs unless they got the
signal too, as a terminal's Ctrl-C gives them.  :func:`stop_on_sigterm` routes
SIGTERM to that path and passes it on to every running job first.
"""

import os
import signal

__all__ = ["descendants", "stop_on_sigterm"]

_PROC = os.sep + "proc"


def descendants(pid):
    """Process ids of every descendant of a process.

    Parameters
    ----------
    pid : int
        The process whose children, grandchildren and so on are wanted.

    Returns
    -------
    list of int
        Their process ids, parents before children.  Empty where the system has
        no ``/proc`` (the parent of each process is read from ``/proc/<pid>/stat``).
    """
    children = {}
    entries = os.listdir(_PROC) if os.path.isdir(_PROC) else []
    for entry in entries:
        if not entry.isdigit():
            continue
        try:
            with open(os.path.join(_PROC, entry, "stat"), encoding="ascii") as handle:
                parent = int(handle.read().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            continue
        children.setdefault(parent, []).append(int(entry))
    found, stack = [], [pid]
    while stack:
        for child in children.get(stack.pop(), []):
            found.append(child)
            stack.append(child)
    return found


def stop_on_sigterm():
    """Make ``kill`` (SIGTERM) stop a build the way Ctrl-C does, jobs included.

    The running jobs are sent SIGTERM (whatever process group they are in, and even
    if they ignore SIGINT), then a ``KeyboardInterrupt`` takes Snakemake's Ctrl-C
    path: outputs of cut jobs are marked incomplete, and the build exits.  Call it
    when the workflow is read (a signal between Snakemake's locking and its
    scheduler's start then unwinds through the lock's cleanup instead of killing
    the process with its locks left behind), and again from ``onstart:``, which
    runs after the scheduler has installed its own handler.
    """

    def interrupt(signum, frame):
        for child in descendants(os.getpid()):
            try:
                os.kill(child, signal.SIGTERM)
            except ProcessLookupError:
                pass
        raise KeyboardInterrupt(f"signal {signum}")

    signal.signal(signal.SIGTERM, interrupt)
