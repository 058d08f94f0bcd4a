"""Fitting the models to the averaged profiles, one trial or a whole batch at a time.

The public face: what scripts, tests and the other wings use.  One idea per module:

Modules
-------
families
    The registry of model families: curve, parameters, solver, columns, colour.
batch
    The batch engine: every family fitted to many trials at once; the fit table.
windows
    The points a fit sees (the fit window), padded batches, their covariances.
goodness
    Residual measures and the AICc; the :class:`FitResult` of one fit.
intervals
    The 95 % intervals on L (profile likelihood or sandwich) and bounds of L.
optimize
    The bounded one-parameter least-squares solver shared by the searched fits.
waterbed, shifted, arc, free_depth, boussinesq
    Each family's solver (``search`` holds what the searched ones share).
bending
    Fits of the bending skin (tension with bending stiffness), its own table.
inputs
    The trials of a batch as the fit jobs read them (points, sides, noise, keys).
sensitivity
    Refits under other choices (windows, weights, models) to show what each choice moves.
"""

from lineload.fitting.batch import (
    FIT_COLUMNS,
    MODELS,
    TABLE_MODELS,
    WINDOW_MODELS,
    BatchFits,
    fit_arc,
    fit_batch,
    fit_boussinesq,
    fit_shifted,
    fit_trial,
    fit_trials,
    fit_waterbed,
    fit_waterbed_free_depth,
    fit_windowed,
)
from lineload.fitting.bending import (
    BENDING_COLUMNS,
    BENDING_LENGTH_BOUNDS_MM,
    fit_bending,
    fit_bending_trials,
    with_bending,
)
from lineload.fitting.families import FAMILIES, Family, Parameter, curve_mm, family
from lineload.fitting.goodness import FitResult, goodness_of_fit
from lineload.fitting.inputs import Batch, labelled_rows, read_batch
from lineload.fitting.intervals import AT_BOUND_RTOL, at_search_bound
from lineload.fitting.optimize import CHI2_1DOF_95
from lineload.fitting.windows import (
    in_fit_window,
    window_covariance,
    window_covariances,
    window_points,
)

__all__ = [
    "AT_BOUND_RTOL",
    "BENDING_COLUMNS",
    "BENDING_LENGTH_BOUNDS_MM",
    "CHI2_1DOF_95",
    "FAMILIES",
    "FIT_COLUMNS",
    "MODELS",
    "TABLE_MODELS",
    "WINDOW_MODELS",
    "Batch",
    "BatchFits",
    "Family",
    "FitResult",
    "Parameter",
    "at_search_bound",
    "curve_mm",
    "family",
    "fit_arc",
    "fit_batch",
    "fit_bending",
    "fit_bending_trials",
    "fit_boussinesq",
    "fit_shifted",
    "fit_trial",
    "fit_trials",
    "fit_waterbed",
    "fit_waterbed_free_depth",
    "fit_windowed",
    "goodness_of_fit",
    "in_fit_window",
    "labelled_rows",
    "read_batch",
    "window_covariance",
    "window_covariances",
    "window_points",
    "with_bending",
]
