"""A trial as the rules see it: its fit row, its averaged points and their noise.

The fit table has one row per subject and depth; the averaged profiles are stacked.
:func:`_trials` pairs them, :func:`_window_points` keeps the fitted points, and
:func:`_averaged_covariance_mm2` gives their covariance under the trial's noise.
"""

from __future__ import annotations

import math

import numpy as np

from lineload.fitting.windows import in_fit_window
from lineload.trials import profiles_by_trial, trial_key, trial_label

__all__ = [
    "trial_key",
]


#: The waterbed fits in the fit table: the paper's procedure and the two in
#: measured coordinates, with the words used for them in the table.
PAPER_FIT = "waterbed"
CONSISTENT_FITS = ("shifted", "arc")
FIT_WORDS = {
    "waterbed": "the paper's procedure",
    "shifted": "the shifted parabola",
    "arc": "the exact arc",
}


def _trials(fits, averaged):
    """Pairs (fit row, averaged points) for every row of the fit table, in its order.

    A trial without averaged points gets an empty frame.
    """
    profiles = profiles_by_trial(averaged)
    empty = averaged.iloc[0:0]
    for _, fit in fits.iterrows():
        yield fit, profiles.get(trial_key(fit["subject"], fit["depth_mm"]), empty)


def _window_points(fit, points):
    """Distances, deflections and side counts of a trial's fitted points (the fit window)."""
    x = points["distance_mm"].to_numpy(float)
    w = points["deflection_mm"].to_numpy(float)
    sides = points["n_sides"].to_numpy(float)
    keep = in_fit_window(x, float(fit["fit_window_mm"])) & np.isfinite(w)
    return x[keep], w[keep], sides[keep]


def _label(fit):
    return trial_label(fit["subject"], fit["depth_mm"])


def _finite_L(fit, model=PAPER_FIT):
    L_mm = float(fit[f"{model}_L_mm"])
    return math.isfinite(L_mm) and L_mm > 0


def _noise_sd_mm(noise_mm, n_sides):
    """Noise of each averaged point: one reading's noise over the root of the sides averaged."""
    return noise_mm / np.sqrt(np.maximum(np.asarray(n_sides, dtype=float), 1.0))


def _averaged_covariance_mm2(x_mm, sides, y_mm, fit, settings):
    """Covariance of a trial's averaged points under its noise.

    With a noise model, :meth:`lineload.noise.NoiseModel.average_covariance_mm2`
    (every measured part and every prior; the trial's own model where
    ``settings.trial_noise`` has one); otherwise independent readings of
    ``noise_mm`` over the number of sides averaged.
    """
    depth_mm = float(fit["depth_mm"])
    if settings.noise_model is not None and settings.noise_mm is None:
        model = (settings.trial_noise or {}).get(
            trial_key(fit["subject"], depth_mm), settings.noise_model
        )
        return model.average_covariance_mm2(x_mm, sides, y_mm, depth_mm)
    return np.diag(_noise_sd_mm(settings.reading_noise_mm, sides) ** 2)
