"""Seeded generator of the synthetic reconstruction shipped in ``data/raw``.

The digitised profiles behind Srinivasan (1989) were never published.  This
module builds a stand-in dataset that follows every experimental number the
paper gives (subjects, depths, reading grid, magnification, extent of the
deformed region) from a *true* profile that is deliberately neither of the
models the workflow fits, plus seeded digitising noise.

True profile
------------
For one side of the wedge, with ``s = 1 - x / e`` on ``0 <= x <= e`` and zero
beyond the edge ``e`` of the deformed region::

    w(x) = depth * ((1 - beta) * s**p + beta * s**q)

a broad power-law decay (exponent ``p``) plus a narrow near-field term
(exponent ``q``, weight ``beta``) that makes the skin next to the wedge drop
faster than the broad term alone.  ``w(0) = depth``, ``w(e) = 0``, ``w`` falls
strictly on ``[0, e]`` and, for ``p > 1``, meets the resting surface with zero
slope: there is no bulge.  Per subject, ``e`` and ``p`` vary linearly with depth
between their values at 0.5 and 2 mm, and ``beta`` grows linearly from 0 at
0.5 mm; each side's edge is ``e (1 + a)`` (left) or ``e (1 - a)`` (right).

The calibration's boundary worlds (:mod:`lineload.simulation.calibration`) also blend in,
with weight ``c``, the circle that meets the resting surface at the edge with
zero slope and passes through the depth at the wedge (``circle_fraction``;
zero for the shipped fingers): ``w = (1 - c) w_above + c w_circle``.

Forces
------
The shipped fingers also get a steady reaction force on the wedge at every
depth (``forces.csv``) and the length of wedge edge in contact with each finger
(``contact_length_mm`` in ``subjects.csv``).  The forces come from a waterbed
membrane under tension at rest (:mod:`lineload.mechanics`), ``F = 2 l (N0 + E
eps) sin(theta0)``, whose shape at each depth is the exact arc fitted, within
3 mm of the wedge, to the noise-free left/right mean of the true profile; plus
seeded Gaussian noise, rounded to 1 mN.  See :func:`trial_forces`.

Everything here is a pure function: no file is read or written.  The CLI
``workflow/scripts/make_synthetic_data.py`` writes what :func:`build_dataset`
returns.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from lineload import paper
from lineload.claims.registry import built_in_verdicts as _registry_built_in_verdicts
from lineload.io import csv_text
from lineload.noise import NoiseModel, draw_side_errors_mm
from lineload.publishing.tables import markdown_table
from lineload.rawdata.readings import GRID_TICK_MM, reading_distances_mm

__all__ = [
    "DEFAULT_SEED",
    "DEPTHS_MM",
    "FORCE_NOISE_SD_N",
    "MAGNIFICATION",
    "SubjectParameters",
    "TrialParameters",
    "build_dataset",
    "draw_subjects",
    "force_markdown",
    "force_table",
    "membrane_markdown",
    "outline_table",
    "parameter_markdown",
    "parameter_table",
    "profile_table",
    "reading_distances_mm",
    "registration_error_mm",
    "shipped_subjects",
    "subject_markdown",
    "subject_rng",
    "subjects_table",
    "trial_forces",
    "trial_parameters",
    "true_deflection_mm",
]

#: Seed of the shipped dataset (the paper's year).
DEFAULT_SEED = 1989
#: Enlargement of the photographs on which readings are taken.
MAGNIFICATION = 20.0
#: Indentation depths given to every subject (tissue mm).
DEPTHS_MM = (0.5, 1.0, 1.5, 2.0)
#: Depths of the third human (the paper gave it 1 and 2 mm only).
SHORT_DEPTHS_MM = (1.0, 2.0)
#: Depths at which the per-subject parameters are specified; linear in between.
SHALLOW_DEPTH_MM, DEEP_DEPTH_MM = 0.5, 2.0
#: Exponent of the narrow near-field term (same for every trial).
NEAR_EXPONENT = 10.0
#: The digitising errors of the reconstruction (tissue mm unless named otherwise).  None
#: was measured: the study's raw readings were never published.  Each is a size a hand
#: tracing on a 20x print plausibly makes, stated so that a reader can change it.
#: Independent error of one reading of one side: 0.16 mm on the print, about the width
#: of a traced pencil line.
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
#: Resolution of a reading on the enlargement (image mm).
IMAGE_RESOLUTION_MM = 0.1
#: First reading of a side is 0.05 mm with this probability, else 0.1 mm (glare).
P_FIRST_AT_FINEST = 0.6
#: Sampling step of the drawn outlines (tissue mm) and their margin beyond the edge.
OUTLINE_STEP_MM = 0.1
OUTLINE_MARGIN_MM = 2.0
#: Outlines stop at this fraction of the resting radius (a circle cannot go further).
OUTLINE_MAX_FRACTION_OF_RADIUS = 0.9
#: Depths at which outlines are drawn (Figure 1).
OUTLINE_DEPTHS_MM = (1.0, 2.0)
#: Standard deviation of one force reading (N) and its resolution (N).
FORCE_NOISE_SD_N = 0.005
FORCE_RESOLUTION_N = 0.001
#: Distance from the wedge (mm) within which the membrane's arc is fitted to the
#: noise-free mean profile: the paper's region of interest.
FORCE_FIT_WINDOW_MM = paper.REACH_MM

#: Species number in the random-stream key (the order of lineload.paper.SPECIES).
SPECIES_CODE = {species: code for code, species in enumerate(paper.SPECIES)}
SPECIES_PREFIX = {"monkey": "M", "human": "H"}
SPECIES_LABEL = {"monkey": "Monkey", "human": "Human"}

#: Ranges (low, high) from which scale-mode subjects draw their parameters.
#: They enclose the hand-chosen values of the shipped subjects.
PARAMETER_RANGES = {
    "monkey": {
        "extent_shallow_mm": (3.3, 4.2),
        "extent_deep_mm": (5.4, 6.6),
        "exponent_shallow": (1.25, 1.45),
        "exponent_deep": (1.48, 1.70),
        "near_fraction_deep": (0.18, 0.24),
        "side_asymmetry": (-0.03, 0.03),
        "resting_radius_mm": (6.0, 8.0),
    },
    "human": {
        "extent_shallow_mm": (6.6, 7.4),
        "extent_deep_mm": (10.0, 11.2),
        "exponent_shallow": (2.00, 2.20),
        "exponent_deep": (2.40, 2.65),
        "near_fraction_deep": (0.20, 0.26),
        "side_asymmetry": (-0.03, 0.03),
        "resting_radius_mm": (40.0, 60.0),
    },
}


@dataclass(frozen=True)
class SubjectParameters:
    """True-profile parameters of one synthetic finger.

    Attributes
    ----------
    subject : str
        Id (``M1``, ``H2``...), also the profile file name.
    species : str
        ``monkey`` or ``human``.
    index : int
        1-based number within the species; with the species it keys the
        subject's random stream.
    label : str
        Display label (``Monkey 1``).
    depths_mm : tuple of float
        Indentation depths given to this finger (tissue mm).
    extent_shallow_mm, extent_deep_mm : float
        Edge of the deformed region (mean of the sides) at 0.5 and 2 mm depth.
    exponent_shallow, exponent_deep : float
        Power ``p`` of the broad term at 0.5 and 2 mm depth (> 1).
    near_fraction_deep : float
        Weight ``beta`` of the near-field term at 2 mm (at 0.5 mm:
        ``near_fraction_shallow``).
    side_asymmetry : float
        ``a``: the left edge is ``e (1 + a)``, the right edge ``e (1 - a)``.
    resting_radius_mm : float or None
        Radius of the circular resting outline drawn for Figure 1; ``None``
        for fingers without an outline file.
    contact_length_mm : float or None
        Length of wedge edge in contact with the finger (mm); ``None``: no
        forces are made for this finger (the scale-mode fingers).
    stiffness_N_per_mm : float or None
        Membrane stiffness ``E`` (modulus times thickness, N/mm).
    prestrain : float or None
        Pre-strain ``N0 / E`` of the membrane at rest.
    near_fraction_shallow : float
        Weight ``beta`` of the near-field term at 0.5 mm (0: the shipped fingers).
    near_exponent : float
        Power ``q`` of the near-field term (the shipped fingers: :data:`NEAR_EXPONENT`).
        With ``p = 2``, ``q = 1`` and ``beta = 2/3`` at every depth the profile is
        the waterbed's eq. 19 with ``L = 3 e`` up to its zero at ``L / 3``.
    circle_fraction : float
        Weight ``c`` of a circular profile blended in (0: the shipped fingers; 1:
        each side a circle, see :func:`true_deflection_mm`).
    """

    subject: str
    species: str
    index: int
    label: str
    depths_mm: tuple
    extent_shallow_mm: float
    extent_deep_mm: float
    exponent_shallow: float
    exponent_deep: float
    near_fraction_deep: float
    side_asymmetry: float
    resting_radius_mm: float | None = None
    contact_length_mm: float | None = None
    stiffness_N_per_mm: float | None = None
    prestrain: float | None = None
    near_fraction_shallow: float = 0.0
    near_exponent: float = NEAR_EXPONENT
    circle_fraction: float = 0.0

    @property
    def pretension_N_per_mm(self):
        """Membrane force at rest, ``N0 = prestrain x E`` (N/mm); None without a membrane."""
        if self.stiffness_N_per_mm is None or self.prestrain is None:
            return None
        return self.prestrain * self.stiffness_N_per_mm


@dataclass(frozen=True)
class TrialParameters:
    """True-profile parameters of one subject at one depth.

    Attributes
    ----------
    depth_mm : float
        Indentation depth, equal to the true deflection at the wedge (mm).
    extent_left_mm, extent_right_mm : float
        Edge of the deformed region on each side (mm, multiples of 0.05 mm).
    exponent : float
        Power ``p`` of the broad term.
    near_fraction : float
        Weight ``beta`` of the near-field term.
    near_exponent : float
        Power ``q`` of the near-field term.
    circle_fraction : float
        Weight ``c`` of the circular profile.
    """

    depth_mm: float
    extent_left_mm: float
    extent_right_mm: float
    exponent: float
    near_fraction: float
    near_exponent: float
    circle_fraction: float = 0.0

    def extent_mm(self, side):
        """Edge of the deformed region on ``side`` (``left`` or ``right``), mm."""
        return {"left": self.extent_left_mm, "right": self.extent_right_mm}[side]


def _subject(species, index, depths_mm, **values):
    prefix, label = SPECIES_PREFIX[species], SPECIES_LABEL[species]
    return SubjectParameters(
        subject=f"{prefix}{index}",
        species=species,
        index=index,
        label=f"{label} {index}",
        depths_mm=tuple(float(d) for d in depths_mm),
        **values,
    )


#: Membrane of each shipped finger: contact length of the wedge edge (mm), stiffness E
#: (N/mm) and pre-strain N0 / E.  Chosen by hand, once: contact lengths near the width
#: of a juvenile macaque's and an adult's fingertip, pre-strains of 0.25-0.45, and E
#: such that the true force at 2 mm is about 0.97 N.  With these profile shapes no
#: pre-strain keeps every force inside the paper's 0.3-1 N (data/README.md).
SHIPPED_MEMBRANES = {
    "M1": (9.0, 0.24, 0.35),
    "M2": (9.5, 0.18, 0.45),
    "M3": (8.5, 0.225, 0.40),
    "M4": (10.0, 0.24, 0.30),
    "H1": (15.0, 0.185, 0.30),
    "H2": (14.5, 0.17, 0.35),
    "H3": (16.0, 0.205, 0.25),
}


def shipped_subjects():
    """The seven hand-chosen fingers of the shipped dataset.

    Four monkeys and three humans; the third human has 1 and 2 mm only.  Only
    ``M1`` (markedly curved at rest) and ``H1`` (nearly flat) get outlines.
    The values were tuned once, offline, so that fits of the averaged profiles
    within 3 mm show what the paper reports; see ``data/README.md``.

    Returns
    -------
    list of SubjectParameters
    """
    rows = [
        # species, index, extent 0.5 / 2 mm, exponent 0.5 / 2 mm, beta at 2 mm, a, radius
        ("monkey", 1, 3.6, 5.9, 1.35, 1.53, 0.20, 0.020, 8.0),
        ("monkey", 2, 3.9, 6.4, 1.40, 1.63, 0.22, -0.030, None),
        ("monkey", 3, 3.4, 5.6, 1.25, 1.48, 0.18, 0.015, None),
        ("monkey", 4, 4.1, 6.5, 1.45, 1.68, 0.24, -0.020, None),
        ("human", 1, 7.0, 10.6, 2.10, 2.55, 0.24, 0.025, 45.0),
        ("human", 2, 6.7, 10.2, 2.00, 2.40, 0.22, -0.020, None),
        ("human", 3, 7.3, 11.0, 2.20, 2.60, 0.26, 0.030, None),
    ]
    subjects = []
    for row in rows:
        species, index, e_lo, e_hi, p_lo, p_hi, beta, asym, radius = row
        contact_mm, stiffness, prestrain = SHIPPED_MEMBRANES[f"{SPECIES_PREFIX[species]}{index}"]
        depths = SHORT_DEPTHS_MM if (species, index) == ("human", 3) else DEPTHS_MM
        subjects.append(
            _subject(
                species,
                index,
                depths,
                extent_shallow_mm=e_lo,
                extent_deep_mm=e_hi,
                exponent_shallow=p_lo,
                exponent_deep=p_hi,
                near_fraction_deep=beta,
                side_asymmetry=asym,
                resting_radius_mm=radius,
                contact_length_mm=contact_mm,
                stiffness_N_per_mm=stiffness,
                prestrain=prestrain,
            )
        )
    return subjects


def subject_rng(seed, species, index, stream):
    """Random generator of one subject, independent of the other subjects.

    The stream is keyed by ``(seed, species, index, stream)`` through a
    :class:`numpy.random.SeedSequence`, so a subject's numbers do not depend on
    how many subjects are generated or in which order.

    Parameters
    ----------
    seed : int
        Dataset seed.
    species : str
        ``monkey`` or ``human``.
    index : int
        1-based number within the species.
    stream : int
        0 for parameter draws, 1 for readings, 2 for row shuffling, 3 for the
        registration error of each trial.

    Returns
    -------
    numpy.random.Generator
    """
    sequence = np.random.SeedSequence(seed, spawn_key=(SPECIES_CODE[species], index, stream))
    return np.random.default_rng(sequence)


def draw_subjects(n_monkeys, n_humans, seed=DEFAULT_SEED):
    """Scale-mode fingers with parameters drawn uniformly from :data:`PARAMETER_RANGES`.

    Every finger gets all four depths.  The first monkey and the first human
    get a resting radius (and so an outline file), as in the shipped data.

    Parameters
    ----------
    n_monkeys, n_humans : int
        Number of fingers of each species (>= 0).
    seed : int
        Dataset seed.

    Returns
    -------
    list of SubjectParameters
        Monkeys ``M1..Mn`` then humans ``H1..Hm``.
    """
    subjects = []
    for species, count in (("monkey", n_monkeys), ("human", n_humans)):
        if count < 0:
            raise ValueError(f"number of {species}s must be >= 0, got {count}")
        ranges = PARAMETER_RANGES[species]
        names = list(ranges)
        low = np.array([ranges[name][0] for name in names])
        high = np.array([ranges[name][1] for name in names])
        for index in range(1, count + 1):
            drawn = subject_rng(seed, species, index, 0).uniform(low, high)
            values = {name: round(float(v), 3) for name, v in zip(names, drawn, strict=True)}
            if index != 1:
                values["resting_radius_mm"] = None
            subjects.append(_subject(species, index, DEPTHS_MM, **values))
    return subjects


def trial_parameters(subject, depth_mm):
    """True-profile parameters of ``subject`` at ``depth_mm``.

    ``e``, ``p`` and ``beta`` are interpolated linearly in depth between their
    0.5 and 2 mm values (``beta`` is 0 at 0.5 mm for the shipped fingers; depths
    outside [0.5, 2] mm take the nearer end).  Each side's edge is
    rounded to the 0.05 mm reading grid.

    Parameters
    ----------
    subject : SubjectParameters
    depth_mm : float
        Indentation depth (mm, > 0).

    Returns
    -------
    TrialParameters
    """
    t = float(np.clip((depth_mm - SHALLOW_DEPTH_MM) / (DEEP_DEPTH_MM - SHALLOW_DEPTH_MM), 0, 1))
    extent_mm = subject.extent_shallow_mm + t * (subject.extent_deep_mm - subject.extent_shallow_mm)
    exponent = subject.exponent_shallow + t * (subject.exponent_deep - subject.exponent_shallow)

    def on_grid(value_mm):
        return round(value_mm / GRID_TICK_MM) * GRID_TICK_MM

    return TrialParameters(
        depth_mm=float(depth_mm),
        extent_left_mm=on_grid(extent_mm * (1.0 + subject.side_asymmetry)),
        extent_right_mm=on_grid(extent_mm * (1.0 - subject.side_asymmetry)),
        exponent=round(exponent, 4),
        near_fraction=round(
            subject.near_fraction_shallow
            + t * (subject.near_fraction_deep - subject.near_fraction_shallow),
            4,
        ),
        near_exponent=subject.near_exponent,
        circle_fraction=subject.circle_fraction,
    )


def true_deflection_mm(
    distance_mm,
    depth_mm,
    extent_mm,
    exponent,
    near_fraction=0.0,
    near_exponent=NEAR_EXPONENT,
    circle_fraction=0.0,
):
    """True (noise-free) downward deflection of one side of the wedge.

    ``w = depth ((1 - beta) s**p + beta s**q)`` with ``s = 1 - x / e`` for
    ``x < e`` and ``w = 0`` beyond the edge; with ``circle_fraction`` ``c > 0``,
    ``(1 - c) w + c (R - sqrt(R**2 - (e - x)**2))``, the circle of radius ``R =
    (e**2 + depth**2) / (2 depth)`` through the depth at the wedge that meets the
    resting surface at ``e`` with zero slope (its small-slope form is ``depth
    s**2``).

    Parameters
    ----------
    distance_mm : array_like
        Horizontal distance from the wedge (mm, >= 0).
    depth_mm : float
        Indentation depth, the deflection at the wedge (mm).
    extent_mm : float
        Edge of the deformed region, ``e`` (mm, > 0).
    exponent : float
        Power ``p`` of the broad term (> 1 for a smooth join at the edge).
    near_fraction : float, optional
        Weight ``beta`` of the near-field term, in [0, 1).
    near_exponent : float, optional
        Power ``q`` of the near-field term.
    circle_fraction : float, optional
        Weight ``c`` of the circle, in [0, 1].

    Returns
    -------
    numpy.ndarray
        Deflection (mm), downward positive, never negative.
    """
    distance_mm = np.asarray(distance_mm, dtype=float)
    s = np.clip(1.0 - np.abs(distance_mm) / extent_mm, 0.0, 1.0)
    w = depth_mm * ((1.0 - near_fraction) * s**exponent + near_fraction * s**near_exponent)
    if circle_fraction == 0.0:
        return w
    radius_mm = (extent_mm**2 + depth_mm**2) / (2.0 * depth_mm)
    to_edge_mm = s * extent_mm
    circle = radius_mm - np.sqrt(radius_mm**2 - to_edge_mm**2)
    return (1.0 - circle_fraction) * w + circle_fraction * circle


def _trial_deflection_mm(distance_mm, trial, side=None, extent_mm=None):
    """The true deflection of ``trial`` on ``side``, or with the edge ``extent_mm``
    (an array where the side changes along the distances)."""
    return true_deflection_mm(
        distance_mm,
        trial.depth_mm,
        trial.extent_mm(side) if extent_mm is None else extent_mm,
        trial.exponent,
        trial.near_fraction,
        trial.near_exponent,
        trial.circle_fraction,
    )


def _to_image(value_mm, magnification):
    """Tissue mm to image mm, rounded to the digitising resolution, no ``-0.0``."""
    steps = np.round(np.asarray(value_mm) * magnification / IMAGE_RESOLUTION_MM)
    return steps * IMAGE_RESOLUTION_MM + 0.0


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
    sides = [_trial_deflection_mm(distance_mm, trial, side) for side in ("left", "right")]
    return distance_mm, (sides[0] + sides[1]) / 2.0


def trial_forces(subject, seed=DEFAULT_SEED):
    """The membrane behind each trial's force, its true force and the force as read.

    At each depth the membrane takes the ``L`` of the exact arc fitted
    (:func:`lineload.fitting.batch.fit_arc`) to :func:`noise_free_mean_profile`, and
    pushes back on the wedge with ``F = 2 l (N0 + E eps) sin(theta0)`` (exact
    arc geometry, :func:`lineload.mechanics.force_terms`).  The reading adds
    Gaussian noise of SD :data:`FORCE_NOISE_SD_N` (stream 4 of the subject) and
    is rounded to :data:`FORCE_RESOLUTION_N`.

    Parameters
    ----------
    subject : SubjectParameters
        Must have a contact length, stiffness and pre-strain.
    seed : int, optional
        Dataset seed.

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
        tension = subject.pretension_N_per_mm + subject.stiffness_N_per_mm * strain
        true_N = 2.0 * subject.contact_length_mm * tension * math.sin(angle)
        read_N = round(round((true_N + noise) / FORCE_RESOLUTION_N) * FORCE_RESOLUTION_N, 9)
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


def force_table(subjects, seed=DEFAULT_SEED, errors=True):
    """The force readings of every finger with a membrane: ``subject``, ``depth_mm``, ``force_N``.

    Parameters
    ----------
    subjects : list of SubjectParameters
    seed : int, optional
    errors : bool, optional
        False: the true forces, without reading noise or rounding.

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
        for r in trial_forces(s, seed)
    ]
    return pd.DataFrame(rows, columns=["subject", "depth_mm", "force_N"])


def registration_error_mm(subject, seed=DEFAULT_SEED):
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

    Returns
    -------
    dict
        ``depth_mm -> (offset_mm, tilt)``, in the subject's depth order.
    """
    rng = subject_rng(seed, subject.species, subject.index, 3)
    draws = rng.normal(0.0, 1.0, (len(subject.depths_mm), 2))
    return {
        float(depth_mm): (
            float(REGISTRATION_OFFSET_SD_MM * offset),
            float(REGISTRATION_TILT_SD * tilt),
        )
        for depth_mm, (offset, tilt) in zip(subject.depths_mm, draws, strict=True)
    }


#: The per-side errors as the noise model describes them.
SIDE_NOISE = NoiseModel(
    reading_sd_mm=NOISE_SD_MM,
    tracing_sd_mm=TRACING_SD_MM,
    tracing_length_mm=TRACING_LENGTH_MM,
    side_offset_sd_mm=SIDE_OFFSET_SD_MM,
)


def trial_errors(subject, seed=DEFAULT_SEED):
    """The errors of each trial that are not per reading: shared tilt, depth, wedge.

    Parameters
    ----------
    subject : SubjectParameters
    seed : int, optional
        Dataset seed.

    Returns
    -------
    dict
        ``depth_mm -> (shared_tilt, depth_error_mm, wedge_shift_mm)``, in the
        subject's depth order (stream 5 of the subject).
    """
    rng = subject_rng(seed, subject.species, subject.index, 5)
    draws = rng.normal(0.0, 1.0, (len(subject.depths_mm), 3))
    sizes = np.array([SHARED_TILT_SD, DEPTH_SD_MM, WEDGE_POSITION_SD_MM])
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
    x = np.asarray(distance_mm, dtype=float)
    seen_mm = np.clip(x + (wedge_shift_mm if side == "left" else -wedge_shift_mm), 0.0, None)
    scale = 1.0 + depth_error_mm / trial.depth_mm
    return scale * _trial_deflection_mm(seen_mm, trial, side) + shared_tilt * x


def profile_table(
    subject, seed=DEFAULT_SEED, magnification=MAGNIFICATION, shuffle=False, errors=True
):
    """Simulated digitised readings of one finger, in image units.

    For each depth and side: the reading grid up to that side's edge (first
    reading at 0.05 mm with probability 0.6, else 0.1 mm); the true deflection
    as the trial's shared errors make it read (:func:`true_reading_mm`: depth
    error, wedge position, shared tilt); plus the side's own errors
    (:data:`SIDE_NOISE`: independent reading error, tracing error correlated
    along the outline, an offset of the side's trace; stream 6), symmetric and
    not clipped, so a reading can be slightly negative where the skin barely
    moves; plus the trial's registration error (:func:`registration_error_mm`);
    rounded to 0.1 mm on the enlargement.  At the edge, where the outlines
    rejoin, the reading carries the registration error only.

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

    Returns
    -------
    pandas.DataFrame
        Columns ``depth_mm``, ``side``, ``distance_image_mm``,
        ``deflection_image_mm``.
    """
    rng = subject_rng(seed, subject.species, subject.index, 1)
    tracing_rng = subject_rng(seed, subject.species, subject.index, 6)
    registration = registration_error_mm(subject, seed)
    shared = trial_errors(subject, seed)
    depth, side, distance, deflection = [], [], [], []
    for depth_mm in subject.depths_mm:
        trial = trial_parameters(subject, depth_mm)
        offset_mm, tilt = registration[float(depth_mm)]
        for side_name in ("left", "right"):
            first_mm = GRID_TICK_MM if rng.random() < P_FIRST_AT_FINEST else 2 * GRID_TICK_MM
            distance_mm = reading_distances_mm(trial.extent_mm(side_name), first_mm)
            noise_mm = draw_side_errors_mm(tracing_rng, distance_mm, SIDE_NOISE)
            signed_mm = -distance_mm if side_name == "left" else distance_mm
            if errors:
                true_mm = true_reading_mm(distance_mm, trial, side_name, shared[float(depth_mm)])
                read_mm = true_mm + noise_mm + offset_mm + tilt * signed_mm
                read_mm[-1] = offset_mm + tilt * signed_mm[-1]  # the edge: outlines meet
            else:
                read_mm = true_reading_mm(distance_mm, trial, side_name, (0.0, 0.0, 0.0))
                read_mm[-1] = 0.0
            depth.append(np.full(distance_mm.size, depth_mm))
            side.append(np.full(distance_mm.size, side_name, dtype=object))
            distance.append(_to_image(distance_mm, magnification))
            deflection.append(
                _to_image(read_mm, magnification) if errors else read_mm * magnification
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
            _trial_deflection_mm(-x_mm, trial, "left"),
            _trial_deflection_mm(x_mm, trial, "right"),
        )
        for state, z_mm in (("resting", resting_mm), ("deformed", resting_mm - deflection_mm)):
            frames.append(
                pd.DataFrame(
                    {
                        "depth_mm": depth_mm,
                        "state": state,
                        "x_image_mm": _to_image(x_mm, magnification),
                        "z_image_mm": _to_image(z_mm, magnification),
                    }
                )
            )
    return pd.concat(frames, ignore_index=True)


def subjects_table(subjects, magnification=MAGNIFICATION):
    """The subject sheet: ``subject``, ``species``, ``magnification``, ``label``.

    ``contact_length_mm`` follows when every finger has one (the shipped ones).

    Parameters
    ----------
    subjects : list of SubjectParameters
    magnification : float, optional

    Returns
    -------
    pandas.DataFrame
    """
    table = pd.DataFrame(
        {
            "subject": [s.subject for s in subjects],
            "species": [s.species for s in subjects],
            "magnification": float(magnification),
            "label": [s.label for s in subjects],
        }
    )
    if all(s.contact_length_mm is not None for s in subjects):
        table["contact_length_mm"] = [s.contact_length_mm for s in subjects]
    return table


def parameter_table(subjects):
    """True-profile parameters of every trial (one row per subject and depth).

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    pandas.DataFrame
        ``subject``, ``species``, ``depth_mm``, ``extent_left_mm``,
        ``extent_right_mm``, ``exponent``, ``near_fraction``, ``near_exponent``.
    """
    rows = []
    for subject in subjects:
        for depth_mm in subject.depths_mm:
            trial = trial_parameters(subject, depth_mm)
            rows.append({"subject": subject.subject, "species": subject.species, **trial.__dict__})
    columns = [
        "subject",
        "species",
        "depth_mm",
        "extent_left_mm",
        "extent_right_mm",
        "exponent",
        "near_fraction",
        "near_exponent",
    ]
    return pd.DataFrame(rows)[columns]


def parameter_markdown(subjects):
    """The per-trial parameter table as Markdown, as printed in ``data/README.md``.

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    str
        A Markdown table ending with a newline.
    """
    headers = [
        "subject",
        "species",
        "depth (mm)",
        "edge left e_L (mm)",
        "edge right e_R (mm)",
        "p",
        "beta",
        "q",
    ]
    rows = [
        [
            row.subject,
            row.species,
            f"{row.depth_mm:.2f}",
            f"{row.extent_left_mm:.2f}",
            f"{row.extent_right_mm:.2f}",
            f"{row.exponent:.3f}",
            f"{row.near_fraction:.4f}",
            f"{row.near_exponent:g}",
        ]
        for row in parameter_table(subjects).itertuples(index=False)
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def subject_markdown(subjects):
    """The per-subject parameters as a Markdown table, as printed in ``data/README.md``.

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    str
        A Markdown table ending with a newline.
    """
    headers = [
        "subject",
        "species",
        "depths (mm)",
        "e at 0.5 mm",
        "e at 2 mm",
        "p at 0.5 mm",
        "p at 2 mm",
        "beta at 2 mm",
        "a (left/right)",
        "resting radius (mm)",
    ]
    rows = [
        [
            s.subject,
            s.species,
            ", ".join(f"{d:g}" for d in s.depths_mm),
            f"{s.extent_shallow_mm:g}",
            f"{s.extent_deep_mm:g}",
            f"{s.exponent_shallow:g}",
            f"{s.exponent_deep:g}",
            f"{s.near_fraction_deep:g}",
            f"{s.side_asymmetry:+g}",
            "-" if s.resting_radius_mm is None else f"{s.resting_radius_mm:g}",
        ]
        for s in subjects
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def membrane_markdown(subjects):
    """The membrane of each finger with one, as a Markdown table, as printed in ``data/README.md``.

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    str
        A Markdown table ending with a newline (no rows if no finger has a membrane).
    """
    headers = [
        "subject",
        "contact length l (mm)",
        "stiffness E (N/mm)",
        "pre-strain N0/E",
        "pre-tension N0 (N/mm)",
    ]
    rows = [
        [
            s.subject,
            f"{s.contact_length_mm:g}",
            f"{s.stiffness_N_per_mm:g}",
            f"{s.prestrain:g}",
            f"{s.pretension_N_per_mm:.4f}",
        ]
        for s in subjects
        if s.contact_length_mm is not None
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def force_markdown(subjects, seed=DEFAULT_SEED):
    """Every trial's membrane geometry and force as a Markdown table (``data/README.md``).

    Parameters
    ----------
    subjects : list of SubjectParameters
    seed : int, optional

    Returns
    -------
    str
        A Markdown table ending with a newline.
    """
    headers = [
        "subject",
        "depth (mm)",
        "arc L (mm)",
        "theta0 (rad)",
        "strain",
        "true force (N)",
        "force_N as written",
    ]
    rows = [
        [
            s.subject,
            f"{r['depth_mm']:.2f}",
            f"{r['L_mm']:.3f}",
            f"{r['load_angle_rad']:.4f}",
            f"{r['strain']:.5f}",
            f"{r['true_force_N']:.4f}",
            f"{r['force_N']:.3f}",
        ]
        for s in subjects
        if s.contact_length_mm is not None
        for r in trial_forces(s, seed)
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def _csv_text(table, formats):
    """CSV text with one fixed format per column (:func:`lineload.io.csv_text` lines)."""
    columns = [column for column in formats if column in table.columns]
    cells = []
    for column in columns:
        fmt = formats[column]
        values = table[column].tolist()
        cells.append([format(v, fmt) if fmt else str(v) for v in values])
    return csv_text(columns, cells)


SUBJECT_FORMATS = {
    "subject": "",
    "species": "",
    "magnification": ".1f",
    "label": "",
    "contact_length_mm": ".1f",
}
FORCE_FORMATS = {"subject": "", "depth_mm": ".2f", "force_N": ".3f"}
PROFILE_FORMATS = {
    "depth_mm": ".2f",
    "side": "",
    "distance_image_mm": ".1f",
    "deflection_image_mm": ".1f",
}
OUTLINE_FORMATS = {"depth_mm": ".2f", "state": "", "x_image_mm": ".1f", "z_image_mm": ".1f"}


#: Written as NOTICE.txt into every generated folder; its first line becomes the
#: footer of each figure and table built from these data.
DATA_NOTICE = (
    "Synthetic reconstruction made by a seeded generator; not the original measurements "
    "of Srinivasan (1989).\n"
    "The study's digitised profiles were never published. See data/README.md for how these "
    "files were made.\n"
)


#: What the generator puts into the shipped reconstruction, claim by claim (the
#: verdict, its truth and how it comes about), is stated in each claim's registry entry
#: (``built_in``); written to ``data/built_in_verdicts.json`` by the generator's script.
built_in_verdicts = _registry_built_in_verdicts


def build_dataset(
    seed=DEFAULT_SEED, n_monkeys=None, n_humans=None, shuffle=False, magnification=MAGNIFICATION
):
    """Every file of a synthetic raw-data folder, as text.

    Parameters
    ----------
    seed : int, optional
        Dataset seed (1989 for the shipped data).
    n_monkeys, n_humans : int, optional
        Scale mode: that many fingers with drawn parameters.  Leave both
        ``None`` for the seven hand-chosen fingers of the shipped data.
    shuffle : bool, optional
        Shuffle the rows of each profile file (seeded).
    magnification : float, optional
        Enlargement factor written to the subject sheet and applied to readings.

    Returns
    -------
    dict of str to str
        Relative POSIX path (``NOTICE.txt``, ``subjects.csv``, ``forces.csv``
        when the fingers have membranes, ``profiles/M1.csv``,
        ``outlines/M1.csv``...) to file content, in a
        stable order.  ``NOTICE.txt`` marks the folder as synthetic: the
        workflow prints its first line under every figure and table.
    """
    if n_monkeys is None and n_humans is None:
        subjects = shipped_subjects()
    else:
        subjects = draw_subjects(n_monkeys or 0, n_humans or 0, seed)
    if not subjects:
        raise ValueError("a dataset needs at least one subject")
    files = {
        "NOTICE.txt": DATA_NOTICE,
        "subjects.csv": _csv_text(subjects_table(subjects, magnification), SUBJECT_FORMATS),
    }
    forces = force_table(subjects, seed)
    if len(forces):
        files["forces.csv"] = _csv_text(forces, FORCE_FORMATS)
    for subject in subjects:
        readings = profile_table(subject, seed, magnification, shuffle)
        files[f"profiles/{subject.subject}.csv"] = _csv_text(readings, PROFILE_FORMATS)
    for subject in subjects:
        if subject.resting_radius_mm is not None:
            files[f"outlines/{subject.subject}.csv"] = _csv_text(
                outline_table(subject, magnification), OUTLINE_FORMATS
            )
    return files


# ---------------------------------------------------------------- photographs

#: The photograph example: which fingers, at which depths, seen how.
PHOTOGRAPH_SUBJECTS = ("M1", "M2")
PHOTOGRAPH_DEPTHS_MM = (1.0, 2.0)
#: Radius of the resting finger in the photographs (mm): a side view of a fingertip,
#: wide enough that the skin beyond the deformed region is still nearly level.
PHOTOGRAPH_RADIUS_MM = 12.0
#: Field of view of every photograph: 60 pixels per tissue mm, 16 mm wide.
PHOTOGRAPH_PIXELS_PER_MM = 60.0
PHOTOGRAPH_VIEW_MM = (-8.0, 0.6, 16.0, 4.0)  # x0, z0 (top left), width, height
#: Largest shift of the loaded shot against the resting one (mm): camera or finger moved.
PHOTOGRAPH_SHIFT_MM = 0.03

PHOTOGRAPH_NOTICE = (
    "Synthetic photographs rendered by a seeded generator from the reconstruction's true "
    "profiles; not photographs of fingers.\n"
    "See data/README.md for how they are made.\n"
)


def photograph_scene():
    """The :class:`lineload.rawdata.photographs.Scene` of every example photograph."""
    from lineload.rawdata.photographs import Scene

    x0, z0, width, height = PHOTOGRAPH_VIEW_MM
    ppmm = PHOTOGRAPH_PIXELS_PER_MM
    return Scene(ppmm, x0, z0, round(width * ppmm), round(height * ppmm))


def photograph_outlines(subject, depth_mm, shift_mm=(0.0, 0.0)):
    """Resting and loaded outlines (callables of x, mm) of one trial, and the wedge's tip.

    The resting finger is a circle of :data:`PHOTOGRAPH_RADIUS_MM` whose top is at
    ``z = 0``; the loaded one is lowered by the trial's true deflection on each side
    (:func:`true_deflection_mm`), and the loaded shot is moved by ``shift_mm``.
    """
    trial = trial_parameters(subject, depth_mm)
    radius = PHOTOGRAPH_RADIUS_MM
    dx, dz = shift_mm

    def rest(x):
        x = np.asarray(x, dtype=float)
        return -(radius - np.sqrt(radius**2 - np.minimum(x**2, 0.99 * radius**2)))

    def loaded(x):
        xs = np.asarray(x, dtype=float) - dx
        extent = np.where(xs < 0, trial.extent_left_mm, trial.extent_right_mm)
        return rest(xs) - _trial_deflection_mm(xs, trial, extent_mm=extent) + dz

    return rest, loaded, (dx, float(loaded(dx)))


def photograph_dataset(seed=DEFAULT_SEED, camera=None):
    """The photograph example: every file of its raw-data folder.

    Two monkeys of the reconstruction (:data:`PHOTOGRAPH_SUBJECTS`) at two depths, each
    trial a resting and a loaded side view rendered from the true profiles with what a
    camera adds (:class:`lineload.rawdata.photographs.Camera`, its defaults unless given), the
    loaded shot moved a little against the resting one, seeded per trial.

    Returns
    -------
    dict
        Relative path -> content: ``NOTICE.txt``, ``subjects.csv``,
        ``images/images.csv`` and ``images/truth.csv`` (the true deflection the
        photographs were rendered from) as text, the photographs (PNG) as bytes.
    """
    import io

    import imageio.v3 as iio

    from lineload.rawdata.photographs import Camera, render_photograph

    camera = camera or Camera()
    scene = photograph_scene()
    subjects = {s.subject: s for s in shipped_subjects()}
    files = {
        "NOTICE.txt": PHOTOGRAPH_NOTICE,
        "subjects.csv": "subject,species,magnification,label\n"
        + "".join(
            f"{name},{subjects[name].species},1,{subjects[name].label}\n"
            for name in PHOTOGRAPH_SUBJECTS
        ),
    }
    rows = ["subject,depth_mm,state,file,pixels_per_mm"]
    for number, name in enumerate(PHOTOGRAPH_SUBJECTS):
        for depth_mm in PHOTOGRAPH_DEPTHS_MM:
            rng = np.random.default_rng([seed, number, round(depth_mm * 100), 77])
            shift = tuple(rng.uniform(-PHOTOGRAPH_SHIFT_MM, PHOTOGRAPH_SHIFT_MM, 2))
            rest, loaded, tip = photograph_outlines(subjects[name], depth_mm, shift)
            shots = {
                "rest": render_photograph(rest, scene, camera, rng),
                "loaded": render_photograph(loaded, scene, camera, rng, wedge_tip_mm=tip),
            }
            for state, image in shots.items():
                file = f"{name}_{depth_mm:g}mm_{state}.png"
                buffer = io.BytesIO()
                iio.imwrite(buffer, image, extension=".png")
                files[f"images/{file}"] = buffer.getvalue()
                rows.append(f"{name},{depth_mm:g},{state},{file},{PHOTOGRAPH_PIXELS_PER_MM:g}")
    files["images/images.csv"] = "\n".join(rows) + "\n"
    # the truth the photographs were rendered from, at the distances a reader reads
    truth = ["subject,depth_mm,side,distance_mm,deflection_mm"]
    for name in PHOTOGRAPH_SUBJECTS:
        for depth_mm in PHOTOGRAPH_DEPTHS_MM:
            trial = trial_parameters(subjects[name], depth_mm)
            for side in ("left", "right"):
                distance = reading_distances_mm(trial.extent_mm(side), 0.05)
                w = _trial_deflection_mm(distance, trial, side)
                truth += [
                    f"{name},{depth_mm:g},{side},{d:.4f},{v:.6f}"
                    for d, v in zip(distance, w, strict=True)
                ]
    files["images/truth.csv"] = "\n".join(truth) + "\n"
    return files
