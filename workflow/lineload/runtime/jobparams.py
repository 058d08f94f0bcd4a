"""What a job was given: Snakemake's ``params``, as a dict, written to the job's log.

The values come from the rule's ``params:`` (Snakemake compares them with those of the
last run and reruns the job when they change); the log keeps them, one JSON line, so a
reviewer reads what each job was given beside what it did.
"""

from __future__ import annotations

import json

__all__ = ["given"]


def given(params):
    """Return a job's params as a dict, printed first as one line ``params: {...}``.

    Parameters
    ----------
    params : snakemake.io.Params
        ``snakemake.params`` of a ``script:`` job (named values only).

    Returns
    -------
    dict
        Name -> value, as the rule gave them.
    """
    values = dict(params.items())
    print("params: " + json.dumps(values, sort_keys=True, default=str))
    return values
