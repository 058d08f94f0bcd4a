"""The forward error model: what digitising a true profile adds to it.

One model serves every simulation: the generator of the shipped reconstruction
(:mod:`lineload.simulation.readings`), the coverage study and the parametric
bootstrap (:mod:`lineload.simulation.coverage`) and, through the generator, the
verdict calibration.  Each draws the errors from its own random streams; how a
drawn error changes a reading is written once, here (:func:`read_side_mm`).

A trial's readings share five errors (:class:`TrialErrors`): the registration
of the two superimposed outlines (a vertical offset and a rotation about the
wedge, which raises one side as much as it lowers the other), a tilt shared by
both sides (``t |x|``, a print not quite square), an error of the indentation
depth (the true indentation is ``depth + error``, so the profile is scaled) and
a misplaced wedge (the left side's distances too long by the shift, the right
side's too short).  Each side adds its own errors (:class:`lineload.noise.NoiseModel`:
an independent error per reading, a tracing error correlated along the outline,
an offset of the side's whole trace).

None of the sizes below was measured: the study's raw readings were never
published.  Each is a size a hand tracing on a 20x print plausibly makes, stated so
that a reader can change it; the workflow itself measures the noise of any dataset
from its left-right differences and never takes these sizes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lineload.noise import NoiseModel

__all__ = [
    "AS_ASSUMED",
    "DEPTH_SD_MM",
    "FORCE_NOISE_SD_N",
    "FORCE_RESOLUTION_N",
    "IMAGE_RESOLUTION_MM",
    "MISREAD_FRACTION",
    "MISREAD_SDS",
    "NOISE_SD_MM",
    "REGISTRATION_OFFSET_SD_MM",
    "REGISTRATION_TILT_SD",
    "RESTING_CURVATURE_SD_PER_MM",
    "SEEN_FLOOR_MM",
    "SHARED_TILT_SD",
    "SIDE_NOISE",
    "SIDE_OFFSET_SD_MM",
    "TRACING_LENGTH_MM",
    "TRACING_SD_MM",
    "TRUE_NOISE",
    "WEDGE_POSITION_SD_MM",
    "TrialErrors",
    "draw_misreads_mm",
    "image_mm",
    "read_force_N",
    "read_side_mm",
    "registration_mm",
    "seen_distance_mm",
]

#: Independent error of one reading of one side (tissue mm): 0.16 mm on the print,
#: about the width of a traced pencil line.
NOISE_SD_MM = 0.008
#: Error that wanders along a traced outline (the hand drifts): SD and correlation
#: length along the outline (exponential kernel, as lineload.noise assumes).
TRACING_SD_MM = 0.005
TRACING_LENGTH_MM = 0.5
#: Offset of one side's whole trace (each side of the wedge traced on its own).
SIDE_OFFSET_SD_MM = 0.004
#: Registration error of one photograph: the resting and the deformed outline are
#: superimposed by hand, so every reading of a trial shares a small vertical offset
#: and a small rotation about the wedge.  Standard deviations of the offset
#: (tissue mm) and of the rotation (mm of deflection per mm of distance, i.e. radians).
REGISTRATION_OFFSET_SD_MM = 0.005
REGISTRATION_TILT_SD = 0.001
#: A symmetric tilt shared by both sides (t |x|), e.g. a print not quite square.
SHARED_TILT_SD = 0.0005
#: Error of the indentation depth (the positioner's reading, about 10 um).
DEPTH_SD_MM = 0.01
#: Misplacement of the wedge along the outline: the left side's distances too long by
#: this much and the right side's too short.
WEDGE_POSITION_SD_MM = 0.01
#: Two errors the generator does not make and the noise model does not name, for the
#: coverage study's misspecified worlds (:data:`lineload.simulation.coverage.SCENARIOS`):
#:
#: An error of the resting outline's curvature, the same on both sides (the resting
#: outline traced or superimposed a little too round or too flat): a reading at ``x``
#: is raised by ``curvature x**2 / 2``.  Symmetric, it cancels in the left-right
#: differences, so no dataset can measure it.  Stated size: the resting outline's
#: radius (about 10 mm) misjudged by 2 %, a curvature error of SD 0.002 per mm, 9 um
#: at 3 mm from the wedge.
RESTING_CURVATURE_SD_PER_MM = 0.002
#: Misreads: a share of the readings off by a multiple of the reading error's SD, up or
#: down at random (a slip of the pencil, a grid line miscounted): 5 % at 6 SD.
MISREAD_FRACTION = 0.05
MISREAD_SDS = 6.0

#: Resolution of a reading on the enlargement (image mm).
IMAGE_RESOLUTION_MM = 0.1
#: Standard deviation of one force reading (N) and its resolution (N).
FORCE_NOISE_SD_N = 0.005
FORCE_RESOLUTION_N = 0.001

#: Where a misplaced wedge's reading stops (tissue mm from the true wedge): at the
#: wedge's tip.  A reading taken at ``x`` sees the skin at ``x`` plus the wedge's
#: shift; when the shift is larger than ``x`` (the wrong way), the reading lands on
#: the tip itself, where the skin is at the indentation depth: no skin is seen past
#: it.  The floor is therefore 0.  (The coverage study once clipped at 1 um instead:
#: not a property of digitising but a guard for the Boussinesq form, whose logarithm
#: is infinite at the tip; that guard now lives with that form in
#: :mod:`lineload.simulation.coverage`.)  With the first reading at 0.05 mm and a
#: wedge error of SD 0.01 mm, a reading reaches the tip at five standard deviations:
#: in the shipped data and the committed calibrations it never does (the nearest of their
#: readings lands 8.8 um from it; ``docs/calibration/scripts/wedge_tip.py`` counts), so
#: the floor changes no number there.
SEEN_FLOOR_MM = 0.0

#: The per-side errors as the noise model describes them.
SIDE_NOISE = NoiseModel(
    reading_sd_mm=NOISE_SD_MM,
    tracing_sd_mm=TRACING_SD_MM,
    tracing_length_mm=TRACING_LENGTH_MM,
    side_offset_sd_mm=SIDE_OFFSET_SD_MM,
)

#: The sizes of every error of a reading, as the noise model names them: the per-side
#: errors and the errors shared by a trial's readings.
TRUE_NOISE = NoiseModel(
    reading_sd_mm=NOISE_SD_MM,
    tracing_sd_mm=TRACING_SD_MM,
    tracing_length_mm=TRACING_LENGTH_MM,
    side_offset_sd_mm=SIDE_OFFSET_SD_MM,
    rotation_sd=REGISTRATION_TILT_SD,
    wedge_position_sd_mm=WEDGE_POSITION_SD_MM,
    shared_offset_sd_mm=REGISTRATION_OFFSET_SD_MM,
    shared_tilt_sd=SHARED_TILT_SD,
    depth_sd_mm=DEPTH_SD_MM,
)


@dataclass(frozen=True)
class TrialErrors:
    """The errors every reading of one trial shares.

    Attributes
    ----------
    offset_mm : float
        Vertical offset of the superimposed outlines (the registration's offset).
    rotation : float
        Rotation of the superimposed outlines about the wedge (radians): a reading at
        signed distance ``x`` (left side negative) is raised by ``rotation * x``.
    shared_tilt : float
        Tilt shared by both sides: a reading at ``x`` is raised by ``shared_tilt * |x|``.
    depth_error_mm : float
        Error of the indentation depth: the true indentation is ``depth + error``.
    wedge_shift_mm : float
        Misplacement of the wedge: the left side's distances too long by this much,
        the right side's too short.
    curvature_per_mm : float
        Error of the resting outline's curvature (1/mm), the same on both sides: a
        reading at ``x`` is raised by ``curvature_per_mm * x**2 / 2``
        (:data:`RESTING_CURVATURE_SD_PER_MM`; none in the generator).
    """

    offset_mm: float = 0.0
    rotation: float = 0.0
    shared_tilt: float = 0.0
    depth_error_mm: float = 0.0
    wedge_shift_mm: float = 0.0
    curvature_per_mm: float = 0.0


def _sign(side):
    if side not in ("left", "right"):
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    return 1.0 if side == "left" else -1.0


def seen_distance_mm(distance_mm, side, wedge_shift_mm):
    """Where on the skin a reading taken at ``distance_mm`` lands with a misplaced wedge.

    The left side's distances are too long by the shift, the right side's too short;
    no reading lands past the wedge's tip (:data:`SEEN_FLOOR_MM`).
    """
    x = np.asarray(distance_mm, dtype=float)
    return np.clip(x + _sign(side) * wedge_shift_mm, SEEN_FLOOR_MM, None)


def registration_mm(distance_mm, side, errors):
    """The registration's part of a reading: the offset and the rotation about the wedge."""
    x = np.asarray(distance_mm, dtype=float)
    return errors.offset_mm + errors.rotation * (-_sign(side) * x)


def read_side_mm(true_profile, distance_mm, side, depth_mm, errors, side_errors_mm=0.0):
    """One side of a trial as read, before rounding: the true profile with every error.

    Parameters
    ----------
    true_profile : callable
        Distance from the wedge (mm, array) -> true deflection (mm) of this side.
    distance_mm : array_like
        Reading positions (tissue mm, >= 0).
    side : {"left", "right"}
    depth_mm : float
        Indentation depth as set (mm): the depth error scales the profile by
        ``1 + depth_error / depth``.
    errors : TrialErrors
        The errors the trial's readings share.
    side_errors_mm : array_like or float, optional
        The side's own errors at each reading (e.g.
        :func:`lineload.noise.draw_side_errors_mm`).

    Returns
    -------
    numpy.ndarray
        ``(1 + e_d / depth) w(seen x) + t |x| + k x**2 / 2 + side errors + offset +
        rotation x``, tissue mm, not rounded: a reading can be slightly negative where
        the skin barely moves.
    """
    x = np.asarray(distance_mm, dtype=float)
    seen_mm = seen_distance_mm(x, side, errors.wedge_shift_mm)
    scale = 1.0 + errors.depth_error_mm / depth_mm
    true_mm = scale * true_profile(seen_mm) + errors.shared_tilt * x
    if errors.curvature_per_mm:  # added only where made: no rounding moves elsewhere
        true_mm = true_mm + 0.5 * errors.curvature_per_mm * x**2
    # the registration added term by term, as registration_mm writes it
    return true_mm + side_errors_mm + errors.offset_mm + errors.rotation * (-_sign(side) * x)


def draw_misreads_mm(rng, n_readings, fraction, size_mm):
    """Misreads of one side: each reading, with probability ``fraction``, off by
    ``size_mm`` up or down at random.

    Parameters
    ----------
    rng : numpy.random.Generator
    n_readings : int
    fraction : float
        Probability that a reading is a misread (0-1).
    size_mm : float
        How far a misread is off (tissue mm).

    Returns
    -------
    numpy.ndarray
        The misreads' errors (mm), 0 where a reading is not a misread.
    """
    misread = rng.random(n_readings) < fraction
    sign = np.where(rng.random(n_readings) < 0.5, -1.0, 1.0)
    return np.where(misread, sign * size_mm, 0.0)


def image_mm(value_mm, magnification):
    """Tissue mm to image mm, rounded to the digitising resolution, no ``-0.0``."""
    steps = np.round(np.asarray(value_mm) * magnification / IMAGE_RESOLUTION_MM)
    return steps * IMAGE_RESOLUTION_MM + 0.0


def read_force_N(true_N, noise_N):
    """A force as read: the true force plus its noise, rounded to :data:`FORCE_RESOLUTION_N`."""
    return round(round((true_N + noise_N) / FORCE_RESOLUTION_N) * FORCE_RESOLUTION_N, 9)


@dataclass(frozen=True)
class Scenario:
    """The errors of a simulation: which correlation, which tails, which true sizes.

    The fit always states the priors at the sizes it is given (the stated noise);
    a scenario changes only what the data are made with.

    Attributes
    ----------
    name : str
    kernel : {"exponential", "squared_exponential"}
        Correlation of the tracing error (the estimator assumes exponential).
    df : float or None
        Student t reading errors with these degrees of freedom; None: Gaussian.
    misspecified : str
        What the scenario makes differently from what the fit states ("none").
    prior_ratio : float
        Every prior's true size over its stated size (:data:`lineload.noise.PRIORS`).
    true_sizes : tuple of (str, float)
        Priors whose true size is set outright (mm or rad), after the ratio.
    curvature_sd_per_mm : float
        SD of a resting curvature error the same on both sides (1/mm; the fit has
        no room for it).
    misread_fraction : float
        Share of readings misread by ``misread_sds`` reading SDs, up or down.
    misread_sds : float
    """

    name: str
    kernel: str = "exponential"
    df: float | None = None
    misspecified: str = "none"
    prior_ratio: float = 1.0
    true_sizes: tuple = ()
    curvature_sd_per_mm: float = 0.0
    misread_fraction: float = 0.0
    misread_sds: float = MISREAD_SDS

    def true_noise(self, stated):
        """The sizes the data are made with, from the ``stated`` NoiseModel."""
        return stated.scaled_priors(self.prior_ratio).with_priors(**dict(self.true_sizes))


#: The world the fit assumes: every error at its stated size and shape (the shipped
#: data's).
AS_ASSUMED = Scenario("as assumed")
