"""How the per-subject rules split a dataset's subjects into jobs.

Every job pays Python's start-up and its imports (numpy, scipy: about 0.7 s of CPU on
a laptop) before it does any work, while one subject's fits take a fraction of that.
So a job takes several subjects: at least :data:`MIN_SUBJECTS_PER_JOB`, which keeps
the start-up to about half a job's time or less, and a rule has at most
:data:`MAX_JOBS_PER_RULE` jobs, which keeps the number of jobs (and of files, and the
time Snakemake spends planning) bounded however many subjects there are.  The split
depends on the data only, never on ``--cores``, so the same data give the same files
on a laptop and on a cluster.
"""

from __future__ import annotations

__all__ = ["MAX_JOBS_PER_RULE", "MIN_SUBJECTS_PER_JOB", "batch_name", "batches", "per_job"]

#: Fewest subjects a job takes under ``subjects_per_job: auto`` (fewer only when the
#: dataset has fewer).
MIN_SUBJECTS_PER_JOB = 4
#: Most jobs one per-subject rule has under ``subjects_per_job: auto``.
MAX_JOBS_PER_RULE = 8


def per_job(n_subjects, setting="auto"):
    """Subjects handled by one job.

    Parameters
    ----------
    n_subjects : int
        Subjects in the dataset.
    setting : int or "auto"
        The config's ``subjects_per_job``: a number is used as given; ``"auto"`` gives
        at least :data:`MIN_SUBJECTS_PER_JOB` and at most :data:`MAX_JOBS_PER_RULE`
        jobs per rule.

    Returns
    -------
    int
        At least 1.
    """
    if setting != "auto":
        return max(1, int(setting))
    spread = -(-n_subjects // MAX_JOBS_PER_RULE)  # ceil: at most MAX_JOBS_PER_RULE jobs
    return max(1, MIN_SUBJECTS_PER_JOB, spread)


def batch_name(members):
    """A batch's name: its subject alone, or its first subject and how many follow
    (``"M1+124"``: M1 and the next 124 subjects of the sheet)."""
    return members[0] if len(members) == 1 else f"{members[0]}+{len(members) - 1}"


def batches(subject_ids, setting="auto"):
    """The batches of a dataset, in the sheet's order.

    Parameters
    ----------
    subject_ids : sequence of str
        The subjects in the sheet's order.
    setting : int or "auto"
        The config's ``subjects_per_job`` (see :func:`per_job`).

    Returns
    -------
    dict
        Batch name -> list of its subjects; consecutive runs of the sheet, each of
        :func:`per_job` subjects but the last.
    """
    size = per_job(len(subject_ids), setting)
    return {
        batch_name(list(subject_ids[i : i + size])): list(subject_ids[i : i + size])
        for i in range(0, len(subject_ids), size)
    }
