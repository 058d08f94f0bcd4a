"""The digitising noise: measured from the left-right differences, stated where it cannot be.

Every reading of a profile carries the error of the hand that traced it.  The
model used here (per side of the wedge, at distance ``x`` from it, tissue mm):

* ``reading``: independent error of each reading, SD ``reading_sd_mm``;
* ``tracing``: an error that wanders along the outline, SD ``tracing_sd_mm``,
  correlated over a distance ``tracing_length_mm`` (exponential kernel
  ``exp(-|x - x'| / length)``: the reading grid is irregular, so the kernel is
  one of distance, not of reading number);
* ``side offset``: an offset of one side's whole trace, SD ``side_offset_sd_mm``;
* ``rotation``: a small rotation of the photograph, which raises one side as
  much as it lowers the other (``+t x`` on the right, ``-t x`` on the left);
* ``wedge position``: the wedge placed ``delta`` mm off its true position
  along the outline, so one side's distances are too long and the other's too
  short (to first order, ``+/- delta w'(x)``; the left-right mean keeps the
  second-order ``w''(x) delta**2 / 2``, which matters only where the profile is
  sharply curved, as the log-singular Boussinesq form is near the wedge);

and shared by both sides of a trace, which the left-right difference cancels:

* ``shared offset`` (SD ``shared_offset_sd_mm``) and ``shared tilt`` (SD
  ``shared_tilt_sd``, a symmetric ``t |x|``) of the superimposed outlines;
* ``depth error``: the indentation differs from its nominal depth by a small
  amount (SD ``depth_sd_mm``); the profile then scales as ``w (1 + e / W0)``.

The left-minus-right difference of a trial, ``d(x)``, holds everything of the
first list: an offset (two side offsets), a slope (the rotation), a multiple of
the profile's slope (the wedge position) and the reading and tracing errors of
both sides; and the true difference between the two sides, which a finger need
not make symmetric (two membranes of spans ``L_l`` and ``L_r`` differ by a line
and a parabola in ``x``).  :func:`estimate_noise` fits it by restricted maximum
likelihood, with the offset, slope, wedge-position and quadratic terms of each
trial as fixed effects, so none of them is mistaken for correlated noise, and
the reading and tracing parts as the covariance ``2 (reading^2 I + tracing^2 K)``.
The profile's slope is taken from the left-right mean (a model-free local fit): the mean's
errors are independent of the difference's when both sides are read alike.
The model under test never enters, so the misfit that some claims are about
cannot leak into the noise.  What is measured: the reading error, the tracing
error and its length (:data:`MEASURED`).

The side offsets and the rotation are in the differences but not measured from
them.  Their traces there, a constant and a line, are nearly reproduced by the
other per-trial terms the fit must leave free: on a membrane-shaped profile the
slope ``w'(x)`` is nearly a line near the wedge, so a slope, a parabola and a
multiple of ``w'`` together reproduce all but a few parts in a hundred thousand
of a constant (:func:`constant_explained`), and the spread of the trials' offsets
is a small difference of large numbers: on held-out data with side offsets of
SD 4 um it came out anywhere from 0 to 20 um (docs/calibration/heldout_arc.md).
A rotation cancels in the left-right mean where both sides were read; a side
offset does not, and the mean carries half its variance, a constant like the
shared offset's.  So the shared-offset prior stands for the mean's whole
constant error (the registration's offset and half the side offsets' variance,
:attr:`NoiseModel.mean_offset_sd_mm`), and where one side alone was read the
shared tilt's prior stands for the rotation (:func:`noise_rows`).

What the differences cancel cannot be measured from these data: the shared
offset, the shared tilt and the depth error are priors (config, with their
source), and every interval built on :meth:`NoiseModel.average_covariance_mm2`
is conditional on them.  So is the wedge position: the differences do hold it,
but only as a multiple of the profile's slope, which the true difference
between two sides of one finger also is; measured from the spread of that
term it came out nil on the shipped reconstruction (made with 10 um) and 13 um
on simulated Boussinesq profiles (where the first-order term is too crude at
the first readings).  The fixed effect stays, so that neither the wedge nor an
asymmetry is mistaken for noise; its size is the config's prior.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

import numpy as np

from lineload.trials import trial_label

__all__ = [
    "MEASURED",
    "MIN_DIFFERENCES",
    "NOISE_COLUMNS",
    "PRIORS",
    "PRIOR_BASIS",
    "TRIAL_PRIORS",
    "UNMEASURED",
    "NoiseEstimate",
    "NoiseModel",
    "average_covariances_mm2",
    "constant_explained",
    "draw_side_errors_mm",
    "estimate_noise",
    "exponential_kernel",
    "measure_noise_table",
    "model_from_rows",
    "noise_rows",
    "noise_trials",
    "reading_noise_mm",
    "registration_rows",
    "trial_differences",
    "trial_models",
]

#: Parameters measured from the left-right differences, in the order of the fit.
MEASURED = ("reading_sd_mm", "tracing_sd_mm", "tracing_length_mm")
#: Per-side errors the differences hold but cannot measure (see the module's
#: description), and what the noise table says of each: the prior that stands for it.
UNMEASURED = {
    "side_offset_sd_mm": "not measured: in the left-right differences a side offset is "
    "a constant, which the slope, parabola and wedge terms each trial's difference must "
    "leave free reproduce on membrane-shaped profiles; the left-right mean carries half "
    "its variance, a constant like the shared offset, and the prior "
    "noise.shared_offset_sd_mm stands for both (the mean's whole constant error)",
    "rotation_sd": "not measured: in the left-right differences a rotation is a line, "
    "which the offset, parabola and wedge terms reproduce as they do a constant; it "
    "cancels in the left-right mean, and where one side alone was read the prior "
    "noise.shared_tilt_sd (the outlines superimposed to a slope) stands for it",
}
#: Parameters the differences cannot see: priors from the config.
PRIORS = ("shared_offset_sd_mm", "shared_tilt_sd", "depth_sd_mm", "wedge_position_sd_mm")
#: What each prior rests on, for the noise table's source column: none is a measurement
#: or a cited accuracy, and the synthetic reconstruction was made with the same values,
#: so its calibration cannot test them (the fit tables give each interval's share of
#: variance from them, ``*_prior_share``).
PRIOR_BASIS = {
    "shared_offset_sd_mm": "assumed default for the whole constant error of the left-right "
    "mean: the two outlines superimposed, and each side's trace placed, to about 0.1 mm on "
    "the 20x print (5 um in tissue each; the mean keeps the first whole and half the "
    "variance of the other two, 6.1 um)",
    "shared_tilt_sd": "assumed default: the outlines superimposed to a slope of 0.1 mm "
    "over 10 cm of the 20x print",
    "depth_sd_mm": "assumed default: a positioner read to about 10 um",
    "wedge_position_sd_mm": "assumed default: the apex marked to about 0.2 mm on the 20x "
    "print (the wedge's edge is under 50 um wide)",
}
#: Parameters a trial may replace with its own measurement: a photographed trial's
#: registration error (in place of the shared offset's prior) and its readings' own
#: error as the digitiser states it (in place of the dataset's reading error, which
#: pools the trials of every kind); the others hold for the whole dataset.
TRIAL_PRIORS = ("shared_offset_sd_mm", "reading_sd_mm")
#: Scope of the noise table's rows that hold for a whole dataset; a trial's own rows
#: name the trial (:func:`_trial_scope`).
DATASET_SCOPE = "dataset"
#: Columns of the noise table.
NOISE_COLUMNS = ["scope", "parameter", "value", "se", "source", "n_trials", "n_differences"]
#: Fewest differences a trial needs to enter the noise fit (four fixed effects
#: leave too little below this).
MIN_DIFFERENCES = 5
#: Smallest standard deviation searched (mm): far below any reading's resolution.
_LOG_FLOOR = math.log(1e-7)
#: L-BFGS-B's stopping rules, tightened: where one error dominates, the likelihood is
#: nearly flat in the other's logarithm and the default tolerances stop short of the
#: optimum (a white-noise dataset then showed a spurious tracing error).
_OPTIMISER_OPTIONS = {"ftol": 1e-14, "gtol": 1e-9, "maxiter": 2000}


def exponential_kernel(distance_mm, length_mm):
    """Correlation ``exp(-|x_i - x_j| / length)`` of readings at distances ``x``.

    Parameters
    ----------
    distance_mm : array_like
        Positions along the outline (mm), shape ``(..., n)``.
    length_mm : float or array_like
        Correlation length (mm), >= 0 (0: white noise, each reading correlated with
        itself alone); an array broadcasts against ``(..., n, n)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., n, n)``.
    """
    x = np.asarray(distance_mm, dtype=float)
    apart = np.abs(x[..., :, None] - x[..., None, :])
    with np.errstate(divide="ignore", invalid="ignore"):
        # a reading with itself correlates fully, also at a zero length
        return np.where(apart == 0.0, 1.0, np.exp(-apart / length_mm))


@dataclass(frozen=True)
class NoiseModel:
    """Standard deviations of every digitising error (see the module's description).

    Attributes
    ----------
    reading_sd_mm, tracing_sd_mm, tracing_length_mm : float
        Measured per side (mm; the length in mm along the outline).
    side_offset_sd_mm : float
        Offset of one side's whole trace (mm): made by the simulations, not measured
        (:data:`UNMEASURED`); a fit's model has it at zero and its share of the mean's
        constant error in ``shared_offset_sd_mm``.
    rotation_sd : float
        Rotation of the photograph (rad); cancels in the left-right mean; not
        measured, like the side offset.
    wedge_position_sd_mm : float
        Prior: misplacement of the wedge along the outline (mm); cancels in the
        mean to first order, and cannot be told apart from an asymmetry of the
        finger in the difference.
    shared_offset_sd_mm, shared_tilt_sd, depth_sd_mm : float
        Priors: shared by both sides, invisible in their difference.
    """

    reading_sd_mm: float
    tracing_sd_mm: float = 0.0
    tracing_length_mm: float = 1.0
    side_offset_sd_mm: float = 0.0
    rotation_sd: float = 0.0
    wedge_position_sd_mm: float = 0.0
    shared_offset_sd_mm: float = 0.0
    shared_tilt_sd: float = 0.0
    depth_sd_mm: float = 0.0

    def side_covariance_mm2(self, distance_mm):
        """Covariance of one side's errors at ``distance_mm`` (reading, tracing, offset)."""
        x = np.asarray(distance_mm, dtype=float)
        eye = np.eye(x.shape[-1])
        return (
            self.reading_sd_mm**2 * eye
            + self.tracing_sd_mm**2 * exponential_kernel(x, self.tracing_length_mm)
            + self.side_offset_sd_mm**2
        )

    def average_covariance_mm2(self, distance_mm, n_sides, deflection_mm, depth_mm):
        """Covariance of a trial's left-right mean, every error included.

        Parameters
        ----------
        distance_mm : array_like
            The averaged profile's distances (mm), shape ``(n,)``.
        n_sides : array_like
            How many sides were read at each distance (1 or 2).  Where one side
            only was read, its error is not halved and the rotation stays.
        deflection_mm : array_like
            The averaged deflections (mm): the depth error scales the profile,
            ``w e / W0``, and the profile is its own best estimate of ``w``.
        depth_mm : float
            Nominal depth (mm).

        Returns
        -------
        numpy.ndarray
            ``(n, n)`` covariance (mm^2).
        """
        x = np.asarray(distance_mm, dtype=float)
        covariances = average_covariances_mm2(
            [self], x[None], np.asarray(n_sides, dtype=float)[None],
            np.asarray(deflection_mm, dtype=float)[None], [depth_mm],
        )  # fmt: skip
        return covariances[0]

    @property
    def mean_offset_sd_mm(self):
        """SD of the constant error of the left-right mean where both sides were read:
        the shared offset and half the variance of the side offsets,
        ``sqrt(shared**2 + side**2 / 2)``."""
        return math.hypot(self.shared_offset_sd_mm, self.side_offset_sd_mm / math.sqrt(2))

    def as_stated(self):
        """The model a lab that knew these sizes would give the fit: the side offsets,
        which the differences do not measure, folded into the shared-offset prior
        (:attr:`mean_offset_sd_mm`), and themselves at zero."""
        return replace(self, shared_offset_sd_mm=self.mean_offset_sd_mm, side_offset_sd_mm=0.0)

    def priors_only(self):
        """A copy with every measured part (and the rotation) at zero: its
        :meth:`average_covariance_mm2` is the part of the covariance the stated priors
        make (shared offset, tilt, depth error), linear in their variances."""
        return replace(
            self, reading_sd_mm=0.0, tracing_sd_mm=0.0, side_offset_sd_mm=0.0, rotation_sd=0.0
        )

    def scaled_priors(self, multiple):
        """A copy with every prior's standard deviation (:data:`PRIORS`) times ``multiple``."""
        return replace(self, **{name: multiple * getattr(self, name) for name in PRIORS})

    def with_priors(self, **priors):
        """A copy with the prior standard deviations replaced."""
        return replace(self, **priors)

    def as_dict(self):
        """The parameters by name."""
        return asdict(self)


def average_covariances_mm2(models, distance_mm, n_sides, deflection_mm, depth_mm):
    """:meth:`NoiseModel.average_covariance_mm2` of many trials at once.

    Parameters
    ----------
    models : sequence of NoiseModel
        One per trial.
    distance_mm, n_sides, deflection_mm : numpy.ndarray
        Shape ``(T, n)``: each trial's points, padded after its last point with NaN
        distances (whatever the other two hold there): a NaN distance is padding, its
        row and column zero.
    depth_mm : array_like
        Nominal depth of each trial (mm), shape ``(T,)``.

    Returns
    -------
    numpy.ndarray
        ``(T, n, n)`` (mm^2): each trial's covariance, zero in its padding.
    """
    x = np.asarray(distance_mm, dtype=float)
    points = np.isfinite(x)
    x = np.where(points, x, 0.0)
    sides = np.where(points, np.asarray(n_sides, dtype=float), 2.0)

    def size(name, power=2):
        return np.array([getattr(m, name) for m in models], dtype=float)[:, None, None] ** power

    both = sides >= 2
    # independent per side: each pair of points shares the sides read at both
    shared_sides = np.where(both[:, :, None] & both[:, None, :], 2.0, 1.0)
    weight = shared_sides / np.maximum(sides[:, :, None] * sides[:, None, :], 1.0)
    kernel = exponential_kernel(x, size("tracing_length_mm", 1))
    tracing = np.where(size("tracing_sd_mm") > 0, size("tracing_sd_mm") * kernel, 0.0)
    side = size("reading_sd_mm") * np.eye(x.shape[1]) + tracing + size("side_offset_sd_mm")
    covariance = side * weight
    # a rotation cancels where both sides were read; its sign where one was is
    # unknown here, so its variance is added to those points alone
    rotation = np.where(both, 0.0, size("rotation_sd", 1)[:, :, 0] * x)
    covariance += rotation[:, :, None] ** 2 * np.eye(x.shape[1])
    depth = np.asarray(depth_mm, dtype=float)[:, None]
    w = np.clip(np.where(points, np.asarray(deflection_mm, dtype=float), 0.0), 0.0, None)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = np.where(depth > 0, w / depth, 0.0)
    covariance += size("shared_offset_sd_mm")
    covariance += size("shared_tilt_sd") * (x[:, :, None] * x[:, None, :])
    covariance += size("depth_sd_mm") * (scale[:, :, None] * scale[:, None, :])
    return np.where(points[:, :, None] & points[:, None, :], covariance, 0.0)


def draw_side_errors_mm(rng, distance_mm, model, kernel="exponential", df=None):
    """Errors of one side's readings that are independent of the other side.

    Parameters
    ----------
    rng : numpy.random.Generator
    distance_mm : array_like
        Reading positions (mm).
    model : NoiseModel
        Sizes of the reading, tracing and side-offset errors.
    kernel : {"exponential", "squared_exponential"}, optional
        Correlation of the tracing error; the second is one the estimator does
        not assume (for robustness studies).
    df : float, optional
        Draw the reading errors from a Student t with ``df`` degrees of freedom,
        scaled to the same SD (heavy tails), instead of a Gaussian.

    Returns
    -------
    numpy.ndarray
        One error per reading (mm).
    """
    x = np.asarray(distance_mm, dtype=float)
    if df is None:
        reading = rng.normal(0.0, model.reading_sd_mm, x.size)
    else:
        reading = rng.standard_t(df, x.size) * model.reading_sd_mm * math.sqrt((df - 2) / df)
    if kernel == "exponential":
        correlation = exponential_kernel(x, model.tracing_length_mm)
    elif kernel == "squared_exponential":
        correlation = np.exp(-0.5 * ((x[:, None] - x[None, :]) / model.tracing_length_mm) ** 2)
    else:
        raise ValueError(f"unknown kernel {kernel!r}")
    values, vectors = np.linalg.eigh(correlation)
    tracing = vectors @ (np.sqrt(np.clip(values, 0.0, None)) * rng.normal(0.0, 1.0, x.size))
    offset = rng.normal(0.0, model.side_offset_sd_mm)
    return reading + model.tracing_sd_mm * tracing + offset


def trial_differences(distance_mm, left_mm, right_mm, window_mm=np.inf):
    """Where both sides were read: the distances, left minus right, and the mean's slope.

    Parameters
    ----------
    distance_mm, left_mm, right_mm : array_like
        One trial's averaged profile with each side's value (NaN where a side was
        not read).
    window_mm : float, optional
        Only distances ``0 < x <= window_mm``: the region the fits use, where
        the two sides' true profiles differ smoothly (beyond it one side may
        have reached its edge and the other not).

    Returns
    -------
    tuple of numpy.ndarray
        ``(distance_mm, difference_mm, slope)``: the slope of the left-right mean
        on the points both sides share (:func:`_local_slope`), the regressor of a
        misplaced wedge.
    """
    x, left, right = (np.asarray(v, dtype=float) for v in (distance_mm, left_mm, right_mm))
    both = _both_read(x, left, right, window_mm)
    x, left, right = x[both], left[both], right[both]
    mean = 0.5 * (left + right)
    return x, left - right, _local_slope(x, mean)


def _local_slope(x, w):
    """The slope of ``w(x)`` at each reading, from ``a + b x + c ln x`` through it and
    its neighbours (the first and last readings: the three nearest).

    Exact for a profile that is straight near the wedge, as a membrane's is, and
    for one that is logarithmic, as the Boussinesq form is (where differences in
    ``x`` miss the first reading's slope by a third); two readings give their
    difference quotient, one gives zero.
    """
    n = x.size
    if n < 3:
        return np.gradient(w, x) if n == 2 else np.zeros_like(x)
    start = np.clip(np.arange(n) - 1, 0, n - 3)
    near = start[:, None] + np.arange(3)
    xs = x[near]
    basis = np.stack([np.ones_like(xs), xs, np.log(xs)], axis=-1)
    coefficients = np.linalg.solve(basis, w[near][..., None])[..., 0]
    return coefficients[:, 1] + coefficients[:, 2] / x


def _both_read(distance_mm, left_mm, right_mm, window_mm):
    """Where both sides were read inside the window."""
    x = distance_mm
    return np.isfinite(left_mm) & np.isfinite(right_mm) & (x > 0) & (x <= window_mm)


def _evenly(items, count):
    """At most ``count`` of ``items``, taken evenly through the sequence."""
    if len(items) <= count:
        return list(items)
    pick = np.unique(np.linspace(0, len(items) - 1, count).round().astype(int))
    return [items[i] for i in pick]


def noise_trials(profiles, window_mm=np.inf, max_trials=400):
    """The left-right differences of the trials the noise is measured from.

    Parameters
    ----------
    profiles : sequence of tuple
        ``(distance_mm, left_mm, right_mm)`` of every trial of the dataset.
    window_mm : float, optional
        As in :func:`trial_differences`.
    max_trials : int, optional
        As in :func:`estimate_noise`: the trials with enough differences, at most
        this many, taken evenly through the sequence (chosen before any slope is
        computed, so a dataset of ten thousand subjects costs no more than the
        reading).

    Returns
    -------
    list of tuple
        :func:`trial_differences` of each chosen trial.
    """
    usable = [
        profile
        for profile in profiles
        if np.count_nonzero(_both_read(*profile, window_mm)) >= MIN_DIFFERENCES
    ]
    return [trial_differences(*profile, window_mm) for profile in _evenly(usable, max_trials)]


@dataclass(frozen=True)
class NoiseEstimate:
    """What :func:`estimate_noise` measured.

    Attributes
    ----------
    model : NoiseModel
        The measured parts, with the priors at zero (add them with
        :meth:`NoiseModel.with_priors`).
    se : dict
        Standard error of each measured parameter (NaN where the likelihood is
        flat, e.g. a length when the tracing error is nil).
    n_trials, n_differences : int
        Trials and left-right differences used.
    """

    model: NoiseModel
    se: dict
    n_trials: int
    n_differences: int


def _padded(trials, columns=4):
    """Trials' differences stacked, padded with decoupled rows that add nothing.

    Returns the stacked distances, differences, fixed-effect designs and the
    mask of real rows, and the distinct reading grids: ``grids`` (distances and
    mask of each) and ``group``, the grid of every trial.  Trials read on one
    grid share their covariance, so each grid's is factorised once.
    """
    width = max(t[0].size for t in trials)
    count = len(trials)
    x = np.zeros((count, width))
    d = np.zeros((count, width))
    design = np.zeros((count, width, columns))
    real = np.zeros((count, width), dtype=bool)
    for i, (xi, di, slope) in enumerate(trials):
        n = xi.size
        x[i, :n], d[i, :n], real[i, :n] = xi, di, True
        design[i, :n, 0] = 1.0
        design[i, :n, 1] = xi
        design[i, :n, 2] = slope
        design[i, :n, 3] = xi**2
    keys, first, group = np.unique(
        np.concatenate([x, real], axis=1), axis=0, return_index=True, return_inverse=True
    )
    del keys
    return x, d, design, real, (x[first], real[first]), group.reshape(-1)


def _covariances(theta, x, real):
    """``2 (reading^2 I + tracing^2 K)`` on every grid; identity on padded rows."""
    reading, tracing, length = np.exp(theta)
    kernel = exponential_kernel(x, length)
    pair = real[:, :, None] & real[:, None, :]
    eye = np.eye(x.shape[1])
    covariance = np.where(pair, 2.0 * (reading**2 * eye + tracing**2 * kernel), 0.0)
    return covariance + np.where(real, 0.0, 1.0)[:, :, None] * eye


def _restricted_terms(theta, d, design, grids, group, gradient=False):
    """-2 log restricted likelihood (up to a constant), GLS effects and their covariance.

    With ``gradient``, also its gradient by the log-parameters (REML's score,
    ``tr(P dV) - r' dV r`` summed over the trials, with ``P`` the projection of the
    residuals and ``r = P d``), as a fifth element.
    """
    chol = np.linalg.cholesky(_covariances(theta, *grids))
    # whiten with each grid's inverse factor: z = L^-1 d, Z = L^-1 X
    inverse_factor = np.linalg.inv(chol)
    whiten = inverse_factor[group]
    zd = (whiten @ d[..., None])[..., 0]
    zx = whiten @ design
    zx_t = zx.transpose(0, 2, 1)
    information = zx_t @ zx
    # a column that is zero for a trial (e.g. a flat profile's slope) is dropped
    diagonal = np.einsum("tii->ti", information)
    dead = diagonal <= 1e-12 * np.maximum(diagonal.max(axis=1, keepdims=True), 1e-300)
    information = information + np.eye(design.shape[2]) * dead[:, :, None]
    information_chol = np.linalg.cholesky(information)
    effects = np.linalg.solve(information, zx_t @ zd[..., None])
    residual = zd - (zx @ effects)[..., 0]
    effects = effects[..., 0]
    log_det = 2.0 * np.log(np.einsum("gii->gi", chol)).sum(axis=1)
    value = (
        log_det[group].sum()
        + 2.0 * np.log(np.einsum("tii->ti", information_chol)).sum()
        + np.sum(residual**2)
    )
    covariance = np.linalg.inv(information)
    if not gradient:
        return value, effects, covariance, dead
    return (
        value,
        effects,
        covariance,
        dead,
        _score(theta, zx @ covariance, zx, residual, grids, group, inverse_factor),
    )


def _score(theta, spread, zx, residual, grids, group, inverse_factor):
    """Gradient of -2 log restricted likelihood by the log-parameters (REML's score).

    Per trial ``tr(P dV) - r' dV r``, with ``P = W' (I - H) W``, ``H = Z M^-1 Z'`` and
    ``r = P d = W' e`` (``W`` the inverse Cholesky factor, ``Z = W X``, ``e`` the whitened
    residual).  The trials of one grid share ``W`` and ``dV``, so their sum is
    ``tr(S dV)`` with ``S = n V^-1 - W' R W`` and ``R`` the sum of ``H + e e'`` over them;
    ``dV`` by the log-parameters is ``4 a^2 I``, ``4 b^2 K`` and ``2 b^2 K |dx| / l``
    (``V = 2 (a^2 I + b^2 K)``, ``K = exp(-|dx| / l)``), zero on padded rows.  One grid at
    a time, so that no array of every trial's or every grid's matrices is held at once.
    """
    reading, tracing, length = np.exp(theta)
    x_grids, real_grids = grids
    # H + e e' of a trial is A B' with A = [Z M^-1, e] and B = [Z, e]
    left = np.concatenate([spread, residual[:, :, None]], axis=2)
    right = np.concatenate([zx, residual[:, :, None]], axis=2)
    order = np.argsort(group, kind="stable")
    starts = np.searchsorted(group[order], np.arange(len(x_grids) + 1))
    score = np.zeros(3)
    for g, (x, real) in enumerate(zip(x_grids, real_grids, strict=True)):
        members = order[starts[g] : starts[g + 1]]
        a = left[members].transpose(1, 0, 2).reshape(x.size, -1)
        b = right[members].transpose(1, 0, 2).reshape(x.size, -1)
        inverse = inverse_factor[g]
        summed = members.size * (inverse.T @ inverse) - inverse.T @ (a @ b.T) @ inverse
        pair = real[:, None] & real[None, :]
        kernel = np.where(pair, exponential_kernel(x, length), 0.0)
        score += [
            4.0 * reading**2 * summed.diagonal()[real].sum(),
            4.0 * tracing**2 * np.sum(summed * kernel),
            2.0 * tracing**2 / length * np.sum(summed * kernel * np.abs(x[:, None] - x[None, :])),
        ]
    return score


def estimate_noise(trials, max_trials=400):
    """Measure the per-side noise from the left-right differences of many trials.

    Parameters
    ----------
    trials : sequence of tuple
        ``(distance_mm, difference_mm, slope)`` per trial, as
        :func:`trial_differences` gives them.  Trials with fewer than
        :data:`MIN_DIFFERENCES` differences are left out.
    max_trials : int, optional
        At most this many trials enter the likelihood, taken evenly through the
        sequence (a dataset of thousands of subjects measures the noise as well
        from a few hundred of them, in a fixed time).

    Returns
    -------
    NoiseEstimate

    Raises
    ------
    ValueError
        If fewer than two trials have enough differences.
    """
    from scipy.optimize import minimize

    usable = [t for t in trials if np.asarray(t[0]).size >= MIN_DIFFERENCES]
    if len(usable) < 2:
        raise ValueError(
            "the noise needs at least two trials with five or more distances read on both sides"
        )
    usable = _evenly(usable, max_trials)
    x, d, design, real, grids, group = _padded(usable)
    n_differences = int(real.sum())
    spacing = np.diff(np.sort(np.unique(x[real])))
    span = float(x[real].max() - x[real].min())
    low_length = math.log(max(float(spacing.min()) if spacing.size else 0.01, 1e-3) / 2)
    # a correlation longer than a quarter of the span is an offset or a tilt of the
    # trace, which the fixed effects remove: the likelihood is flat there, so the
    # length is bounded (and a tracing error of that reach is not identifiable)
    high_length = math.log(max(span, 1e-2) / 4)
    # start: the residual SD of a line through each trial's differences
    start_sd = float(np.std(d[real])) / math.sqrt(2) or 1e-3
    bounds = [
        (_LOG_FLOOR, math.log(10 * start_sd + 1e-6)),
        (_LOG_FLOOR, math.log(10 * start_sd + 1e-6)),
        (low_length, high_length),
    ]

    def objective(theta):
        return _restricted_terms(theta, d, design, grids, group)[0]

    def objective_and_score(theta):
        value, _, _, _, score = _restricted_terms(theta, d, design, grids, group, gradient=True)
        return value, score

    best = None
    # a few starts: the tracing part may be nil, short or long
    for tracing_share, length in ((0.3, 0.3), (0.7, 1.0), (0.05, 0.1)):
        start = np.array(
            [
                math.log(start_sd * math.sqrt(1 - tracing_share**2)),
                math.log(start_sd * tracing_share),
                min(max(math.log(length), low_length), high_length),
            ]
        )
        result = minimize(
            objective_and_score,
            start,
            jac=True,
            method="L-BFGS-B",
            bounds=bounds,
            options=_OPTIMISER_OPTIONS,
        )
        if best is None or result.fun < best.fun:
            best = result
    theta = best.x
    se_log = _log_parameter_se(objective, theta, bounds)
    reading, tracing, length = np.exp(theta)
    # the side offsets and the rotation are left at zero: the per-trial terms reproduce
    # their traces (:data:`UNMEASURED`), so the spread of the trials' offsets and slopes
    # would be a chance value
    model = NoiseModel(
        reading_sd_mm=float(reading), tracing_sd_mm=float(tracing), tracing_length_mm=float(length)
    )
    se = {
        "reading_sd_mm": float(reading * se_log[0]),
        "tracing_sd_mm": float(tracing * se_log[1]),
        "tracing_length_mm": float(length * se_log[2]),
    }
    return NoiseEstimate(model, se, len(usable), n_differences)


def constant_explained(distance_mm, slope):
    """The share of a constant that a trial's other difference terms reproduce.

    A side offset adds a constant to one trial's left-right difference; the noise fit
    leaves a slope, a parabola and a multiple of the profile's slope free in each trial
    (:func:`estimate_noise`).  The share of the constant's sum of squares in their span
    is what those terms can take of it: near 1, a constant is not told from them, and
    the trials' offsets say nothing of the side offsets' size.

    Parameters
    ----------
    distance_mm : array_like
        A trial's distances read on both sides (mm).
    slope : array_like
        The profile's slope there (the wedge-position term).

    Returns
    -------
    float
        Between 0 and 1.
    """
    x = np.asarray(distance_mm, dtype=float)
    terms = np.column_stack([x, x**2, np.asarray(slope, dtype=float)])
    ones = np.ones_like(x)
    left = ones - terms @ np.linalg.lstsq(terms, ones, rcond=None)[0]
    return float(1.0 - left @ left / x.size)


def _log_parameter_se(objective, theta, bounds, step=1e-3):
    """Standard errors of the log-parameters from the curvature of -2 log likelihood.

    A parameter on its bound, or along a direction where the likelihood is flat,
    gets NaN: no curvature, no standard error.
    """
    k = theta.size
    hessian = np.empty((k, k))
    f0 = objective(theta)
    for i in range(k):
        for j in range(i, k):
            e_i = np.eye(k)[i] * step
            e_j = np.eye(k)[j] * step
            value = (
                objective(theta + e_i + e_j)
                - objective(theta + e_i - e_j)
                - objective(theta - e_i + e_j)
                + objective(theta - e_i - e_j)
            ) / (4 * step * step)
            hessian[i, j] = hessian[j, i] = value
    se = np.full(k, np.nan)
    on_bound = np.array(
        [
            abs(t - lo) < 1e-6 or abs(t - hi) < 1e-6
            for t, (lo, hi) in zip(theta, bounds, strict=True)
        ]
    )
    free = ~on_bound
    if free.any():
        information = hessian[np.ix_(free, free)] / 2.0  # -2 log L -> Fisher information
        try:
            covariance = np.linalg.inv(information)
        except np.linalg.LinAlgError:
            return se
        diagonal = np.diag(covariance)
        se[free] = np.where(diagonal > 0, np.sqrt(np.abs(diagonal)), np.nan)
    del f0
    return se


def noise_rows(estimate, priors, overrides=None):
    """The rows of the noise table: each parameter, its value, SE and where it comes from.

    Parameters
    ----------
    estimate : NoiseEstimate
        What the left-right differences measured.
    priors : dict
        ``shared_offset_sd_mm``, ``shared_tilt_sd``, ``depth_sd_mm`` and
        ``wedge_position_sd_mm`` (config).  The side offset's row is zero (the
        shared-offset prior holds its share of the mean); the rotation's is the
        shared tilt's prior, which stands for it where one side alone was read
        (:data:`UNMEASURED`).
    overrides : dict, optional
        Measured parameters replaced by a configured value (not None).

    Returns
    -------
    list of dict
        Columns :data:`NOISE_COLUMNS`, one row per parameter of :class:`NoiseModel`.
    """
    overrides = {k: v for k, v in (overrides or {}).items() if v is not None}
    rows = []
    for name, value in estimate.model.as_dict().items():
        if name in PRIORS:
            source = f"prior, {PRIOR_BASIS[name]}: config noise.{name}"
            value, se = priors[name], math.nan
        elif name in overrides:
            value, se, source = overrides[name], math.nan, f"set: config noise.{name}"
        elif name in UNMEASURED:
            value = priors["shared_tilt_sd"] if name == "rotation_sd" else 0.0
            se, source = math.nan, UNMEASURED[name]
        else:
            se = estimate.se.get(name, math.nan)
            source = "measured: left-right differences"
        rows.append(
            {
                "scope": DATASET_SCOPE,
                "parameter": name,
                "value": float(value),
                "se": float(se),
                "source": source,
                "n_trials": estimate.n_trials,
                "n_differences": estimate.n_differences,
            }
        )
    return rows


def registration_rows(records, n_trials, n_differences):
    """Rows of the noise table for digitised trials: each one's registration error and,
    where the record gives it, its readings' own error.

    A photographed trial's readings are the loaded outline minus the resting one,
    registered on the skin far from the wedge; the registration's error is an
    offset shared by every reading of the trial, which the left-right differences
    cannot see and the config's prior ``shared_offset_sd_mm`` stands for.  Where
    the digitiser measured it, it replaces the prior for that trial.  Each reading's
    own error (the two outlines' edge errors over its columns) is what
    ``reading_sd_mm`` stands for; the digitiser states it per reading
    (docs/calibration/digitiser.md measures it against rendered pairs) and its RMS
    over the fit window replaces, for that trial, the dataset's measured value, which
    pools every trial's (hand-read ones too) and would count the digitiser's error
    twice if added to it.

    Parameters
    ----------
    records : iterable of tuple
        ``(subject, depth_mm, registration_sd_mm, source)`` per digitised trial, or
        ``(subject, depth_mm, registration_sd_mm, source, reading_sd_mm)``.
    n_trials, n_differences : int
        As in the dataset's rows.

    Returns
    -------
    list of dict
        Columns :data:`NOISE_COLUMNS`, scope ``"<subject> at <depth> mm"``.
    """
    rows = []
    for subject, depth_mm, sd_mm, source, *reading in records:
        measured = [("shared_offset_sd_mm", sd_mm, "registration of the photographs")]
        if reading and reading[0] is not None:
            measured.append(("reading_sd_mm", reading[0], "the digitiser's own, per reading"))
        rows += [
            {
                "scope": trial_label(subject, depth_mm),
                "parameter": parameter,
                "value": float(value),
                "se": math.nan,
                "source": f"measured: {what} ({source})",
                "n_trials": n_trials,
                "n_differences": n_differences,
            }
            for parameter, value, what in measured
        ]
    return rows


def trial_models(rows, keys):
    """The noise model of each trial: the dataset's, with a trial's own rows applied.

    Parameters
    ----------
    rows : iterable of mapping
        A noise table (``scope``, ``parameter``, ``value``).
    keys : iterable of tuple
        ``(subject, depth_mm)`` of each trial.

    Returns
    -------
    list of NoiseModel
        In the order of ``keys``; trials without rows of their own share the
        dataset's model.
    """
    rows = list(rows)
    dataset = model_from_rows(rows)
    own = {}
    for row in rows:
        scope = row.get("scope", DATASET_SCOPE)
        if scope == DATASET_SCOPE:
            continue
        value = float(row["value"])
        if not (math.isfinite(value) and value >= 0) or row["parameter"] not in TRIAL_PRIORS:
            raise ValueError(
                f"noise parameter {row['parameter']} of {scope}: expected "
                f"{' or '.join(TRIAL_PRIORS)} and a number >= 0, got {row['value']!r}"
            )
        own.setdefault(scope, {})[row["parameter"]] = value
    return [
        dataset.with_priors(**own[scope])
        if (scope := trial_label(subject, depth_mm)) in own
        else dataset
        for subject, depth_mm in keys
    ]


def model_from_rows(rows):
    """The :class:`NoiseModel` of a noise table's dataset rows (as :func:`noise_rows`
    writes them; rows of a trial's own scope are left to :func:`trial_models`).

    Parameters
    ----------
    rows : iterable of mapping
        Rows with ``parameter`` and ``value`` (and ``scope``, ``"dataset"`` if absent).

    Returns
    -------
    NoiseModel

    Raises
    ------
    ValueError
        If a parameter is missing or a value is not a finite number >= 0.
    """
    values = {}
    for row in rows:
        if row.get("scope", DATASET_SCOPE) != DATASET_SCOPE:
            continue
        value = float(row["value"])
        if not (math.isfinite(value) and value >= 0):
            raise ValueError(
                f"noise parameter {row['parameter']}: expected a number >= 0, got {row['value']!r}"
            )
        values[row["parameter"]] = value
    missing = [name for name in NoiseModel.__dataclass_fields__ if name not in values]
    if missing:
        raise ValueError(f"the noise table lacks {', '.join(missing)}")
    return NoiseModel(**{name: values[name] for name in NoiseModel.__dataclass_fields__})


def reading_noise_mm(rows, override=None):
    """One reading's noise: ``override`` if set, else the noise table's reading and
    tracing errors together, ``sqrt(reading_sd_mm**2 + tracing_sd_mm**2)``.

    Parameters
    ----------
    rows : iterable of mapping, or pandas.DataFrame, or None
        The noise table (``parameter``, ``value``); may be None with an override.
    override : float, optional
        Config ``claims: noise_mm``.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        Neither a table nor an override, or a table without those parameters.
    """
    if override is not None:
        return float(override)
    if rows is None:
        raise ValueError("one reading's noise needs the noise table or a configured value")
    if hasattr(rows, "to_dict"):
        rows = rows.to_dict("records")
    model = model_from_rows(rows)
    return math.hypot(model.reading_sd_mm, model.tracing_sd_mm)


def measure_noise_table(profiles, priors, window_mm=np.inf, max_trials=400, registrations=()):
    """A dataset's noise table, measured from its trials' left-right differences.

    What rule ``noise`` writes and what the verdict calibration
    (:mod:`lineload.simulation.verdicts`) measures on each simulated dataset: the
    trials chosen (:func:`noise_trials`), the noise fitted to their differences
    (:func:`estimate_noise`), the rows with the priors (:func:`noise_rows`) and a
    digitised trial's own registration and reading errors (:func:`registration_rows`).

    Parameters
    ----------
    profiles : sequence of tuple
        ``(distance_mm, left_mm, right_mm)`` of every trial of the dataset.
    priors : dict
        The priors (config ``noise``), as for :func:`noise_rows`.
    window_mm : float, optional
        As in :func:`trial_differences`.
    max_trials : int, optional
        As in :func:`estimate_noise`.
    registrations : iterable of tuple, optional
        ``(subject, depth_mm, registration_sd_mm, source[, reading_sd_mm])`` of each
        digitised trial (:func:`registration_rows`).

    Returns
    -------
    tuple
        ``(estimate, rows)``: the :class:`NoiseEstimate` and the noise table's rows
        (columns :data:`NOISE_COLUMNS`).
    """
    trials = noise_trials(profiles, window_mm, max_trials)
    estimate = estimate_noise(trials, max_trials=max_trials)
    rows = noise_rows(estimate, priors)
    rows += registration_rows(registrations, estimate.n_trials, estimate.n_differences)
    return estimate, rows
