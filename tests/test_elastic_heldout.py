"""Held-out profiles of the finite-element finger through the whole build: no 'nan' anywhere.

The plane-strain finger (:mod:`lineload.elastic`) makes profiles that belong to none of the
fitted families: fits end on their bounds, the shifted curve may not exist (L below
sqrt(6) W0), intervals may be one-sided.  Whatever the fits do, what a reader sees (the
tables, the figures' text, the article's facts) must say it in words, never 'nan'.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from conftest import shared_build
from lineload.elastic import materials, solver
from lineload.elastic import mesh as meshing
from lineload.elastic.geometry import SPECIES
from lineload.elastic.wedge import Wedge
from lineload.rawdata.readings import GRID_TICK_MM, reading_distances_mm

pytestmark = pytest.mark.e2e

#: Coarse meshes (a few tenths of a second per finger): the test wants profiles that are
#: not of any fitted family, not converged ones.
GRADE = 0.5
#: Depths per species (mm): at 2 mm only the monkey's, whose L there is below sqrt(6) W0,
#: where the shifted parabola does not exist (the arc-versus-parabola supplement's case).
DEPTHS_MM = {"monkey": (0.5, 1.0, 2.0), "human": (0.5, 1.0, 1.5)}
MAGNIFICATION = 20.0
#: Digitising noise added to each side's readings (mm), as the small raw datasets have.
READING_SD_MM = 0.005
#: The profile is read out to where the deflection falls below this share of the depth.
EDGE_SHARE = 0.01
#: A 'nan' as a word, in any case (not inside 'financial' or 'nanometre').
NAN = re.compile(r"\bnan\b", re.IGNORECASE)


def _material(species, layered):
    if not layered:
        return materials.Homogeneous(0.1)
    return materials.TwoLayer(0.1, 5.0, SPECIES[species].outer_layer_thickness.value_mm)


def finite_element_profiles(species, layered):
    """``{depth: (distance_mm, deflection_mm)}`` of one finger on the shipped reading grid."""
    section = SPECIES[species].section()
    material = _material(species, layered)
    wedge = Wedge()
    mesh = meshing.finger_mesh(
        section,
        material.layer_thickness_mm or 1.0,
        solver.FINEST_PER_TIP_RADIUS * wedge.tip_radius_mm,
        GRADE,
    )
    profiles = {}
    depths_mm = DEPTHS_MM[species]
    for depth_mm, solution in zip(
        depths_mm, solver.solve_depths(mesh, section, material, wedge, depths_mm), strict=True
    ):
        below = np.flatnonzero(solution.deflection_mm < EDGE_SHARE * depth_mm)
        edge_mm = solution.distance_mm[below[0]] if below.size else solution.distance_mm[-1]
        distance_mm = reading_distances_mm(np.floor(edge_mm / GRID_TICK_MM) * GRID_TICK_MM)
        profiles[depth_mm] = (distance_mm, solution.deflection_at_mm(distance_mm))
    return profiles


def write_finite_element_dataset(raw_dir, seed=11):
    """A raw folder in the contract: a monkey and a human finger, each homogeneous and
    two-layer, at 0.5-2 mm (:data:`DEPTHS_MM`), both sides read with independent noise."""
    rng = np.random.default_rng(seed)
    (raw_dir / "profiles").mkdir(parents=True, exist_ok=True)
    subjects = ["subject,species,magnification,label"]
    for species in ("monkey", "human"):
        for layered in (False, True):
            subject = f"{species[0].upper()}{'L' if layered else 'H'}"
            kind = "two-layer" if layered else "homogeneous"
            subjects.append(f"{subject},{species},{MAGNIFICATION:g},{species} FE {kind}")
            rows = ["depth_mm,side,distance_image_mm,deflection_image_mm"]
            for depth_mm, (x, w) in finite_element_profiles(species, layered).items():
                for side in ("left", "right"):
                    read = np.clip(w + rng.normal(0.0, READING_SD_MM, x.size), 0.0, None)
                    rows += [
                        f"{depth_mm:g},{side},{xi * MAGNIFICATION:.3f},{wi * MAGNIFICATION:.3f}"
                        for xi, wi in zip(x, read, strict=True)
                    ]
            (raw_dir / "profiles" / f"{subject}.csv").write_text("\n".join(rows) + "\n")
    (raw_dir / "subjects.csv").write_text("\n".join(subjects) + "\n")
    return raw_dir


@pytest.fixture(scope="module")
def finite_element_build(tmp_path_factory):
    """One build for the session, whichever worker asks first (its tests read only)."""
    _, results = shared_build(tmp_path_factory, "finite_element", write_finite_element_dataset)
    return results


def _reader_files(results):
    """The tables (CSV, Markdown) and JSON a reader gets, not the copied source (whose
    documents name NaN as a refused input) nor the logs."""
    return [
        path
        for path in sorted(results.rglob("*"))
        if path.suffix in (".csv", ".md", ".json")
        and path.relative_to(results).parts[0] not in ("source", "logs", "benchmarks")
    ]


def _nan_lines(text):
    return [line.strip()[:200] for line in text.splitlines() if NAN.search(line)]


def test_the_finite_element_fingers_reach_the_cases_that_made_nan(finite_element_build):
    # the test is only worth its build if the profiles are of none of the families: some
    # fit ends on its bound, and at 2 mm the shifted parabola does not exist at the median L
    import pandas as pd

    fits = pd.read_csv(finite_element_build / "tables" / "fits.csv")
    assert fits[[c for c in fits.columns if c.endswith("_at_bound")]].any(axis=None)
    deep = fits[fits["depth_mm"] == 2.0]
    assert deep["waterbed_L_mm"].median() < np.sqrt(6) * 2.0


def test_a_fit_on_its_bound_is_not_read_as_precise(finite_element_build):
    # a fit that ends on the lower bound of L has no minimum there, only a slope: its
    # interval must not shrink to the microns that slope gives, so it is at least half
    # as wide (relative to L) as the narrowest interval of a fit that found a minimum
    import pandas as pd

    fits = pd.read_csv(finite_element_build / "tables" / "fits.csv")
    checked = 0
    for model in ("waterbed", "shifted", "arc"):
        width = (fits[f"{model}_L_ci_high_mm"] - fits[f"{model}_L_ci_low_mm"]) / fits[
            f"{model}_L_mm"
        ]
        bound = fits[f"{model}_L_at_bound"].astype(bool)
        if not bound.any():
            continue
        assert width[bound].notna().all()
        assert width[bound].min() >= 0.5 * width[~bound].min(), fits.loc[bound, "subject"]
        checked += 1
    assert checked


def test_no_nan_in_any_table_or_fact(finite_element_build):
    files = _reader_files(finite_element_build)
    assert any(path.name == "fits.csv" for path in files)
    assert any(path.name == "facts.json" for path in files)
    found = {
        path.relative_to(finite_element_build).as_posix(): hits
        for path in files
        if (hits := _nan_lines(path.read_text(encoding="utf-8")))
    }
    assert found == {}


def test_no_nan_in_the_facts_values(finite_element_build):
    # facts.json holds floats too: a NaN written as a bare token is not JSON, so Python
    # reads it back as nan; every value must be a finite number, a string or a list of them
    facts = json.loads(
        next(finite_element_build.rglob("facts.json")).read_text(encoding="utf-8"),
        parse_constant=lambda name: pytest.fail(f"facts.json holds {name}"),
    )
    assert facts


def test_no_nan_in_the_figures_text(finite_element_build):
    from pypdf import PdfReader

    pdfs = sorted(
        path
        for path in finite_element_build.rglob("*.pdf")
        if path.relative_to(finite_element_build).parts[0] in ("figures", "article")
    )
    assert len(pdfs) > 5
    found = {}
    for path in pdfs:
        text = "\n".join(page.extract_text() or "" for page in PdfReader(path).pages)
        assert text.strip(), f"{path.name}: no text extracted"
        if hits := _nan_lines(text):
            found[path.name] = hits
    assert found == {}
