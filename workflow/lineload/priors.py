"""Verdicts at other priors: every fit and claim again with the priors scaled.

The left-right differences cannot see the shared offset, the shared tilt, the depth
error or the wedge's position (:mod:`lineload.noise`); their sizes are assumed, and
every interval rests on them (the fit table's ``*_prior_share``).  Here each trial is
fitted again with all four priors' standard deviations times a multiple, the claims
computed again from those fits and that noise, and each claim's verdict set beside the
one at the stated priors.  The offset, tilt and depth enter the covariance linearly in
their variances; the wedge enters A's interval through the Gauss-Hermite correction,
which the refit recomputes.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from lineload.fitting.batch import FIT_COLUMNS, fit_trials
from lineload.trials import profiles_by_trial, trial_key

__all__ = [
    "CHANGED_COLUMN",
    "changed_claims",
    "prior_column",
    "refit_at_priors",
    "with_prior_verdicts",
]

#: Column of the claims table naming the multiples at which a verdict differs from
#: the one at the stated priors (empty where it never does).
CHANGED_COLUMN = "verdict_changes_at_priors"


def prior_column(multiple):
    """The claims table's column of the verdicts at ``multiple`` times the priors,
    ``verdict_prior_x0.5``."""
    return f"verdict_prior_x{float(multiple):g}"


def refit_at_priors(fits, averaged, noise_models):
    """The fit table again, each trial fitted with its own (scaled) noise model.

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``subject``, ``species``, ``depth_mm``, ``fit_window_mm``, ...).
    averaged : pandas.DataFrame
        The averaged profiles (``subject``, ``depth_mm``, ``distance_mm``,
        ``deflection_mm``, ``n_sides``).
    noise_models : sequence of lineload.noise.NoiseModel
        One per row of ``fits``.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`lineload.fitting.batch.FIT_COLUMNS`, rows as in ``fits``; L's range
        across the other windows (least squares, free of the noise) copied from ``fits``.
    """
    points = profiles_by_trial(averaged)
    distance, deflection, sides = [], [], []
    for subject, depth_mm in zip(fits["subject"], fits["depth_mm"], strict=True):
        trial = points.get(trial_key(subject, depth_mm))
        if trial is None:
            trial = averaged.iloc[:0]
        distance.append(trial["distance_mm"].to_numpy(float))
        deflection.append(trial["deflection_mm"].to_numpy(float))
        sides.append(trial["n_sides"].to_numpy(float))
    rows = fit_trials(
        distance,
        deflection,
        fits["depth_mm"].to_numpy(float),
        fits["fit_window_mm"].to_numpy(float),
        noise=list(noise_models),
        n_sides=sides,
    )
    table = pd.DataFrame(rows)
    table.insert(0, "species", fits["species"].to_numpy())
    table.insert(0, "subject", fits["subject"].to_numpy())
    # L across other windows is a least-squares L, free of the noise model: kept
    for column in [c for c in FIT_COLUMNS if "_L_window_" in c and c in fits]:
        table[column] = fits[column].to_numpy()
    return table.reindex(columns=FIT_COLUMNS)


def with_prior_verdicts(claims, claims_by_multiple):
    """The claims table with each claim's verdict at every multiple of the priors.

    Parameters
    ----------
    claims : pandas.DataFrame
        The claims at the stated priors (``claim``, ``verdict``, ...).
    claims_by_multiple : dict
        ``multiple -> claims table`` computed with the priors scaled.

    Returns
    -------
    pandas.DataFrame
        ``claims`` with one :func:`prior_column` per multiple and
        :data:`CHANGED_COLUMN` (``"x0.5, x3"``: the multiples whose verdict differs).
    """
    out = claims.copy()
    changed = [[] for _ in range(len(out))]
    for multiple, other in claims_by_multiple.items():
        verdicts = dict(zip(other["claim"], other["verdict"], strict=True))
        column = [verdicts.get(claim, "") for claim in out["claim"]]
        out[prior_column(multiple)] = column
        for i, (mine, theirs) in enumerate(zip(out["verdict"], column, strict=True)):
            if mine != theirs:
                changed[i].append(f"x{float(multiple):g}")
    out[CHANGED_COLUMN] = [", ".join(c) for c in changed]
    return out


def changed_claims(claims, below=np.inf):
    """The claims whose verdict differs from the stated priors' at some multiple under
    ``below`` (in the order of the table)."""
    columns = [c for c in claims.columns if c.startswith("verdict_prior_x")]
    keep = [c for c in columns if float(c.removeprefix("verdict_prior_x")) < below]
    differs = np.zeros(len(claims), dtype=bool)
    for column in keep:
        differs |= (claims[column] != claims["verdict"]).to_numpy()
    return claims.loc[differs, "claim"].tolist()
