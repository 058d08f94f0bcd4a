"""The fingers of the synthetic reconstruction: who they are and the shape of their skin.

The digitised profiles behind Srinivasan (1989) were never published.  The
generator builds a stand-in dataset that follows every experimental number the
paper gives (subjects, depths, reading grid, magnification, extent of the
deformed region) from a *true* profile that is deliberately neither of the
models the workflow fits.  This module holds the fingers and their true
profiles; :mod:`lineload.simulation.errors` what reading them adds,
:mod:`lineload.simulation.readings` the readings themselves.

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

The calibration's boundary worlds (:mod:`lineload.simulation.boundary`) also blend in,
with weight ``c``, the circle that meets the resting surface at the edge with
zero slope and passes through the depth at the wedge (``circle_fraction``;
zero for the shipped fingers): ``w = (1 - c) w_above + c w_circle``.

Every function here is pure: no file is read or written.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lineload import paper
from lineload.rawdata.readings import GRID_TICK_MM

__all__ = [
    "DEFAULT_SEED",
    "DEPTHS_MM",
    "MAGNIFICATION",
    "PARAMETER_RANGES",
    "SubjectParameters",
    "TrialParameters",
    "draw_subjects",
    "shipped_subjects",
    "subject_rng",
    "trial_deflection_mm",
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
        0 for parameter draws, 1 for the reading grids, 2 for row shuffling, 3
        for the registration error of each trial, 4 for the force readings, 5 for
        the other errors shared by a trial's readings, 6 for each side's own
        errors (:mod:`lineload.simulation.readings`).

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


def trial_deflection_mm(distance_mm, trial, side=None, extent_mm=None):
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
