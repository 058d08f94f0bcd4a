"""The trials of a batch as the fit jobs read them: points, sides read, noise, and keys.

The fit jobs (the fit table, the bending fits, the sensitivity refits) each fit every
trial of a batch's subjects at once.  They read the averaged profiles and the noise
table the same way (:func:`read_batch`) and label their rows the same way
(:func:`labelled_rows`), so a trial is the same trial in every table.
"""

from __future__ import annotations

from dataclasses import dataclass

from lineload.io import read_rows, read_trials
from lineload.noise import trial_models

__all__ = ["Batch", "labelled_rows", "read_batch"]


@dataclass(frozen=True)
class Batch:
    """The trials of a batch, in the subject sheet's order, each subject's depths increasing.

    Attributes
    ----------
    subject, species : list of str
        Of each trial.
    depth_mm : list of float
        Indentation depth of each trial (mm).
    distance_mm, deflection_mm : list of numpy.ndarray
        Each trial's averaged profile (mm), in file order.
    n_sides : list of numpy.ndarray or None
        Sides read at each point (None when not asked for).
    noise : list of lineload.noise.NoiseModel or None
        Each trial's noise model (None without a noise table).
    """

    subject: list
    species: list
    depth_mm: list
    distance_mm: list
    deflection_mm: list
    n_sides: list | None = None
    noise: list | None = None

    def __len__(self):
        return len(self.subject)


def read_batch(averaged, subjects, noise=None, sides=True):
    """Read the trials of a batch's subjects.

    Parameters
    ----------
    averaged : str or os.PathLike
        The averaged-profile table (:func:`lineload.io.read_trials`).
    subjects : dict of str to dict
        The batch's subjects (``subject -> {"species": ...}``), in the order of the rows.
    noise : str or os.PathLike, optional
        The noise table: each trial gets its model (:func:`lineload.noise.trial_models`).
    sides : bool, optional
        Whether to read ``n_sides``, the sides read at each point.

    Returns
    -------
    Batch
        A subject without profiles has no trial.
    """
    trials = read_trials(averaged, extra=("n_sides",) if sides else ())
    keys = [
        (subject, about["species"], depth_mm, columns)
        for subject, about in subjects.items()
        for depth_mm, columns in trials.get(subject, {}).items()
    ]
    models = None
    if noise is not None:
        models = trial_models(read_rows(noise), [(key[0], key[2]) for key in keys])
    return Batch(
        subject=[key[0] for key in keys],
        species=[key[1] for key in keys],
        depth_mm=[key[2] for key in keys],
        distance_mm=[key[3][0] for key in keys],
        deflection_mm=[key[3][1] for key in keys],
        n_sides=[key[3][2] for key in keys] if sides else None,
        noise=models,
    )


def labelled_rows(batch, rows):
    """Each trial's row with its ``subject`` and ``species`` first.

    Parameters
    ----------
    batch : Batch
    rows : sequence of dict
        One row per trial of ``batch``, in its order.

    Returns
    -------
    list of dict
    """
    return [
        {"subject": subject, "species": species, **row}
        for subject, species, row in zip(batch.subject, batch.species, rows, strict=True)
    ]
