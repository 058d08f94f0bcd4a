"""The thresholds of the claims' rules (config key ``claims``; defaults from the schema)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from lineload.io import config_defaults
from lineload.noise import NoiseModel
from lineload.trials import trial_key

__all__ = [
    "ClaimSettings",
    "judged_settings",
]


#: The schema's defaults of the claims' settings: read, never restated.
_DEFAULTS = {**config_defaults("claims"), "force_sd_N": config_defaults("mechanics")["force_sd_N"]}


@dataclass(frozen=True)
class ClaimSettings:
    """Thresholds of the verdict rules (config key ``claims``; defaults from its schema).

    Attributes
    ----------
    noise_mm : float or None
        Digitising noise of one reading of one side (tissue mm, standard
        deviation), set by hand (config ``claims: noise_mm``); None takes it
        from ``noise_model`` (see :attr:`reading_noise_mm`).
    large_depth_mm : float
        Depths at or above this are the 'larger depths' of C9.
    significance : float
        Error rate of the claims' tests (Bonferroni over the trials or subjects
        where a claim tests several); which claims use it, and each other
        threshold, is in their registry entries (:func:`lineload.claims.registry.claims_using`).
    extent_fraction : float
        C1: the deformed region ends where the deflection falls through this
        fraction of the depth.
    symmetry_margin, shift_margin, circularity_margin : float
        The equivalence margins of the symmetry, shift and circularity claims, the
        workflow's own (config keys of the same names; the schema gives the reasons).
    slope_min_df : int
        The fewest degrees of freedom for the spread between subjects with which a
        slope against depth is tested across subjects; with fewer, the claim cannot
        be checked.
    elastic_margin : float
        C12: the part of the misfit a layer must remove, a fraction of the depth, before
        it is read as a layer rather than a wrong geometry (config key of the same name).
    force_sd_N : float
        C11: precision of one force reading (N, standard deviation); config key
        ``mechanics: force_sd_N``.
    zero_crossing_rtol : float
        C7: largest relative distance between the numerical zero and L/3.  A
        bound on floating-point error, not on the data, so not a config key.
    noise_model : lineload.noise.NoiseModel or None
        The dataset's digitising noise (the noise table: measured parts and
        priors); the covariance of each trial's averaged points comes from it.
        None: independent readings of ``noise_mm`` and nothing else.
    trial_noise : dict or None
        ``(subject, depth_mm)`` -> the NoiseModel of a trial with rows of its own
        in the noise table (a digitised trial's registration error); the others
        take ``noise_model``.
    prior_multiples : tuple of float
        Multiples of the noise priors at which the claims are computed again
        (:mod:`lineload.priors`); config ``claims: prior_multiples``.
    """

    noise_mm: float | None = _DEFAULTS["noise_mm"]
    large_depth_mm: float = _DEFAULTS["large_depth_mm"]
    significance: float = _DEFAULTS["significance"]
    force_sd_N: float = _DEFAULTS["force_sd_N"]
    extent_fraction: float = _DEFAULTS["extent_fraction"]
    symmetry_margin: float = _DEFAULTS["symmetry_margin"]
    shift_margin: float = _DEFAULTS["shift_margin"]
    circularity_margin: float = _DEFAULTS["circularity_margin"]
    slope_min_df: int = _DEFAULTS["slope_min_df"]
    elastic_margin: float = _DEFAULTS["elastic_margin"]
    zero_crossing_rtol: float = 1e-6
    noise_model: NoiseModel | None = None
    trial_noise: dict | None = None
    prior_multiples: tuple = tuple(_DEFAULTS["prior_multiples"])

    @property
    def reading_noise_mm(self):
        """One reading's noise: ``noise_mm`` if set, else the noise model's reading and
        tracing errors together (``sqrt(reading**2 + tracing**2)``)."""
        if self.noise_mm is not None:
            return float(self.noise_mm)
        if self.noise_model is None:
            raise ValueError("the claims need noise_mm or a noise model")
        return math.hypot(self.noise_model.reading_sd_mm, self.noise_model.tracing_sd_mm)


def judged_settings(settings, fits, noise_model, trial_noise_models):
    """The settings the claims are judged with: the config's, the dataset's noise model
    and each trial's, keyed as the rules look them up.

    Rule ``claims_table`` and the calibration's reconstructions both build their
    settings here.

    Parameters
    ----------
    settings : mapping
        The config's ``claims`` values (and ``force_sd_N``); missing ones take the
        schema's defaults.
    fits : pandas.DataFrame
        The fit table (``subject``, ``depth_mm``), in the order of ``trial_noise_models``.
    noise_model : lineload.noise.NoiseModel
        The dataset's noise model.
    trial_noise_models : sequence of lineload.noise.NoiseModel
        Each trial's noise model, one per row of ``fits``.

    Returns
    -------
    ClaimSettings
    """
    values = dict(settings)
    if "prior_multiples" in values:
        values["prior_multiples"] = tuple(values["prior_multiples"])
    keys = zip(fits["subject"], fits["depth_mm"], strict=True)
    trial_noise = {
        trial_key(*key): model for key, model in zip(keys, trial_noise_models, strict=True)
    }
    return ClaimSettings(**values, noise_model=noise_model, trial_noise=trial_noise)
