"""How well a fit fits: residual measures and the small-sample AICc, and the result object.

Every model is fitted to the same points and reported with the same measures (sum
of squares, RMSE, largest residual, AICc), so that models compare on equal terms.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["MEASURES", "FitResult", "goodness_of_fit"]

#: The measures of every fit, in the order of :class:`BatchFits` and the tables.
MEASURES = ("sse_mm2", "rmse_mm", "max_abs_residual_mm", "aicc")


@dataclass(frozen=True)
class FitResult:
    """Outcome of one least-squares fit.

    Attributes
    ----------
    model : str
        ``"waterbed"``, ``"shifted"``, ``"arc"``, ``"waterbed_free_depth"`` or
        ``"boussinesq"``.
    params : dict of str to float
        Fitted parameters, units in their names (``L_mm``, ``A_mm``, ``x0_mm``).
    n_points : int
        Number of points fitted.
    n_params : int
        Number of free model parameters (the noise variance not included).
    sse_mm2 : float
        Sum of squared residuals (mm^2).
    rmse_mm : float
        Root-mean-square residual (mm).
    max_abs_residual_mm : float
        Largest absolute residual (mm).
    aicc : float
        Small-sample corrected Akaike information criterion (see
        :func:`goodness_of_fit`).
    residual_mm : numpy.ndarray
        Data minus model at each point, in input order.
    chi2 : float
        With a covariance ``C`` only: ``r' C^-1 r`` of the residuals at the
        minimum (how far the misfit is beyond the noise); NaN without one.
    at_bound : bool
        Whether the fitted L ends on a bound of its search (:func:`at_search_bound`):
        its interval is then one-sided and the value itself is not a measurement.
    """

    model: str
    params: dict
    n_points: int
    n_params: int
    sse_mm2: float
    rmse_mm: float
    max_abs_residual_mm: float
    aicc: float
    residual_mm: np.ndarray = field(repr=False)
    chi2: float = np.nan
    at_bound: bool = False


def _python_float(value):
    """A float for tables and params; NaN is always the ``numpy.nan`` object."""
    value = float(value)
    return np.nan if value != value else value


def _measures(residual_mm, mask, n_params):
    """:func:`goodness_of_fit` for each row of padded residuals."""
    n = np.sum(mask, axis=-1)
    sse = np.sum(np.where(mask, residual_mm, 0.0) ** 2, axis=-1)
    k = n_params + 1
    aicc = np.full(n.shape, np.nan)
    rmse = np.full(n.shape, np.nan)
    largest = np.full(n.shape, np.nan)
    corrected = n - k - 1 > 0
    with np.errstate(divide="ignore"):
        aicc[corrected] = (
            n[corrected] * np.log(sse[corrected] / n[corrected])
            + 2 * k
            + 2 * k * (k + 1) / (n[corrected] - k - 1)
        )
    some = n > 0
    rmse[some] = np.sqrt(sse[some] / n[some])
    largest[some] = np.max(np.where(mask, np.abs(residual_mm), -np.inf), axis=-1)[some]
    return {"sse_mm2": sse, "rmse_mm": rmse, "max_abs_residual_mm": largest, "aicc": aicc}


def goodness_of_fit(residual_mm, n_params):
    """RMSE, largest absolute residual and AICc of a least-squares fit.

    The AICc assumes independent Gaussian errors of unknown variance, which
    counts as one more parameter: with ``k = n_params + 1``,
    ``AICc = n ln(SSE / n) + 2 k + 2 k (k + 1) / (n - k - 1)``.

    Parameters
    ----------
    residual_mm : array_like
        Data minus model (mm).
    n_params : int
        Number of free model parameters.

    Returns
    -------
    dict
        ``sse_mm2``, ``rmse_mm``, ``max_abs_residual_mm`` and ``aicc`` (NaN when
        there are too few points for the correction).
    """
    residual_mm = np.asarray(residual_mm, dtype=float).reshape(1, -1)
    mask = np.ones(residual_mm.shape, dtype=bool)
    measures = _measures(residual_mm, mask, n_params)
    return {name: _python_float(values[0]) for name, values in measures.items()}


class _ChunkFit:
    """One model fitted to the trials of a chunk (:class:`lineload.fitting.windows._Trials`):
    what a solver returns; the engine adds the measures (:func:`_measures`)."""

    def __init__(
        self,
        model,
        trials,
        params,
        residual_mm,
        errors=None,
        at_bound=None,
        prior_share=None,
        wedge_share=None,
    ):
        self.model = model
        self.trials = trials
        self.params = params
        count = trials.n.size
        self.at_bound = np.zeros(count, dtype=bool) if at_bound is None else at_bound
        self.prior_share = np.full(count, np.nan) if prior_share is None else prior_share
        self.wedge_share = np.full(count, np.nan) if wedge_share is None else wedge_share
        self.residual_mm = residual_mm
        self.errors = errors or {}
        self.chi2 = (
            np.full(trials.n.size, np.nan)
            if trials.covariance is None
            else trials.generalised_chi2(residual_mm)
        )
