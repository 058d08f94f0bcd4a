"""The batch engine: every model family fitted to many trials at once, and the fit table.

Every fit takes the same points (distance and deflection in mm) and returns a
:class:`FitResult` with its parameters and the same goodness-of-fit measures,
so that models can be compared on equal terms.

The waterbed fits keep ``W0`` fixed to the indentation depth, as in the paper,
and fit ``L`` alone, constrained to ``L >= max(distance)`` so that every fitted
point lies on the membrane (inside the wall).  Three waterbed variants are
fitted:

``waterbed``
    The paper's procedure: eq. 19, W(X), compared with readings taken at the
    deformed position x as if X were x.
``shifted``
    The same small-slope solution in measured coordinates: W(X) placed at
    ``x = X + U(X)`` (eqs 19-20).  It exists only while that map is one-to-one,
    ``L > sqrt(6) W0``; the fit searches that range only, and when the data
    would want a narrower membrane it stops at the bound (the fitted ``L`` then
    equals ``sqrt(6) W0`` to within the search tolerance and the interval's
    lower end is that bound).
``arc``
    The exact solution, a circular arc in the deformed plane.

The intervals (see :mod:`lineload.fitting.intervals`) are least squares' own: the
fits stay ordinary least squares whatever the noise.  Each family's solver lives in
its own module (:mod:`~lineload.fitting.waterbed`, :mod:`~lineload.fitting.shifted`,
:mod:`~lineload.fitting.arc`, :mod:`~lineload.fitting.free_depth`,
:mod:`~lineload.fitting.boussinesq`), found through the registry
(:mod:`lineload.fitting.families`); the points and their covariances come from
:mod:`lineload.fitting.windows`, the measures from :mod:`lineload.fitting.goodness`.

Batches
-------
Every algorithm here runs on many trials at once (:func:`fit_trials`,
:func:`fit_windowed`, :func:`fit_batch`); the single-trial functions
(:func:`fit_waterbed`, :func:`fit_trial`, ...) are the same code with a batch
of one.  The trials' points are padded to a common length and each step is done
for all trials together by :mod:`lineload.fitting.optimize`.  A trial's numbers do not
depend on its batch beyond rounding: two batchings agree to the tolerance of
:func:`lineload.fitting.optimize.solution_tolerance`, not to the last bit.
"""

from __future__ import annotations

import warnings

import numpy as np

from lineload.fitting.families import FAMILIES, solved_families, table_families
from lineload.fitting.goodness import MEASURES, FitResult, _measures, _python_float, goodness_of_fit
from lineload.fitting.intervals import AT_BOUND_RTOL, at_search_bound
from lineload.fitting.optimize import CHI2_1DOF_95
from lineload.fitting.windows import (
    _as_points,
    _as_trials,
    _Trials,
    in_fit_window,
    window_covariances,
    window_points,
)

__all__ = [
    "AT_BOUND_RTOL",
    "CHI2_1DOF_95",
    "FIT_COLUMNS",
    "MODELS",
    "TABLE_MODELS",
    "WINDOW_MODELS",
    "BatchFits",
    "FitResult",
    "at_search_bound",
    "fit_arc",
    "fit_batch",
    "fit_boussinesq",
    "fit_shifted",
    "fit_trial",
    "fit_trials",
    "fit_waterbed",
    "fit_waterbed_free_depth",
    "fit_windowed",
    "goodness_of_fit",
    "in_fit_window",
    "window_points",
]

#: Trials fitted together (after sorting by number of points, so that little is
#: padded).
CHUNK_TRIALS = 1024

#: The models :func:`fit_batch` knows (the families of the registry with a solver),
#: with their parameters (in ``FitResult.params`` order), number of free parameters and
#: the fewest points each needs.
MODELS = {
    name: (FAMILIES[name].results, FAMILIES[name].n_params, FAMILIES[name].min_points)
    for name in solved_families()
}

#: The models of the fit table, in column order.
TABLE_MODELS = table_families()


class BatchFits:
    """One model fitted to many trials: parameters and measures as arrays, by trial.

    Attributes
    ----------
    model : str
        The model's name (a key of :data:`MODELS`).
    params : dict of str to numpy.ndarray
        Each parameter of the model (``FitResult.params`` names), NaN where the
        trial has no fit.
    measures : dict of str to numpy.ndarray
        ``sse_mm2``, ``rmse_mm``, ``max_abs_residual_mm`` and ``aicc``, NaN where
        the trial has no fit.
    chi2 : numpy.ndarray
        ``r' C^-1 r`` of the residuals at the minimum, given a covariance ``C``;
        NaN without one.
    n_points : numpy.ndarray of int
        Points of each trial.
    fitted : numpy.ndarray of bool
        Whether the trial has a fit (enough points, an admissible L).
    at_bound : numpy.ndarray of bool
        Whether the fitted L ends on a bound of its search (False for a model
        without L, and for a trial without a fit).
    prior_share : numpy.ndarray
        Share of the variance of the model's first parameter (L, or A) that the
        stated priors make (shared offset, tilt and depth error; for A also the
        wedge's position); NaN without a noise model.
    wedge_share : numpy.ndarray
        Share of that variance the wedge's position alone makes (A only: the fits of L
        do not take it in); NaN without a noise model and for the fits of L.
    errors : dict of int to str
        Why a trial has no fit, by trial index.
    """

    def __init__(self, model, n_points):
        count = n_points.size
        self.model = model
        self.params = {name: np.full(count, np.nan) for name in FAMILIES[model].results}
        self.measures = {name: np.full(count, np.nan) for name in MEASURES}
        self.chi2 = np.full(count, np.nan)
        self.n_points = n_points
        self.fitted = np.zeros(count, dtype=bool)
        self.at_bound = np.zeros(count, dtype=bool)
        self.prior_share = np.full(count, np.nan)
        self.wedge_share = np.full(count, np.nan)
        self.errors = {}
        self._chunks = []
        self._where = np.full((count, 2), -1)

    def _add(self, trial_index, chunk):
        ok = np.ones(trial_index.size, dtype=bool)
        for row, message in chunk.errors.items():
            ok[row] = False
            self.errors[int(trial_index[row])] = message
        fitted = trial_index[ok]
        for name, values in chunk.params.items():
            self.params[name][fitted] = values[ok]
        for name, values in chunk.measures.items():
            self.measures[name][fitted] = values[ok]
        self.chi2[fitted] = chunk.chi2[ok]
        self.at_bound[fitted] = chunk.at_bound[ok]
        self.prior_share[fitted] = chunk.prior_share[ok]
        self.wedge_share[fitted] = chunk.wedge_share[ok]
        self.fitted[fitted] = True
        self._where[trial_index, 0] = len(self._chunks)
        self._where[trial_index, 1] = np.arange(trial_index.size)
        self._chunks.append(chunk)

    def __len__(self):
        return self.fitted.size

    def result(self, i):
        """The fit of trial ``i`` as a :class:`FitResult`.

        Raises
        ------
        ValueError
            If the trial has no fit (too few points, no admissible L).
        """
        if not self.fitted[i]:
            raise ValueError(self.errors[i])
        chunk, row = self._where[i]
        chunk = self._chunks[chunk]
        n = int(self.n_points[i])
        return FitResult(
            model=self.model,
            params={name: _python_float(values[i]) for name, values in self.params.items()},
            n_points=n,
            n_params=FAMILIES[self.model].n_params,
            residual_mm=chunk.residual_mm[row, :n].copy(),
            chi2=_python_float(self.chi2[i]),
            at_bound=bool(self.at_bound[i]),
            **{name: _python_float(values[i]) for name, values in self.measures.items()},
        )


def _fit_flat(
    x_mm,
    y_mm,
    counts,
    depth_mm,
    models,
    covariance_mm2=None,
    wedge_sd_mm=0.0,
    prior_covariance_mm2=None,
    intervals=True,
):
    """Fit ``models`` to trials given as concatenated points and counts (``prior_covariance_mm2``:
    the priors' part of each covariance, for the fits' ``prior_share``; ``intervals``: see
    :func:`fit_windowed`)."""
    offsets = np.cumsum(counts) - counts
    fits = {model: BatchFits(model, counts) for model in models}
    for model in models:
        minimum = FAMILIES[model].min_points
        for i in np.flatnonzero(counts < minimum):
            fits[model].errors[int(i)] = (
                f"at least {minimum} points are needed, got {int(counts[i])}"
            )
    order = np.argsort(counts, kind="stable")
    order = order[counts[order] >= 1]
    for start in range(0, order.size, CHUNK_TRIALS):
        chunk = order[start : start + CHUNK_TRIALS]
        covariance = None if covariance_mm2 is None else [covariance_mm2[i] for i in chunk]
        prior = None
        if prior_covariance_mm2 is not None:
            prior = [prior_covariance_mm2[i] for i in chunk]
        trials = _Trials.from_flat(
            x_mm, y_mm, counts[chunk], offsets[chunk], covariance, wedge_sd_mm, prior, intervals
        )
        for model in models:
            entry = FAMILIES[model]
            enough = counts[chunk] >= entry.min_points
            if not enough.any():
                continue
            part = trials if enough.all() else trials.take(np.flatnonzero(enough))
            fitted = entry.solver(part, depth_mm[chunk[enough]])
            fitted.measures = _measures(fitted.residual_mm, part.mask, entry.n_params)
            fits[model]._add(chunk[enough], fitted)
    return fits


def fit_batch(distance_mm, deflection_mm, depth_mm=None, models=tuple(MODELS), covariance_mm2=None):
    """Fit models to many trials at once, each on all of its points.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        One 1-D array per trial (mm); distances > 0, all finite.  Trials may
        differ in length.
    depth_mm : float or array_like, optional
        Indentation depth of each trial (mm), W0 of the fixed-depth waterbed
        fits; needed for those.
    models : iterable of str, optional
        Keys of :data:`MODELS`.
    covariance_mm2 : sequence of array_like, optional
        The covariance of each trial's deflections (mm^2), an ``(n, n)`` matrix
        for a trial of ``n`` points: the intervals honour it (the fits stay
        least squares), taking it as known.

    Returns
    -------
    dict of str to BatchFits
        By model.  A trial with fewer points than a model needs, or without an
        admissible L, has no fit (``BatchFits.result`` raises the ValueError the
        single-trial function raises).

    Raises
    ------
    ValueError
        For a trial whose arrays differ in shape, a distance <= 0, a value that
        is not finite, or a covariance of the wrong shape or not positive
        definite.
    """
    models = tuple(models)
    x_mm, y_mm, counts = _as_trials(distance_mm, deflection_mm)
    if not (np.all(np.isfinite(x_mm)) and np.all(np.isfinite(y_mm))):
        raise ValueError("distances and deflections must be finite")
    if np.any(x_mm <= 0):
        raise ValueError("distances must be > 0 (the load point itself is not fitted)")
    if covariance_mm2 is not None and len(covariance_mm2) != counts.size:
        raise ValueError("covariance_mm2 must hold one matrix per trial")
    if depth_mm is None:
        if any(FAMILIES[model].needs_depth for model in models):
            raise ValueError("the fixed-depth fits need depth_mm")
        depth_mm = np.nan
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), counts.shape)
    return _fit_flat(x_mm, y_mm, counts, depth_mm, models, covariance_mm2)


def _fit_one(model, distance_mm, deflection_mm, depth_mm=np.nan, covariance_mm2=None):
    x, y = _as_points(distance_mm, deflection_mm, minimum=FAMILIES[model].min_points)
    covariance = None if covariance_mm2 is None else [covariance_mm2]
    fits = _fit_flat(x, y, np.array([x.size]), np.array([float(depth_mm)]), (model,), covariance)
    return fits[model].result(0)


def fit_waterbed(distance_mm, deflection_mm, depth_mm, covariance_mm2=None):
    """Fit the small-slope waterbed (eq. 19) with W0 fixed: exact global least squares.

    With ``u = 1 / L`` the model ``W0 (3 u**2 x**2 - 4 u x + 1)`` is quadratic
    in ``u``, so the sum of squared residuals is a quartic in ``u``.
    Its global minimum over ``0 <= u <= 1 / max(x)`` is at a real root of the
    cubic derivative or at an end of that interval; all candidates are compared
    exactly, so no start value or iterative optimiser is involved.  ``u = 0``
    means a flat membrane (``L`` infinite).

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}``, the
        last two the 95 % likelihood interval (see the module's notes).
    """
    return _fit_one("waterbed", distance_mm, deflection_mm, depth_mm, covariance_mm2)


def fit_arc(distance_mm, deflection_mm, depth_mm, covariance_mm2=None):
    """Fit the exact circular-arc waterbed with W0 fixed and L free.

    The one-dimensional least-squares problem in ``L`` over
    ``[max(x), 1000 max(x)]`` is solved by :func:`lineload.fitting.optimize.minimize_bounded`.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}`` with
        the 95 % likelihood interval.
    """
    return _fit_one("arc", distance_mm, deflection_mm, depth_mm, covariance_mm2)


def fit_shifted(distance_mm, deflection_mm, depth_mm, covariance_mm2=None):
    """Fit the small-slope waterbed in measured coordinates, W0 fixed and L free.

    The model is eq. 19's ``W(X)`` at ``x = X + U(X)`` (eq. 20), i.e.
    :func:`lineload.models.shifted_deflection_mm`.  It is defined for
    ``L > sqrt(6) W0`` only (where ``x(X)`` is one-to-one), so the search runs
    over ``[max(max(x), sqrt(6) W0 (1 + 1e-9)), 1000 max(x)]``.  A fit that ends
    on the lower bound means the data want a membrane too narrow for the
    small-slope solution.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0.
    depth_mm : float
        Indentation depth, used as W0 (mm).
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm": L, "L_ci_low_mm": ..., "L_ci_high_mm": ...}`` with
        the 95 % likelihood interval.
    """
    return _fit_one("shifted", distance_mm, deflection_mm, depth_mm, covariance_mm2)


def fit_waterbed_free_depth(distance_mm, deflection_mm, covariance_mm2=None):
    """Fit the small-slope waterbed with both W0 and L free.

    For a given L the model ``W0 g(x)``, ``g = 3 s**2 - 4 s + 1``, is linear in
    W0, whose best value is ``sum(y g) / sum(g**2)``; what remains is a one-dimensional problem in L
    (``L >= max(x)``).  The interval on L profiles W0 out.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two.
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"L_mm", "L_ci_low_mm", "L_ci_high_mm", "W0_mm"}``.
    """
    return _fit_one("waterbed_free_depth", distance_mm, deflection_mm, np.nan, covariance_mm2)


def fit_boussinesq(distance_mm, deflection_mm, covariance_mm2=None):
    """Fit the modified Boussinesq profile ``A ln(x0 / x)``: linear least squares.

    The model is a straight line in ``ln x``: ``w = A ln x0 - A ln x``, so the
    fit is an exact linear regression (centred, in closed form).  ``x0`` is
    reported as NaN when the slope has the wrong sign (``A <= 0``), where the
    form has no zero crossing.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        Averaged profile points (mm); distances > 0, at least two distinct.
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2): the interval honours it (the fit
        itself stays least squares).

    Returns
    -------
    FitResult
        ``params = {"A_mm": A, "x0_mm": x0}``.
    """
    return _fit_one("boussinesq", distance_mm, deflection_mm, np.nan, covariance_mm2)


#: Columns of the fit table, in order (one row per subject and depth): the trial's,
#: then each family's of the table (:attr:`Family.table_columns`, registry order).
FIT_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "fit_window_mm",
    "n_points",
    "max_distance_mm",
    *(FAMILIES[name].column(c) for name in TABLE_MODELS for c in FAMILIES[name].table_columns),
]


def fit_windowed(
    distance_mm,
    deflection_mm,
    depth_mm,
    window_mm,
    models=tuple(MODELS),
    noise=None,
    n_sides=None,
    intervals=True,
):
    """Fit models to many trials at once, each on its points inside a fit window.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm), W0 of the fixed-depth waterbed fits.
    window_mm : float or array_like
        Points with ``0 < distance <= window_mm`` and a finite deflection are fitted.
    models : iterable of str, optional
        Keys of :data:`MODELS`.
    noise : lineload.noise.NoiseModel or sequence of NoiseModel, optional
        The digitising noise, one model for every trial or one per trial: the
        intervals honour each trial's covariance (the fits themselves stay least
        squares; see the module's notes).  Without it, least squares with
        intervals from the residuals (independent errors).
    n_sides : sequence of array_like, optional
        With ``noise``: how many sides were read at each point of each trial
        (2 everywhere if not given).
    intervals : bool, optional
        False: the fits alone, for a refit that only follows a parameter (the
        searched fits' intervals, which cost about as much as the search, and their
        prior shares are NaN; the waterbed's closed-form fit keeps its cheap interval).

    Returns
    -------
    dict
        ``n_points`` and ``max_distance_mm`` (arrays by trial, NaN for a trial
        without points) and each model's :class:`BatchFits` by its name.
    """
    x_mm, y_mm, counts = window_points(distance_mm, deflection_mm, window_mm)
    depth_mm = np.broadcast_to(np.asarray(depth_mm, dtype=float), counts.shape)
    covariance_mm2, wedge_sd_mm, prior_covariance_mm2 = None, 0.0, None
    if noise is not None:
        if not isinstance(noise, (list, tuple)):
            noise = [noise] * counts.size
        if len(noise) != counts.size:
            raise ValueError("noise must be one model or one per trial")
        # a dataset's prior: the same in every trial's model
        wedge_sd_mm = max((n.wedge_position_sd_mm for n in noise), default=0.0)
        if n_sides is None:
            n_sides = [np.full(np.shape(x), 2.0) for x in distance_mm]
        window = np.broadcast_to(np.asarray(window_mm, dtype=float), counts.shape)
        covariance_mm2 = window_covariances(
            distance_mm, deflection_mm, depth_mm, window, noise, n_sides
        )
        priors_only = [n.priors_only() for n in noise]
        prior_covariance_mm2 = window_covariances(
            distance_mm, deflection_mm, depth_mm, window, priors_only, n_sides
        )
    fits = _fit_flat(
        x_mm,
        y_mm,
        counts,
        depth_mm,
        tuple(models),
        covariance_mm2,
        wedge_sd_mm,
        prior_covariance_mm2,
        intervals,
    )
    max_distance_mm = np.full(counts.size, np.nan)
    some = counts > 0
    if some.any():
        max_distance_mm[some] = np.maximum.reduceat(x_mm, (np.cumsum(counts) - counts)[some])
    return {"n_points": counts, "max_distance_mm": max_distance_mm, **fits}


#: The fits whose L the fit table follows across other windows (:func:`fit_trials`).
WINDOW_MODELS = tuple(m for m in TABLE_MODELS if "L_window_min_mm" in FAMILIES[m].table_columns)


def fit_trials(
    distance_mm,
    deflection_mm,
    depth_mm,
    window_mm,
    noise=None,
    n_sides=None,
    other_windows_mm=(),
):
    """Fit every model of the fit table to many trials, each on its windowed points.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm), one 1-D array per trial.
    depth_mm : float or array_like
        Indentation depth of each trial (mm), W0 of the waterbed fits.
    window_mm : float or array_like
        Points with ``0 < distance <= window_mm`` are fitted.
    noise : lineload.noise.NoiseModel or sequence of NoiseModel, optional
        The digitising noise, for all trials or per trial (the intervals honour it;
        see :func:`fit_windowed`).
    n_sides : sequence of array_like, optional
        Sides read at each point of each trial (with ``noise``).
    other_windows_mm : sequence of float or None, optional
        Further windows (None or infinity: the whole profile) in which the waterbed
        fits' L is found again: ``{model}_L_window_min_mm`` and ``_max_mm`` give
        the smallest and largest L over these and ``window_mm`` (L is the
        half-width *for a window*; the spread is a sensitivity, not part of the
        95 % interval).  Without any, those columns equal L.

    Returns
    -------
    list of dict
        One row per trial, as :func:`fit_trial` gives it.
    """
    fits = fit_windowed(
        distance_mm, deflection_mm, depth_mm, window_mm, TABLE_MODELS, noise, n_sides
    )
    count = fits["n_points"].size
    columns = {
        "depth_mm": np.broadcast_to(np.asarray(depth_mm, dtype=float), count).tolist(),
        "fit_window_mm": np.broadcast_to(np.asarray(window_mm, dtype=float), count).tolist(),
        "n_points": fits["n_points"].tolist(),
        "max_distance_mm": fits["max_distance_mm"].tolist(),
    }
    for model in TABLE_MODELS:
        fit = fits[model]
        for name, values in (*fit.params.items(), *list(fit.measures.items())[1:]):
            columns[f"{model}_{name}"] = values.tolist()
        first = next(iter(fit.params)).removesuffix("_mm")
        columns[f"{model}_{first}_prior_share"] = fit.prior_share.tolist()
        if f"{first}_wedge_share" in FAMILIES[model].table_columns:
            columns[f"{model}_{first}_wedge_share"] = fit.wedge_share.tolist()
        if "L_mm" in fit.params:
            columns[f"{model}_L_at_bound"] = fit.at_bound.tolist()
    spread = {model: [fits[model].params["L_mm"]] for model in WINDOW_MODELS}
    for other in other_windows_mm:
        other = np.inf if other is None else float(other)
        if np.all(np.asarray(window_mm, dtype=float) == other):
            continue  # the fit window itself (the same L: the fits are least squares)
        refit = fit_windowed(
            distance_mm, deflection_mm, depth_mm, other, WINDOW_MODELS, intervals=False
        )
        for model in WINDOW_MODELS:
            spread[model].append(refit[model].params["L_mm"])
    for model, values in spread.items():
        values = np.array(values)
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a trial without any fit
            columns[f"{model}_L_window_min_mm"] = np.nanmin(values, axis=0).tolist()
            columns[f"{model}_L_window_max_mm"] = np.nanmax(values, axis=0).tolist()
    for name, values in columns.items():
        if name != "n_points" and not name.endswith("_at_bound"):
            columns[name] = [np.nan if v != v else v for v in values]
    names = list(columns)
    return [dict(zip(names, row, strict=True)) for row in zip(*columns.values(), strict=True)]


def fit_trial(distance_mm, deflection_mm, depth_mm, window_mm):
    """Fit every model to one trial on the same points.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        The averaged profile of one subject at one depth (mm).
    depth_mm : float
        Indentation depth (mm), W0 of both waterbed fits.
    window_mm : float
        Points with ``0 < distance <= window_mm`` are fitted.

    Returns
    -------
    dict
        The model columns of :data:`FIT_COLUMNS` (all but ``subject`` and
        ``species``).  A model that needs more points than the window holds
        gets NaN.
    """
    return fit_trials([distance_mm], [deflection_mm], [depth_mm], window_mm)[0]
