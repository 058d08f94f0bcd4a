"""How the per-subject rules split a dataset's subjects into jobs.

Every job pays Python's start-up and its imports before it does any work: about 0.2 s
on this project's laptop-class machine (a check, preparation or fit job of few subjects
took 0.2-0.25 s).  One digitised subject's own work is far less: at four depths about
0.75 ms to check, 1 ms to prepare and 2.8 ms to fit (measured in
docs/speed-and-clusters.md).  So a job takes many subjects: at least
:data:`MIN_SUBJECTS_PER_JOB`, which makes a fit job's own work about three times its
start-up, and a rule has at most :data:`MAX_JOBS_PER_RULE` jobs, which keeps the number
of jobs (and of files, and the time Snakemake spends planning) bounded however many
subjects there are.  A photographed subject costs some 0.1 s or more to digitise and
check, so a dataset with photographs needs only :data:`MIN_PHOTOGRAPHED_PER_JOB` per
job to outweigh the start-up, and spreads over more cores sooner.  The split depends on
the data only, never on ``--cores``, so the same data give the same files on a laptop
and on a cluster.
"""

from __future__ import annotations

__all__ = [
    "MAX_JOBS_PER_RULE",
    "MIN_PHOTOGRAPHED_PER_JOB",
    "MIN_SUBJECTS_PER_JOB",
    "batch_name",
    "batches",
    "per_job",
]

#: Fewest subjects a job takes under ``subjects_per_job: auto`` (fewer only when the
#: dataset has fewer), for digitised profiles.
MIN_SUBJECTS_PER_JOB = 250
#: The same where subjects are read from photographs (digitising dominates a job).
MIN_PHOTOGRAPHED_PER_JOB = 4
#: Most jobs one per-subject rule has under ``subjects_per_job: auto``.
MAX_JOBS_PER_RULE = 8


def per_job(n_subjects, setting="auto", photographs=False):
    """Subjects handled by one job.

    Parameters
    ----------
    n_subjects : int
        Subjects in the dataset.
    setting : int or "auto"
        The config's ``subjects_per_job``: a number is used as given; ``"auto"`` gives
        at least :data:`MIN_SUBJECTS_PER_JOB` (:data:`MIN_PHOTOGRAPHED_PER_JOB` with
        ``photographs``) and at most :data:`MAX_JOBS_PER_RULE` jobs per rule.
    photographs : bool, optional
        Whether subjects of the dataset are read from photographs.

    Returns
    -------
    int
        At least 1.
    """
    if setting != "auto":
        return max(1, int(setting))
    spread = -(-n_subjects // MAX_JOBS_PER_RULE)  # ceil: at most MAX_JOBS_PER_RULE jobs
    fewest = MIN_PHOTOGRAPHED_PER_JOB if photographs else MIN_SUBJECTS_PER_JOB
    return max(1, fewest, spread)


def batch_name(members):
    """A batch's name: its subject alone, or its first subject and how many follow
    (``"M1+124"``: M1 and the next 124 subjects of the sheet)."""
    return members[0] if len(members) == 1 else f"{members[0]}+{len(members) - 1}"


def batches(subject_ids, setting="auto", photographs=False):
    """The batches of a dataset, in the sheet's order.

    Parameters
    ----------
    subject_ids : sequence of str
        The subjects in the sheet's order.
    setting : int or "auto"
        The config's ``subjects_per_job`` (see :func:`per_job`).
    photographs : bool, optional
        Whether subjects of the dataset are read from photographs (see :func:`per_job`).

    Returns
    -------
    dict
        Batch name -> list of its subjects; consecutive runs of the sheet, each of
        :func:`per_job` subjects but the last.
    """
    size = per_job(len(subject_ids), setting, photographs)
    return {
        batch_name(list(subject_ids[i : i + size])): list(subject_ids[i : i + size])
        for i in range(0, len(subject_ids), size)
    }
