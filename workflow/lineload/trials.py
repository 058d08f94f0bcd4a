"""What a trial is: one subject indented to one depth, and how every table names it.

A trial is found in many tables (the averaged points, the fits, the noise models, the
forces), each holding its depth as a float that went through a CSV file.  Every lookup
goes through :func:`trial_key`, which rounds the depth to a nanometre so that ``1.0``
and ``1.0000000000000002`` are one trial, and every sentence names a trial with
:func:`trial_label` ("M1 at 1 mm").
"""

from __future__ import annotations

__all__ = ["DEPTH_DECIMALS", "profiles_by_trial", "trial_key", "trial_label"]

#: Decimals of a depth in millimetres kept by a trial's key (a nanometre).
DEPTH_DECIMALS = 9


def trial_key(subject, depth_mm):
    """The key of a trial in per-trial lookups.

    Parameters
    ----------
    subject : object
        The subject's id (taken as its text).
    depth_mm : float
        The indentation depth in millimetres.

    Returns
    -------
    tuple of (str, float)
        ``(subject, depth_mm)``, the depth rounded to :data:`DEPTH_DECIMALS`.
    """
    return (str(subject), round(float(depth_mm), DEPTH_DECIMALS))


def trial_label(subject, depth_mm):
    """How a sentence names a trial: ``"M1 at 1 mm"``."""
    return f"{subject} at {float(depth_mm):g} mm"


def profiles_by_trial(averaged):
    """The points of each trial, by :func:`trial_key`, sorted by distance.

    Parameters
    ----------
    averaged : pandas.DataFrame
        Rows with ``subject``, ``depth_mm`` and ``distance_mm`` (averaged profiles).

    Returns
    -------
    dict
        ``trial_key -> DataFrame`` of that trial's rows, in the order trials first
        appear, rows sorted by ``distance_mm`` (stable).
    """
    out = {}
    for (subject, depth_mm), group in averaged.groupby(["subject", "depth_mm"], sort=False):
        out[trial_key(subject, depth_mm)] = group.sort_values("distance_mm", kind="stable")
    return out
