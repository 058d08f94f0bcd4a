"""The readings of the synthetic reconstruction: profiles, outlines and forces.

Each finger of :mod:`lineload.simulation.subjects` is read as a lab reads a print:
on the reading grid of :mod:`lineload.rawdata.readings` up to each side's edge,
with every digitising error of :mod:`lineload.simulation.errors` drawn from the
subject's own random streams, and rounded as the enlargement rounds.

Forces
------
The shipped fingers also get a steady reaction force on the wedge at every
depth (``forces.csv``) and the length of wedge edge in contact with each finger
(``contact_length_mm`` in ``subjects.csv``).  The forces come from a waterbed
membrane under tension at rest (:mod:`lineload.mechanics`), ``F = 2 l (N0 + E
eps) sin(theta0)``, whose shape at each depth is the exact arc fitted, within
3 mm of the wedge, to the noise-free left/right mean of the true profile; plus
seeded Gaussian noise, rounded to 1 mN.  See :func:`trial_forces`.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from lineload import paper
from lineload.noise import draw_side_errors_mm
from lineload.rawdata.readings import GRID_TICK_MM, reading_distances_mm
from lineload.simulation.errors import (
    AS_ASSUMED,
    FORCE_NOISE_SD_N,
    TRUE_NOISE,
    TrialErrors,
    draw_misreads_mm,
    image_mm,
    read_force_N,
    read_side_mm,
    registration_mm,
)
from lineload.simulation.subjects import (
    DEFAULT_SEED,
    MAGNIFICATION,
    subject_rng,
    trial_deflection_mm,
    trial_parameters,
)

__all__ = [
    "FORCE_FIT_WINDOW_MM",
    "force_table",
    "noise_free_mean_profile",
    "outline_table",
    "profile_table",
    "registration_error_mm",
    "trial_errors",
    "trial_forces",
    "true_reading_mm",
]

#: Streams of a subject drawn only in a world whose errors are not as stated
#: (:class:`lineload.simulation.errors.Scenario`): the resting curvature error of each
#: trial and each side's misreads.  The shipped data never draw from them.
CURVATURE_STREAM = 7
MISREAD_STREAM = 8
#: First reading of a side is 0.05 mm with this probability, else 0.1 mm (glare).
P_FIRST_AT_FINEST = 0.6
#: Sampling step of the drawn outlines (tissue mm) and their margin beyond the edge.
OUTLINE_STEP_MM = 0.1
OUTLINE_MARGIN_MM = 2.0
#: Outlines stop at this fraction of the resting radius (a circle cannot go further).
OUTLINE_MAX_FRACTION_OF_RADIUS = 0.9
#: Depths at which outlines are drawn (Figure 1).
OUTLINE_DEPTHS_MM = (1.0, 2.0)
#: Distance from the wedge (mm) within which the membrane's arc is fitted to the
#: noise-free mean profile: the paper's region of interest.
FORCE_FIT_WINDOW_MM = paper.REACH_MM


def noise_free_mean_profile(subject, depth_mm, window_mm=FORCE_FIT_WINDOW_MM):
    """Mean of the true left and right deflection at the reading positions within a window.

    Parameters
    ----------
    subject : SubjectParameters
    depth_mm : float
        One of the subject's depths (mm).
    window_mm : float, optional
        Outer edge of the points kept (mm).

    Returns
    -------
    tuple of numpy.ndarray
        ``(distance_mm, deflection_mm)``: the reading grid from 0.05 mm up to
        the window, and the noise-free mean of the two sides there.
    """
    trial = trial_parameters(subject, depth_mm)
    distance_mm = reading_distances_mm(window_mm + GRID_TICK_MM)[:-1]
    distance_mm = distance_mm[distance_mm <= window_mm + 1e-9]
    sides = [trial_deflection_mm(distance_mm, trial, side) for side in ("left", "right")]
    return distance_mm, (sides[0] + sides[1]) / 2.0


def trial_forces(subject, seed=DEFAULT_SEED, stiffening=0.0):
    """The membrane behind each trial's force, its true force and the force as read.

    At each depth the membrane takes the ``L`` of the exact arc fitted
    (:func:`lineload.fitting.batch.fit_arc`) to :func:`noise_free_mean_profile`, and
    pushes back on the wedge with ``F = 2 l (N0 + E eps) sin(theta0)`` (exact
    arc geometry, :func:`lineload.mechanics.force_terms`).  The reading adds
    Gaussian noise of SD :data:`FORCE_NOISE_SD_N` (stream 4 of the subject) and
    is rounded to :data:`lineload.simulation.errors.FORCE_RESOLUTION_N`.

    Parameters
    ----------
    subject : SubjectParameters
        Must have a contact length, stiffness and pre-strain.
    seed : int, optional
        Dataset seed.
    stiffening : float, optional
        0 (the shipped data): the linear law above, the one rule ``mechanics`` inverts.
        Otherwise a strain-stiffening membrane, ``N = N0 + E (exp(b eps) - 1) / b`` with
        ``b`` this value: tension ``N0`` and tangent stiffness ``E`` at rest, stiffer as
        it stretches (a law other than the one the fit inverts).

    Returns
    -------
    list of dict
        Per depth: ``depth_mm``, ``L_mm``, ``load_angle_rad``, ``strain``,
        ``true_force_N``, ``force_N`` (as read).
    """
    from lineload.fitting.batch import fit_arc
    from lineload.mechanics import arc_load_angle_rad, arc_strain

    if subject.contact_length_mm is None:
        raise ValueError(f"subject {subject.subject} has no membrane (no contact length)")
    rng = subject_rng(seed, subject.species, subject.index, 4)
    noise_N = rng.normal(0.0, FORCE_NOISE_SD_N, len(subject.depths_mm))
    rows = []
    for depth_mm, noise in zip(subject.depths_mm, noise_N, strict=True):
        distance_mm, deflection_mm = noise_free_mean_profile(subject, depth_mm)
        L_mm = fit_arc(distance_mm, deflection_mm, depth_mm).params["L_mm"]
        angle = float(arc_load_angle_rad(depth_mm, L_mm))
        strain = float(arc_strain(depth_mm, L_mm))
        if stiffening:
            stretch = math.expm1(stiffening * strain) / stiffening
        else:
            stretch = strain
        tension = subject.pretension_N_per_mm + subject.stiffness_N_per_mm * stretch
        true_N = 2.0 * subject.contact_length_mm * tension * math.sin(angle)
        read_N = read_force_N(true_N, noise)
        rows.append(
            {
                "depth_mm": float(depth_mm),
                "L_mm": float(L_mm),
                "load_angle_rad": angle,
                "strain": strain,
                "true_force_N": true_N,
                "force_N": read_N,
            }
        )
    return rows


def force_table(subjects, seed=DEFAULT_SEED, errors=True, stiffening=0.0):
    """The force readings of every finger with a membrane: ``subject``, ``depth_mm``, ``force_N``.

    Parameters
    ----------
    subjects : list of SubjectParameters
    seed : int, optional
    errors : bool, optional
        False: the true forces, without reading noise or rounding.
    stiffening : float, optional
        As for :func:`trial_forces` (0: the linear law the fit inverts).

    Returns
    -------
    pandas.DataFrame
        Rows in subject order, depths ascending; empty if no finger has a membrane.
    """
    rows = [
        {
            "subject": s.subject,
            "depth_mm": r["depth_mm"],
            "force_N": r["force_N"] if errors else r["true_force_N"],
        }
        for s in subjects
        if s.contact_length_mm is not None
        for r in trial_forces(s, seed, stiffening)
    ]
    return pd.DataFrame(rows, columns=["subject", "depth_mm", "force_N"])


def registration_error_mm(subject, seed=DEFAULT_SEED, noise=TRUE_NOISE):
    """Offset and tilt of each trial's superimposed outlines, drawn once per trial.

    The error of a reading at signed distance ``x`` (left side negative) is
    ``offset + tilt * x``: both sides of the wedge share the photograph, so the
    tilt raises one side as much as it lowers the other, and the left/right
    average cancels it while the offset remains.

    Parameters
    ----------
    subject : SubjectParameters
    seed : int, optional
        Dataset seed.
    noise : NoiseModel, optional
        The errors' sizes (``shared_offset_sd_mm``, ``rotation_sd``).

    Returns
    -------
    dict
        ``depth_mm -> (offset_mm, tilt)``, in the subject's depth order.
    """
    rng = subject_rng(seed, subject.species, subject.index, 3)
    draws = rng.normal(0.0, 1.0, (len(subject.depths_mm), 2))
    return {
        float(depth_mm): (
            float(noise.shared_offset_sd_mm * offset),
            float(noise.rotation_sd * tilt),
        )
        for depth_mm, (offset, tilt) in zip(subject.depths_mm, draws, strict=True)
    }


def trial_errors(subject, seed=DEFAULT_SEED, noise=TRUE_NOISE):
    """The errors of each trial that are not per reading: shared tilt, depth, wedge.

    Parameters
    ----------
    subject : SubjectParameters
    seed : int, optional
        Dataset seed.
    noise : NoiseModel, optional
        The errors' sizes (``shared_tilt_sd``, ``depth_sd_mm``, ``wedge_position_sd_mm``).

    Returns
    -------
    dict
        ``depth_mm -> (shared_tilt, depth_error_mm, wedge_shift_mm)``, in the
        subject's depth order (stream 5 of the subject).
    """
    rng = subject_rng(seed, subject.species, subject.index, 5)
    draws = rng.normal(0.0, 1.0, (len(subject.depths_mm), 3))
    sizes = np.array([noise.shared_tilt_sd, noise.depth_sd_mm, noise.wedge_position_sd_mm])
    return {
        float(depth_mm): tuple(float(v) for v in sizes * draw)
        for depth_mm, draw in zip(subject.depths_mm, draws, strict=True)
    }


def true_reading_mm(distance_mm, trial, side, errors):
    """What a side's true profile reads at ``distance_mm`` with a trial's shared errors.

    The wedge misplaced by ``wedge_shift`` makes the left side's distances too
    long (the reading at ``x`` sees the skin at ``x + shift``) and the right's too
    short; the depth error scales the profile (the true indentation is
    ``depth + error``); the shared tilt adds ``t x`` to both sides.

    Parameters
    ----------
    distance_mm : array_like
        Reading positions (mm).
    trial : TrialParameters
    side : {"left", "right"}
    errors : tuple
        ``(shared_tilt, depth_error_mm, wedge_shift_mm)`` of :func:`trial_errors`.

    Returns
    -------
    numpy.ndarray
        Deflection (mm), before the per-reading errors.
    """
    shared_tilt, depth_error_mm, wedge_shift_mm = errors
    shared = TrialErrors(
        shared_tilt=shared_tilt, depth_error_mm=depth_error_mm, wedge_shift_mm=wedge_shift_mm
    )
    return read_side_mm(
        lambda seen_mm: trial_deflection_mm(seen_mm, trial, side),
        distance_mm,
        side,
        trial.depth_mm,
        shared,
    )


def profile_table(
    subject,
    seed=DEFAULT_SEED,
    magnification=MAGNIFICATION,
    shuffle=False,
    errors=True,
    scenario=AS_ASSUMED,
):
    """Simulated digitised readings of one finger, in image units.

    For each depth and side: the reading grid up to that side's edge (first
    reading at 0.05 mm with probability 0.6, else 0.1 mm); the true deflection
    as the trial's shared errors make it read (depth error, wedge position,
    shared tilt); plus the side's own errors
    (:data:`~lineload.simulation.errors.SIDE_NOISE`: independent reading error,
    tracing error correlated along the outline, an offset of the side's trace;
    stream 6), symmetric and not clipped, so a reading can be slightly negative
    where the skin barely moves; plus the trial's registration error
    (:func:`registration_error_mm`), all applied by
    :func:`lineload.simulation.errors.read_side_mm`; rounded to 0.1 mm on the
    enlargement.  At the edge, where the outlines rejoin, the reading carries the
    registration error only.

    Parameters
    ----------
    subject : SubjectParameters
    seed : int, optional
        Dataset seed.
    magnification : float, optional
        Enlargement factor (image mm per tissue mm).
    shuffle : bool, optional
        Shuffle the rows (seeded); otherwise sorted by depth, side, distance.
    errors : bool, optional
        False: the true profile on the same reading grid, without any error and
        not rounded (the truth the verdict calibration compares with).
    scenario : Scenario, optional
        The world the errors are made in (:class:`lineload.simulation.errors.Scenario`):
        its true sizes of every error (from :data:`~lineload.simulation.errors.TRUE_NOISE`),
        tracing correlation and reading tails, and, where it makes them, a resting
        curvature error per trial (stream 7) and misreads (stream 8).  The default is
        the world the shipped data are made in; the same draws scaled to other sizes
        make the same dataset with larger or smaller errors.

    Returns
    -------
    pandas.DataFrame
        Columns ``depth_mm``, ``side``, ``distance_image_mm``,
        ``deflection_image_mm``.
    """
    rng = subject_rng(seed, subject.species, subject.index, 1)
    tracing_rng = subject_rng(seed, subject.species, subject.index, 6)
    noise = scenario.true_noise(TRUE_NOISE)
    registration = registration_error_mm(subject, seed, noise)
    shared = trial_errors(subject, seed, noise)
    curvature = dict.fromkeys(map(float, subject.depths_mm), 0.0)
    if scenario.curvature_sd_per_mm:
        curvature_rng = subject_rng(seed, subject.species, subject.index, CURVATURE_STREAM)
        draws = curvature_rng.normal(0.0, scenario.curvature_sd_per_mm, len(curvature))
        curvature = dict(zip(curvature, map(float, draws), strict=True))
    misread_rng = subject_rng(seed, subject.species, subject.index, MISREAD_STREAM)
    depth, side, distance, deflection = [], [], [], []
    for depth_mm in subject.depths_mm:
        trial = trial_parameters(subject, depth_mm)
        offset_mm, tilt = registration[float(depth_mm)]
        for side_name in ("left", "right"):
            first_mm = GRID_TICK_MM if rng.random() < P_FIRST_AT_FINEST else 2 * GRID_TICK_MM
            distance_mm = reading_distances_mm(trial.extent_mm(side_name), first_mm)
            noise_mm = draw_side_errors_mm(
                tracing_rng, distance_mm, noise, scenario.kernel, scenario.df
            )
            if scenario.misread_fraction:
                noise_mm = noise_mm + draw_misreads_mm(
                    misread_rng,
                    distance_mm.size,
                    scenario.misread_fraction,
                    scenario.misread_sds * noise.reading_sd_mm,
                )
            if errors:
                shared_tilt, depth_error_mm, wedge_shift_mm = shared[float(depth_mm)]
                trial_error = TrialErrors(
                    offset_mm,
                    tilt,
                    shared_tilt,
                    depth_error_mm,
                    wedge_shift_mm,
                    curvature[float(depth_mm)],
                )
            else:
                trial_error = TrialErrors()
            read_mm = read_side_mm(
                lambda seen_mm, trial=trial, side=side_name: trial_deflection_mm(
                    seen_mm, trial, side
                ),
                distance_mm,
                side_name,
                depth_mm,
                trial_error,
                noise_mm if errors else 0.0,
            )
            # the edge, where the outlines meet again, carries the registration only
            read_mm[-1] = registration_mm(distance_mm[-1], side_name, trial_error)
            depth.append(np.full(distance_mm.size, depth_mm))
            side.append(np.full(distance_mm.size, side_name, dtype=object))
            distance.append(image_mm(distance_mm, magnification))
            deflection.append(
                image_mm(read_mm, magnification) if errors else read_mm * magnification
            )
    table = pd.DataFrame(
        {
            "depth_mm": np.concatenate(depth),
            "side": np.concatenate(side),
            "distance_image_mm": np.concatenate(distance),
            "deflection_image_mm": np.concatenate(deflection),
        }
    )
    if shuffle:
        order = subject_rng(seed, subject.species, subject.index, 2).permutation(len(table))
        table = table.iloc[order].reset_index(drop=True)
    return table


def outline_table(subject, magnification=MAGNIFICATION):
    """Resting and deformed outlines of one finger for Figure 1, in image units.

    The resting outline is a circle of radius ``resting_radius_mm`` whose top
    touches the wedge (``z = 0`` at ``x = 0``, z upward); the deformed outline
    is the resting one lowered by the true deflection (left side at x < 0).
    Both are sampled every 0.1 mm from the wedge to 2 mm beyond each side's
    edge, but no further than 0.9 of the radius.  No noise is added.

    Parameters
    ----------
    subject : SubjectParameters
        Must have a ``resting_radius_mm``.
    magnification : float, optional
        Enlargement factor.

    Returns
    -------
    pandas.DataFrame
        Columns ``depth_mm``, ``state``, ``x_image_mm``, ``z_image_mm``, sorted
        by depth, state (resting first) and x.
    """
    radius_mm = subject.resting_radius_mm
    if radius_mm is None:
        raise ValueError(f"subject {subject.subject} has no resting outline")
    frames = []
    for depth_mm in OUTLINE_DEPTHS_MM:
        if depth_mm not in subject.depths_mm:
            continue
        trial = trial_parameters(subject, depth_mm)
        limit_mm = OUTLINE_MAX_FRACTION_OF_RADIUS * radius_mm
        n_left, n_right = (
            int(
                np.floor(
                    min(trial.extent_mm(side) + OUTLINE_MARGIN_MM, limit_mm) / OUTLINE_STEP_MM
                    + 1e-9
                )
            )
            for side in ("left", "right")
        )
        x_mm = np.arange(-n_left, n_right + 1) * OUTLINE_STEP_MM
        resting_mm = np.sqrt(radius_mm**2 - x_mm**2) - radius_mm
        deflection_mm = np.where(
            x_mm < 0,
            trial_deflection_mm(-x_mm, trial, "left"),
            trial_deflection_mm(x_mm, trial, "right"),
        )
        for state, z_mm in (("resting", resting_mm), ("deformed", resting_mm - deflection_mm)):
            frames.append(
                pd.DataFrame(
                    {
                        "depth_mm": depth_mm,
                        "state": state,
                        "x_image_mm": image_mm(x_mm, magnification),
                        "z_image_mm": image_mm(z_mm, magnification),
                    }
                )
            )
    return pd.concat(frames, ignore_index=True)
