"""Let a finished build exit at once: the scheduler's pending wake-up timers cancelled.

Snakemake 9 limits how many jobs it starts per timespan (``--max-jobs-per-timespan``,
100 per second by default).  At every round of its scheduling loop it starts a
:class:`threading.Timer` of that timespan to wake the loop again, and these timers are
not daemon threads: when the build is over, the interpreter waits for the last one to
fire before it exits.  A build thus ended up to one second after its last job (1.0 s
of the 1,000-subject ``fits`` build's 8.4 s; measured in docs/speed-and-clusters.md).
The timespan cannot be made shorter: the option's ``ms`` unit is read as minutes.

:func:`cancel_scheduler_timers`, called by the Snakefile's ``onsuccess`` and ``onerror``
handlers (the scheduling loop has returned by then, and nothing is left to wake),
cancels the timers the scheduler started and no other.
"""

from __future__ import annotations

import threading

__all__ = ["SCHEDULER_MODULE", "cancel_scheduler_timers"]

#: The module whose wake-up timers are cancelled (the function a timer runs is defined
#: there).
SCHEDULER_MODULE = "snakemake.scheduling.job_scheduler"


def cancel_scheduler_timers(module=SCHEDULER_MODULE):
    """Cancel the pending timers whose function comes from Snakemake's scheduler.

    Parameters
    ----------
    module : str, optional
        The module a timer's function must be defined in to be cancelled.

    Returns
    -------
    int
        How many timers were cancelled.
    """
    cancelled = 0
    for thread in threading.enumerate():
        function = getattr(thread, "function", None)
        if (
            isinstance(thread, threading.Timer)
            and getattr(function, "__module__", None) == module
            and not thread.finished.is_set()
        ):
            thread.cancel()
            cancelled += 1
    return cancelled
