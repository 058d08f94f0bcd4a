"""The calibration of the claims' verdicts: its public face.

How often each claim's rule reaches the right verdict, measured on datasets whose
truth is known.  Its parts, one idea each:

- :mod:`lineload.simulation.verdicts`: the reconstruction's own world read with
  fresh errors and analysed as the workflow does (:func:`reconstruction_claims`,
  :func:`verdict_study`);
- :mod:`lineload.simulation.boundary`: the boundary worlds, each claim where its
  rule has the least power;
- :mod:`lineload.simulation.mechanics_coverage`: the membrane's intervals on the
  same datasets;
- :mod:`lineload.simulation.reports`: their tables as Markdown;
- :mod:`lineload.simulation.rates`: binomial intervals and the error-rate
  sentences the claims table prints.

This module gathers their public names for readers and tests; code that needs one
part imports that part.
"""

from __future__ import annotations

from lineload.simulation.boundary import (
    BOUNDARY_COLUMNS,
    BOUNDARY_SUMMARY_COLUMNS,
    BOUNDARY_WORLDS,
    SIDES,
    boundary_effect,
    boundary_study,
    summarise_boundary,
)
from lineload.simulation.mechanics_coverage import (
    MECHANICS_COLUMNS,
    MECHANICS_SUMMARY_COLUMNS,
    mechanics_study,
    summarise_mechanics,
)
from lineload.simulation.rates import binomial_interval, claim_error_rates, percent_interval
from lineload.simulation.reports import boundary_markdown, mechanics_markdown, verdict_markdown
from lineload.simulation.verdicts import (
    BENDING_CLAIMS,
    DATASET_COLUMNS,
    SUMMARY_COLUMNS,
    TRUTH_SCALE,
    UNCALIBRATED_CLAIMS,
    reconstruction_claims,
    reconstruction_fits,
    summarise_verdicts,
    verdict_study,
)

__all__ = [
    "BENDING_CLAIMS",
    "BOUNDARY_COLUMNS",
    "BOUNDARY_SUMMARY_COLUMNS",
    "BOUNDARY_WORLDS",
    "DATASET_COLUMNS",
    "MECHANICS_COLUMNS",
    "MECHANICS_SUMMARY_COLUMNS",
    "SIDES",
    "SUMMARY_COLUMNS",
    "TRUTH_SCALE",
    "UNCALIBRATED_CLAIMS",
    "binomial_interval",
    "boundary_effect",
    "boundary_markdown",
    "boundary_study",
    "claim_error_rates",
    "mechanics_markdown",
    "mechanics_study",
    "percent_interval",
    "reconstruction_claims",
    "reconstruction_fits",
    "summarise_boundary",
    "summarise_mechanics",
    "summarise_verdicts",
    "verdict_markdown",
    "verdict_study",
]
