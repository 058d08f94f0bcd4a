"""A simulated dataset analysed as the workflow analyses a real one, in memory.

Each step calls what its rule's script calls: ``prepare_profiles``
(:func:`lineload.averaging.average_subjects`), ``noise``
(:func:`lineload.noise.measure_noise_table`), ``fit_models``
(:func:`lineload.noise.trial_models`, :func:`lineload.fitting.batch.fit_trials`) and
``claims_table`` (:func:`lineload.claims.judged_settings`,
:func:`lineload.claims.compute_claims`); nothing is written or read back.  The
verdict calibration (:mod:`lineload.simulation.verdicts`) and the elastic finger's
world (:mod:`lineload.simulation.elastic_world`) add their own families' fits to it.

A dataset without errors is judged as its truth: the noise is the generator's with
every standard deviation times :data:`TRUTH_SCALE`, nothing measured, so that the
intervals close on the values the error-free readings give.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from lineload.averaging import average_subjects
from lineload.claims import ClaimSettings, compute_claims, judged_settings
from lineload.fitting.batch import fit_trials
from lineload.noise import NoiseModel, measure_noise_table, model_from_rows, trial_models
from lineload.simulation.errors import TRUE_NOISE

__all__ = ["TRUTH_SCALE", "Analysis", "analyse", "judged_claims", "truth_noise"]

#: Every standard deviation of the noise, and of a force reading, times this when
#: the rules judge the error-free readings: intervals a thousandth of their size.
TRUTH_SCALE = 1e-3


def truth_noise(scale=TRUTH_SCALE):
    """The generator's noise with every standard deviation times ``scale``."""
    values = TRUE_NOISE.as_dict()
    return type(TRUE_NOISE)(
        **{k: v if k == "tracing_length_mm" else v * scale for k, v in values.items()}
    )


def _trials_of(averaged):
    """Each trial's rows of the averaged columns, in table order: (subject, depth, slice)."""
    subject = np.asarray(averaged["subject"])
    depth = np.asarray(averaged["depth_mm"], dtype=float)
    new = np.r_[True, (subject[1:] != subject[:-1]) | (depth[1:] != depth[:-1])]
    starts = np.flatnonzero(new)
    ends = np.r_[starts[1:], subject.size]
    return [(subject[a], float(depth[a]), slice(a, b)) for a, b in zip(starts, ends, strict=True)]


@dataclass(frozen=True)
class Analysis:
    """One dataset analysed: what the rules up to ``fit_models`` would have written.

    Attributes
    ----------
    fits : pandas.DataFrame
        The fit table, as rule ``fit_models`` writes it (``subject``, ``species``, ...).
    averaged : dict
        The averaged columns (rule ``prepare_profiles``).
    noise : NoiseModel
        The dataset's noise model.
    trial_noise : list of NoiseModel
        Each trial's, in the fit table's order.
    trials : list of tuple
        ``(subject, depth_mm, slice of averaged)`` per trial, in the same order.
    """

    fits: pd.DataFrame
    averaged: dict
    noise: NoiseModel
    trial_noise: list
    trials: list

    def per_trial(self, name):
        """Column ``name`` of :attr:`averaged`, cut into the trials' arrays."""
        column = np.asarray(self.averaged[name], dtype=float)
        return [column[rows] for *_, rows in self.trials]

    @property
    def depths_mm(self):
        """Each trial's depth (mm)."""
        return [depth for _, depth, _ in self.trials]

    def labelled(self, rows):
        """Per-trial result rows (dicts, in the trials' order) with their subject."""
        return pd.DataFrame(
            [{"subject": name, **row} for (name, _, _), row in zip(self.trials, rows, strict=True)]
        )


def analyse(converted, species_of, window_mm, priors, max_trials, errors=True):
    """Average the subjects' tissue tables, measure the noise, fit the paper's models.

    Parameters
    ----------
    converted : list of pandas.DataFrame
        Each subject's readings in tissue mm (:func:`lineload.averaging.tissue_columns`).
    species_of : dict
        Subject -> species.
    window_mm : float
        Fit window (config ``fit_window_mm``).
    priors : dict
        The noise priors (config ``noise``).
    max_trials : int
        Config ``noise: max_trials``.
    errors : bool, optional
        False: the readings are error-free; the noise is :func:`truth_noise`.

    Returns
    -------
    Analysis
    """
    averaged = average_subjects(converted)
    trials = _trials_of(averaged)
    columns = {
        name: np.asarray(averaged[name], dtype=float)
        for name in ("distance_mm", "deflection_mm", "left_mm", "right_mm", "n_sides")
    }
    keys = [(name, depth) for name, depth, _ in trials]
    if errors:
        profiles = [
            (columns["distance_mm"][r], columns["left_mm"][r], columns["right_mm"][r])
            for *_, r in trials
        ]
        _, rows = measure_noise_table(profiles, priors, window_mm, max_trials)
        noise = model_from_rows(rows)
        trial_noise = trial_models(rows, keys)
    else:
        noise = truth_noise()
        trial_noise = [noise] * len(keys)
    fitted = fit_trials(
        [columns["distance_mm"][r] for *_, r in trials],
        [columns["deflection_mm"][r] for *_, r in trials],
        [depth for _, depth, _ in trials],
        window_mm,
        noise=trial_noise,
        n_sides=[columns["n_sides"][r] for *_, r in trials],
    )
    fits = pd.DataFrame(
        [
            {"subject": name, "species": species_of[name], **row}
            for (name, _, _), row in zip(trials, fitted, strict=True)
        ]
    )
    return Analysis(fits, averaged, noise, trial_noise, trials)


def judged_claims(fits, averaged, noise, trial_noise, claims=None, errors=True, forces=None):
    """The claims table of an analysed dataset, as rule ``claims_table`` judges it.

    Parameters
    ----------
    fits, averaged, noise, trial_noise
        As :class:`Analysis` holds them (``fits`` with any other family's columns).
    claims : dict, optional
        Settings of the claims (config ``claims``); schema defaults if None.
    errors : bool, optional
        False: judged as the truth (no noise floor; the force SD times
        :data:`TRUTH_SCALE`).
    forces : pandas.DataFrame, optional
        ``subject``, ``depth_mm``, ``force_N``.

    Returns
    -------
    pandas.DataFrame
        The claims table, every claim.
    """
    settings = dict(claims or {})
    if not errors:
        settings["noise_mm"] = None
        settings["force_sd_N"] = TRUTH_SCALE * ClaimSettings(**settings).force_sd_N
    settings = judged_settings(settings, fits, noise, trial_noise)
    return compute_claims(fits, pd.DataFrame(averaged), settings, forces=forces)
