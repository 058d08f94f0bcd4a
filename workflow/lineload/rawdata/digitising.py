"""Digitising a batch of photographed subjects, one pair at a time.

Rule ``digitise`` runs once per batch of subjects (config ``subjects_per_job``: batches
from the subject sheet, not from the cores), so ten thousand pairs cost a few dozen
Python start-ups, not thousands.  :func:`digitise_batch` reads the batch's pairs one
after another (the two photographs of one pair in memory, and the loaded photographs
kept for the quality figure only while :data:`FIGURE_TRIALS` allow) and gives, per
subject, the readings in the profile contract's form, the quality records and what
the figure draws.  The photographs are named relative to the raw folder, as every
record of the build names raw files.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

__all__ = [
    "FIGURE_TRIALS",
    "PROFILE_COLUMNS",
    "BatchResult",
    "digitise_batch",
    "profile_text",
    "subject_profile",
    "truth_curves",
]

#: Columns of a batch's digitised readings: the profile contract's, after the subject.
PROFILE_COLUMNS = ["subject", "depth_mm", "side", "distance_image_mm", "deflection_image_mm"]
#: The most trials a batch's quality figure draws: every trial of a small batch; of a
#: larger one, those whose readings the digitiser states least sure (largest own SD over
#: the fit window), so a reviewer of thousands of pairs sees the doubtful ones.
FIGURE_TRIALS = 8


@dataclass
class BatchResult:
    """What the digitise job writes for one batch.

    Attributes
    ----------
    rows : list of tuple
        ``(subject, depth_mm, side, distance_image_mm, deflection_image_mm)``.
    records : list of dict
        Per subject, in batch order: ``{"subject", "trials": [quality record, ...]}``.
    drawn : list of dict
        The trials the quality figure draws (:func:`lineload.figures.data.figure_digitised`).
    """

    rows: list = field(default_factory=list)
    records: list = field(default_factory=list)
    drawn: list = field(default_factory=list)


def truth_curves(truth, subject):
    """``{(depth_mm, side): (distance_mm, deflection_mm)}`` of ``subject`` in a truth
    table (images/truth.csv as a DataFrame; None for none)."""
    if truth is None:
        return {}
    mine = truth[truth["subject"] == subject]
    curves = {}
    for (depth_mm, side), rows in mine.groupby(["depth_mm", "side"]):
        rows = rows.sort_values("distance_mm")
        curves[(float(depth_mm), side)] = (
            rows["distance_mm"].to_numpy(float),
            rows["deflection_mm"].to_numpy(float),
        )
    return curves


def digitise_batch(
    raw_dir, images, subjects, settings, window_mm, truth=None, log=print, diagnostic=None
):
    """Digitise every pair of ``subjects``, one pair at a time.

    Parameters
    ----------
    raw_dir : str
        The raw folder (``images/images.csv`` names files under ``images/``).
    images : pandas.DataFrame
        images/images.csv, checked (:func:`lineload.rawdata.validation.read_table`).
    subjects : dict
        Subject id -> its sheet row (``label``, ``magnification``), batch order.
    settings : dict
        The config's ``digitise`` settings.
    window_mm : float
        The fit window (the quality records' error and own SD are taken within it).
    truth : pandas.DataFrame, optional
        images/truth.csv, where the folder has one.
    log : callable, optional
        Called with one line per trial.
    diagnostic : str, optional
        Where to draw a refused pair as the digitiser saw it
        (:mod:`lineload.figures.diagnostic`); its refusal then names it.

    Returns
    -------
    BatchResult

    Raises
    ------
    lineload.rawdata.photographs.ImageError
        If a pair cannot be read (the pair drawn into ``diagnostic``, when given).
    """
    import heapq

    import numpy as np

    from lineload.rawdata.images import image_scale_px_per_mm
    from lineload.rawdata.photographs import (
        ImageError,
        digitise_photographs,
        own_reading_sd_mm,
        profile_rows,
        quality_record,
        read_photograph,
    )
    from lineload.rawdata.readings import reading_distances_mm

    scale = image_scale_px_per_mm(images)
    grid = reading_distances_mm(settings["reach_mm"], settings["first_mm"])
    result = BatchResult()
    # the figure's trials: the FIGURE_TRIALS least sure so far (a bounded heap)
    figure = []
    order = 0
    for subject, about in subjects.items():
        known_truth = truth_curves(truth, subject)
        mine = images[images["subject"] == subject]
        trials = []
        for depth_mm in sorted(set(mine["depth_mm"].astype(float))):
            pair = mine[mine["depth_mm"].astype(float) == depth_mm]
            rest, loaded = (pair[pair["state"] == state].iloc[0] for state in ("rest", "loaded"))
            files = [os.path.join("images", str(r["file"])) for r in (rest, loaded)]
            names = [os.path.join(raw_dir, f) for f in files]
            pictures = [read_photograph(name, name) for name in names]
            ppmm = float(scale.loc[loaded.name])
            try:
                trial = digitise_photographs(
                    *pictures, ppmm, grid, settings, tip_x_px=loaded.get("tip_x_px"), names=names
                )
            except ImageError as error:
                seen = getattr(error, "seen", None)
                if diagnostic is None or seen is None:
                    raise
                from lineload.figures.diagnostic import Refusals

                refusals = Refusals(diagnostic)
                message = refusals.note(pictures[seen.get("failed", 1)], seen, str(error))
                refusals.write()
                raise ImageError(message) from None
            result.rows += [
                (subject, *row) for row in profile_rows(depth_mm, trial, about["magnification"])
            ]
            known = {
                side: known_truth[(depth_mm, side)]
                for side in ("left", "right")
                if (depth_mm, side) in known_truth
            }
            record = quality_record(depth_mm, trial, known, window_mm)
            trials.append({"rest": _posix(files[0]), "loaded": _posix(files[1]), **record})
            height, width = pictures[1].shape[:2]
            drawn = {
                "label": about["label"],
                "depth_mm": depth_mm,
                "image": pictures[1],
                "extent_mm": (0.0, width / ppmm, 0.0, -height / ppmm),
                "outlines": trial.outlines,
                "readings": trial.readings,
                "tip_x_mm": trial.tip_x_mm,
                "truth": known,
            }
            own = own_reading_sd_mm(trial, window_mm)
            entry = (-np.inf if own is None else own, -order, drawn)
            if len(figure) < FIGURE_TRIALS:
                heapq.heappush(figure, entry)
            else:
                heapq.heappushpop(figure, entry)
            order += 1
            del pictures
            counts = sum(len(trial.readings[side][0]) for side in ("left", "right"))
            log(
                f"{subject} {depth_mm:g} mm: {counts} readings, tip at "
                f"{trial.tip_x_mm:.4f} mm, registration residual "
                f"{1000 * trial.registration_rms_mm:.1f} um, "
                f"reading SD {1000 * trial.reading_sd_mm:.1f} um"
            )
        result.records.append({"subject": subject, "trials": trials})
    # in batch order
    result.drawn = [drawn for _, _, drawn in sorted(figure, key=lambda e: -e[1])]
    return result


def _posix(path):
    return path.replace(os.sep, "/")


def profile_text(rows):
    """A batch's digitised readings as CSV (:data:`PROFILE_COLUMNS`), as the job writes them."""
    return (
        ",".join(PROFILE_COLUMNS)
        + "\n"
        + "".join(f"{subject},{d:g},{side},{x:.5f},{w:.5f}\n" for subject, d, side, x, w in rows)
    )


def subject_profile(profile, subject):
    """One subject's rows of a profile read by :func:`lineload.rawdata.sheets.read_columns`
    (a batch's digitised readings carry a ``subject`` column; a raw profile file, which
    holds one subject, has none and comes back as it is)."""
    columns, lines = profile
    if "subject" not in columns:
        return profile
    mine = columns["subject"].astype(str) == str(subject)
    return {name: values[mine] for name, values in columns.items()}, lines[mine]
