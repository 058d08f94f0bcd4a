"""The scheduler's wake-up timers cancelled at the end of a build (lineload.runtime.timers)."""

import threading
import types

from lineload.runtime import timers


def timer_from(module_name, interval=30.0):
    """A started timer whose function is defined in ``module_name``."""
    namespace = types.ModuleType(module_name)
    exec("def wake():\n    pass\n", namespace.__dict__)
    namespace.wake.__module__ = module_name
    timer = threading.Timer(interval, namespace.wake)
    timer.start()
    return timer


def test_only_the_schedulers_timers_are_cancelled():
    theirs = timer_from(timers.SCHEDULER_MODULE)
    ours = timer_from("somewhere.else")
    try:
        assert timers.cancel_scheduler_timers() == 1
        theirs.join(timeout=5)
        assert not theirs.is_alive()  # cancelled: it ended without waiting 30 s
        assert ours.is_alive()  # another module's timer is left to run
        assert timers.cancel_scheduler_timers() == 0  # nothing left of the scheduler's
    finally:
        theirs.cancel()
        ours.cancel()


def test_the_timers_snakemake_starts_are_the_ones_cancelled():
    # Snakemake's own re-evaluation call, on a stand-in scheduler: the timer it starts is
    # found and cancelled (an upgrade that started it otherwise, e.g. from another module
    # or with a bound method, would make this fail rather than leave the exit waiting)
    from snakemake.scheduling.job_scheduler import JobScheduler

    scheduler = types.SimpleNamespace(_open_jobs=threading.Semaphore(0))
    before = set(threading.enumerate())
    JobScheduler._schedule_reevalutation(scheduler, 30)
    (started,) = set(threading.enumerate()) - before
    try:
        assert isinstance(started, threading.Timer)
        assert timers.cancel_scheduler_timers() == 1
        started.join(timeout=5)
        assert not started.is_alive()
        assert not scheduler._open_jobs.acquire(blocking=False)  # it never fired
    finally:
        started.cancel()
