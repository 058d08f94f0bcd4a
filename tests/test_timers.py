"""The scheduler's wake-up timers cancelled at the end of a build (lineload.runtime.timers)."""

import inspect
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


def test_the_timers_are_where_snakemake_starts_them():
    # an upgrade of Snakemake that moved or renamed them would leave the exit waiting
    # again: the module named here must be the one that starts the wake-up timers
    from snakemake.scheduling import job_scheduler

    assert job_scheduler.__name__ == timers.SCHEDULER_MODULE
    source = inspect.getsource(job_scheduler.JobScheduler)
    assert "threading.Timer(" in source
