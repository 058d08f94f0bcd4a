"""Seeded generator of the synthetic reconstruction shipped in ``data/raw``: its public face.

The digitised profiles behind Srinivasan (1989) were never published.  The
generator builds a stand-in dataset that follows every experimental number the
paper gives from a *true* profile that is deliberately neither of the models
the workflow fits, plus seeded digitising errors.  Its parts, one idea each:

- :mod:`lineload.simulation.subjects`: the fingers, their true profiles and
  random streams (``shipped_subjects``, ``draw_subjects``, ``PARAMETER_RANGES``);
- :mod:`lineload.simulation.errors`: the forward error model, the one the
  coverage study uses too (every error's size, ``read_side_mm``);
- :mod:`lineload.simulation.readings`: the profiles, outlines and forces as read;
- :mod:`lineload.simulation.dataset`: the files of the raw-data folder and the
  tables of true parameters;
- :mod:`lineload.simulation.photograph_example`: the photograph example.

This module gathers their public names, for the CLI
``workflow/scripts/make_synthetic_data.py`` and for readers; code that needs one
part imports that part.
"""

from __future__ import annotations

from lineload.rawdata.readings import reading_distances_mm
from lineload.simulation.dataset import (
    DATA_NOTICE,
    build_dataset,
    built_in_verdicts,
    force_markdown,
    membrane_markdown,
    parameter_markdown,
    parameter_table,
    subject_markdown,
    subjects_table,
)
from lineload.simulation.errors import (
    DEPTH_SD_MM,
    FORCE_NOISE_SD_N,
    FORCE_RESOLUTION_N,
    IMAGE_RESOLUTION_MM,
    NOISE_SD_MM,
    REGISTRATION_OFFSET_SD_MM,
    REGISTRATION_TILT_SD,
    SHARED_TILT_SD,
    SIDE_NOISE,
    SIDE_OFFSET_SD_MM,
    TRACING_LENGTH_MM,
    TRACING_SD_MM,
    WEDGE_POSITION_SD_MM,
)
from lineload.simulation.photograph_example import (
    PHOTOGRAPH_DEPTHS_MM,
    PHOTOGRAPH_SUBJECTS,
    photograph_dataset,
    photograph_outlines,
    photograph_scene,
)
from lineload.simulation.readings import (
    force_table,
    noise_free_mean_profile,
    outline_table,
    profile_table,
    registration_error_mm,
    trial_errors,
    trial_forces,
    true_reading_mm,
)
from lineload.simulation.subjects import (
    DEFAULT_SEED,
    DEPTHS_MM,
    MAGNIFICATION,
    PARAMETER_RANGES,
    SubjectParameters,
    TrialParameters,
    draw_subjects,
    shipped_subjects,
    subject_rng,
    trial_parameters,
    true_deflection_mm,
)

__all__ = [
    "DATA_NOTICE",
    "DEFAULT_SEED",
    "DEPTHS_MM",
    "DEPTH_SD_MM",
    "FORCE_NOISE_SD_N",
    "FORCE_RESOLUTION_N",
    "IMAGE_RESOLUTION_MM",
    "MAGNIFICATION",
    "NOISE_SD_MM",
    "PARAMETER_RANGES",
    "PHOTOGRAPH_DEPTHS_MM",
    "PHOTOGRAPH_SUBJECTS",
    "REGISTRATION_OFFSET_SD_MM",
    "REGISTRATION_TILT_SD",
    "SHARED_TILT_SD",
    "SIDE_NOISE",
    "SIDE_OFFSET_SD_MM",
    "TRACING_LENGTH_MM",
    "TRACING_SD_MM",
    "WEDGE_POSITION_SD_MM",
    "SubjectParameters",
    "TrialParameters",
    "build_dataset",
    "built_in_verdicts",
    "draw_subjects",
    "force_markdown",
    "force_table",
    "membrane_markdown",
    "noise_free_mean_profile",
    "outline_table",
    "parameter_markdown",
    "parameter_table",
    "photograph_dataset",
    "photograph_outlines",
    "photograph_scene",
    "profile_table",
    "reading_distances_mm",
    "registration_error_mm",
    "shipped_subjects",
    "subject_markdown",
    "subject_rng",
    "subjects_table",
    "trial_errors",
    "trial_forces",
    "trial_parameters",
    "true_deflection_mm",
    "true_reading_mm",
]
