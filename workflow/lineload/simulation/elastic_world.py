"""A calibration world the fits do not assume: the finite-element finger read as a lab reads it.

The coverage and verdict calibrations make their profiles from the fitted families or from
the reconstruction's power law; neither is a physics the fits could be wrong about. Here the
true profiles are those of the plane-strain finite-element finger (:mod:`lineload.elastic`),
homogeneous or with a stiffer outer layer, of sections the elastic library does not hold
(drawn from the same stated ranges with another seed) and solved on another mesh grade
than the library's. Each dataset is a set of such fingers at the paper's four depths, read
on both sides with every digitising error of :mod:`lineload.simulation.errors`, and analysed
as the workflow analyses a lab's data: readings to tissue mm and the left-right mean
(:mod:`lineload.averaging`), the noise measured from the left-right differences
(:func:`lineload.noise.measure_noise_table`), the paper's models fitted with that noise
(:func:`lineload.fitting.batch.fit_trials`), the elastic finger fitted from the committed
library (:func:`lineload.fitting.elastic.fit_elastic_trials`) and the claims judged
(:func:`lineload.claims.compute_claims` with :func:`lineload.claims.judged_settings`).

Three scores:

``coverage``
    whether each paper's model's interval (``L`` of the waterbed and the arc, ``A`` and
    ``x0`` of the Boussinesq form) holds that model's best fit to the error-free profile
    (the same readings without errors, the same window; the fits are ordinary least
    squares whatever the noise, :mod:`lineload.fitting.batch`, so this is the value the
    estimator aims at when the model is wrong).
``verdicts``
    each claim's verdict against its truth: the verdict the same rules reach on the
    error-free readings, except C12's, whose truth is the finger's own (layered: holds;
    homogeneous: does not hold).
``ratio``
    whether the layered elastic fit's interval holds the finger's true modulus ratio, and
    whether it excludes 1; and whether it holds the layered fit's ratio on the error-free
    profile (what the fit aims at, given that the library holds neither the section nor
    the mesh).

Every function is pure: the solved profiles are a table (:func:`solve_world_profiles`)
that the study script keeps in the repository, so the second half reruns without the solver.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from lineload.averaging import tissue_columns
from lineload.claims import FAILS, HOLDS
from lineload.claims.registry import CLAIMS, FORCE_CLAIMS
from lineload.elastic import materials, solver
from lineload.elastic import mesh as meshing
from lineload.elastic.geometry import SPECIES
from lineload.elastic.library import library_sections
from lineload.elastic.wedge import Wedge
from lineload.fitting.elastic import fit_elastic_trials, with_elastic
from lineload.noise import draw_side_errors_mm
from lineload.rawdata.readings import GRID_TICK_MM, reading_distances_mm
from lineload.simulation.analysis import analyse, judged_claims
from lineload.simulation.coverage import CHECKED
from lineload.simulation.errors import TRUE_NOISE, TrialErrors, image_mm, read_side_mm
from lineload.simulation.rates import binomial_interval
from lineload.simulation.readings import P_FIRST_AT_FINEST
from lineload.simulation.subjects import MAGNIFICATION, SPECIES_PREFIX
from lineload.simulation.verdicts import summarise_verdicts

__all__ = [
    "COVERAGE_COLUMNS",
    "GRADE",
    "PROFILE_COLUMNS",
    "RATIOS",
    "RATIO_COLUMNS",
    "READ_REACH_MM",
    "SECTIONS_PER_SPECIES",
    "SECTION_SEED",
    "VERDICT_COLUMNS",
    "WorldFinger",
    "analyse_dataset",
    "read_dataset",
    "solutions_from_table",
    "solve_world_profiles",
    "summarise_ratio",
    "summarise_world_coverage",
    "summarise_world_verdicts",
    "world_dataset",
    "world_fingers",
    "world_name",
    "world_sections",
    "world_study",
]

#: Seed of the world's sections (the library's is 36, the margin study's 3612 and 3613).
SECTION_SEED = 3636
#: Sections per species: each a subject of every dataset.
SECTIONS_PER_SPECIES = 4
#: The fingers' modulus ratios (outer layer over pulp); 1 is the homogeneous finger.
RATIOS = (1.0, 2.0, 5.0, 20.0, 100.0)
#: The solver's mesh grade for these fingers (the library's is 0.4).
GRADE = 0.5
#: How far from the wedge each side is read (mm): the shipped reading grid's last reading
#: (6 mm) for humans; for monkeys the library's last distance (4.5 mm), since the shortest
#: monkey sections drawn are about 12 mm long and their skin turns down toward the side
#: beyond that. The elastic finger's dip ends well inside both (under 2 mm from the wedge
#: in monkeys, 4 mm in humans, at 0.5 to 2 mm depth) and its skin rises beyond it (a nearly
#: incompressible pad bulges), so the outlines do not meet again at an edge: every reading,
#: the farthest too, reads the skin.
READ_REACH_MM = {"monkey": 4.5, "human": 6.0}
#: The profile is kept this far beyond the reach (mm): a misplaced wedge's reading sees the
#: skin up to its shift (SD 0.01 mm) further.
SHIFT_ROOM_MM = 0.2
#: Decimals of the kept profiles (mm): 0.1 nm, far below the solver's error.
PROFILE_DECIMALS = 7

#: Columns of the solved profiles' table: one row per skin node of the loaded side.
PROFILE_COLUMNS = [
    "species",
    "section",
    "length_mm",
    "height_mm",
    "pad_thickness_mm",
    "modulus_ratio",
    "layer_thickness_mm",
    "depth_mm",
    "force_per_length_N_per_mm",
    "contact_half_width_mm",
    "node",
    "distance_mm",
    "deflection_mm",
]
#: Columns of the coverage rows (one per dataset, trial, model and parameter).
COVERAGE_COLUMNS = [
    "world",
    "dataset",
    "subject",
    "species",
    "depth_mm",
    "model",
    "parameter",
    "true",
    "true_at_bound",
    "estimate",
    "low",
    "high",
    "covered",
]
#: Columns of the verdict rows (one per dataset and claim).
VERDICT_COLUMNS = ["world", "dataset", "claim", "truth", "verdict", "wrong"]
#: Columns of the ratio rows (one per dataset and trial).
RATIO_COLUMNS = [
    "world",
    "dataset",
    "subject",
    "species",
    "depth_mm",
    "true_ratio",
    "error_free_ratio",
    "ratio",
    "low",
    "high",
    "covered",
    "covers_error_free",
    "excludes_1",
    "at_end",
]

#: The opposite of each evidence verdict.
_OPPOSITE = {HOLDS: FAILS, FAILS: HOLDS}
#: Claims this world does not judge: those needing forces (no force is made: the finger's
#: force scales with a modulus this world does not fix) or the bending skin's fits.
NOT_JUDGED = tuple(
    claim.id for claim in CLAIMS if "bending" in claim.needs or claim.id in FORCE_CLAIMS
)


@dataclass(frozen=True)
class WorldFinger:
    """One subject of the world: a section of a species with a modulus ratio.

    Attributes
    ----------
    subject : str
        Id in a dataset (``M1``, ``H2``...).
    species : str
    section : int
        Number of the section among the world's sections of the species.
    modulus_ratio : float
        Outer layer over pulp (1: homogeneous).
    """

    subject: str
    species: str
    section: int
    modulus_ratio: float


def world_sections(species, grid, seed=SECTION_SEED, count=SECTIONS_PER_SPECIES):
    """Sections drawn as the library's are (same ranges, same usability), with another seed,
    the species' default section (the first drawn) left out.

    Parameters
    ----------
    species : str
    grid : lineload.elastic.library.LibraryGrid
        The library's grid (its depths decide which sections are usable).
    seed, count : int, optional

    Returns
    -------
    list of lineload.elastic.geometry.FingerSection
    """
    return library_sections(species, replace(grid, seed=seed, sections=count + 1))[1:]


def _solve(species, section, ratio, depths_mm, grade):
    wedge = Wedge()
    thickness_mm = SPECIES[species].outer_layer_thickness.value_mm
    mesh = meshing.finger_mesh(
        section, thickness_mm, solver.FINEST_PER_TIP_RADIUS * wedge.tip_radius_mm, grade
    )
    material = materials.TwoLayer(1.0, float(ratio), thickness_mm)
    return thickness_mm, solver.solve_depths(mesh, section, material, wedge, depths_mm)


def solve_world_profiles(species, sections, ratios, depths_mm, grade=GRADE):
    """Solve every section of a species at every ratio and depth; the skin's nodes kept.

    Parameters
    ----------
    species : str
    sections : sequence of FingerSection
        Numbered in order from 0.
    ratios : sequence of float
    depths_mm : sequence of float
    grade : float, optional
        The mesh's grade.

    Returns
    -------
    pandas.DataFrame
        Columns :data:`PROFILE_COLUMNS`: the loaded side's skin nodes (corners and
        midpoints alternating, as :class:`lineload.elastic.solver.ContactSolution` holds
        them) up to :data:`READ_REACH_MM` plus :data:`SHIFT_ROOM_MM`.
    """
    reach_mm = READ_REACH_MM[species] + SHIFT_ROOM_MM
    frames = []
    for number, section in enumerate(sections):
        for ratio in ratios:
            thickness_mm, series = _solve(species, section, ratio, depths_mm, grade)
            for depth_mm, solution in zip(depths_mm, series, strict=True):
                corners_mm = solution.distance_mm[::2]
                if corners_mm[-1] < reach_mm:
                    raise ValueError(
                        f"a {species} section {section.length_mm:.2f} mm long reaches "
                        f"{corners_mm[-1]:.2f} mm from the wedge, short of {reach_mm:g} mm"
                    )
                # through the first corner past the reach: every element side is whole
                keep = 2 * int(np.searchsorted(corners_mm, reach_mm)) + 1
                frames.append(
                    pd.DataFrame(
                        {
                            "species": species,
                            "section": number,
                            "length_mm": round(section.length_mm, 4),
                            "height_mm": round(section.height_mm, 4),
                            "pad_thickness_mm": round(section.pad_thickness_mm, 4),
                            "modulus_ratio": float(ratio),
                            "layer_thickness_mm": thickness_mm,
                            "depth_mm": float(depth_mm),
                            "force_per_length_N_per_mm": round(
                                solution.force_per_length_N_per_mm, PROFILE_DECIMALS
                            ),
                            "contact_half_width_mm": round(
                                solution.contact_half_width_mm, PROFILE_DECIMALS
                            ),
                            "node": np.arange(keep),
                            "distance_mm": np.round(solution.distance_mm[:keep], PROFILE_DECIMALS),
                            "deflection_mm": np.round(
                                solution.deflection_mm[:keep], PROFILE_DECIMALS
                            ),
                        }
                    )
                )
    return pd.concat(frames, ignore_index=True)[PROFILE_COLUMNS]


def solutions_from_table(table):
    """The kept profiles as solutions that read the skin between nodes as the element does.

    Parameters
    ----------
    table : pandas.DataFrame
        As :func:`solve_world_profiles` gives it.

    Returns
    -------
    dict
        ``(species, section, modulus_ratio, depth_mm) ->``
        :class:`lineload.elastic.solver.ContactSolution` (its ``deflection_at_mm`` is the
        quadratic element's own trace).
    """
    solutions = {}
    keys = ["species", "section", "modulus_ratio", "depth_mm"]
    for key, rows in table.sort_values([*keys, "node"]).groupby(keys, sort=False):
        solutions[(str(key[0]), int(key[1]), float(key[2]), float(key[3]))] = (
            solver.ContactSolution(
                distance_mm=rows["distance_mm"].to_numpy(float),
                deflection_mm=rows["deflection_mm"].to_numpy(float),
                force_per_length_N_per_mm=float(rows["force_per_length_N_per_mm"].iloc[0]),
                contact_half_width_mm=float(rows["contact_half_width_mm"].iloc[0]),
                passes=0,
                elements=0,
            )
        )
    return solutions


def world_fingers(ratio, sections_per_species=SECTIONS_PER_SPECIES):
    """The subjects of one world's datasets: every section of both species at ``ratio``."""
    return [
        WorldFinger(f"{SPECIES_PREFIX[species]}{number + 1}", species, number, float(ratio))
        for species in ("monkey", "human")
        for number in range(sections_per_species)
    ]


def read_dataset(solutions, fingers, depths_mm, rng, noise=TRUE_NOISE):
    """Read every finger at every depth as a lab reads a print, and the same without errors.

    Each side is read on the reading grid out to :data:`READ_REACH_MM` (first reading at
    0.05 mm with probability :data:`lineload.simulation.readings.P_FIRST_AT_FINEST`, else
    0.1 mm), with the trial's shared errors (registration offset and rotation, shared tilt,
    depth error, misplaced wedge) and the side's own (reading, tracing, side offset; the
    fit measures the first two and states the last in the shared-offset prior) at
    ``noise``'s sizes, applied by :func:`lineload.simulation.errors.read_side_mm` and
    rounded to the enlargement's resolution. The error-free reading is the true profile on
    the same grid, not rounded.

    Parameters
    ----------
    solutions : dict
        As :func:`solutions_from_table` gives them.
    fingers : sequence of WorldFinger
    depths_mm : sequence of float
    rng : numpy.random.Generator
    noise : NoiseModel, optional

    Returns
    -------
    tuple of list
        ``(read, true)``: per finger, ``(subject, species, profile table)`` with the
        columns ``depth_mm``, ``side``, ``distance_image_mm``, ``deflection_image_mm``.
    """
    read, true = [], []
    for finger in fingers:
        columns = {
            kind: {"depth_mm": [], "side": [], "x": [], "w": []} for kind in ("read", "true")
        }
        for depth_mm in depths_mm:
            solution = solutions[(finger.species, finger.section, finger.modulus_ratio, depth_mm)]
            errors = TrialErrors(
                offset_mm=rng.normal(0.0, noise.shared_offset_sd_mm),
                rotation=rng.normal(0.0, noise.rotation_sd),
                shared_tilt=rng.normal(0.0, noise.shared_tilt_sd),
                depth_error_mm=rng.normal(0.0, noise.depth_sd_mm),
                wedge_shift_mm=rng.normal(0.0, noise.wedge_position_sd_mm),
            )
            for side in ("left", "right"):
                first_mm = GRID_TICK_MM if rng.random() < P_FIRST_AT_FINEST else 2 * GRID_TICK_MM
                distance_mm = reading_distances_mm(READ_REACH_MM[finger.species], first_mm)
                side_errors_mm = draw_side_errors_mm(rng, distance_mm, noise)
                made = {
                    "read": read_side_mm(
                        solution.deflection_at_mm,
                        distance_mm,
                        side,
                        depth_mm,
                        errors,
                        side_errors_mm,
                    ),
                    "true": solution.deflection_at_mm(distance_mm),
                }
                for kind, w_mm in made.items():
                    columns[kind]["depth_mm"].append(np.full(distance_mm.size, float(depth_mm)))
                    columns[kind]["side"].append(np.full(distance_mm.size, side, dtype=object))
                    columns[kind]["x"].append(image_mm(distance_mm, MAGNIFICATION))
                    columns[kind]["w"].append(
                        image_mm(w_mm, MAGNIFICATION) if kind == "read" else w_mm * MAGNIFICATION
                    )
        for kind, out in (("read", read), ("true", true)):
            table = pd.DataFrame(
                {
                    "depth_mm": np.concatenate(columns[kind]["depth_mm"]),
                    "side": np.concatenate(columns[kind]["side"]),
                    "distance_image_mm": np.concatenate(columns[kind]["x"]),
                    "deflection_image_mm": np.concatenate(columns[kind]["w"]),
                }
            )
            out.append((finger.subject, finger.species, table))
    return read, true


def analyse_dataset(tables, window_mm, priors, max_trials, blocks, errors=True):
    """A dataset analysed as the workflow does, in memory: averaged, noise, fits, claims' input.

    Parameters
    ----------
    tables : list of (str, str, pandas.DataFrame)
        ``(subject, species, profile table in image mm)`` per finger.
    window_mm : float
        Fit window (config ``fit_window_mm``).
    priors : dict
        The noise priors (config ``noise`` without ``max_trials``).
    max_trials : int
    blocks : dict
        The elastic library (:func:`lineload.fitting.elastic.library_blocks`).
    errors : bool, optional
        False: the error-free readings, fitted with the generator's noise shrunk by
        :data:`lineload.simulation.analysis.TRUTH_SCALE` (nothing measured).

    Returns
    -------
    tuple
        ``(fits, averaged, noise, trial_noise)``: the fit table with the elastic fits'
        columns, the averaged columns, the dataset's noise model and each trial's.
    """
    converted = [tissue_columns(table, subject, MAGNIFICATION) for subject, _, table in tables]
    species_of = {name: species for name, species, _ in tables}
    analysis = analyse(converted, species_of, window_mm, priors, max_trials, errors)
    elastic = fit_elastic_trials(
        analysis.per_trial("distance_mm"),
        analysis.per_trial("deflection_mm"),
        [species_of[name] for name, _, _ in analysis.trials],
        analysis.depths_mm,
        window_mm,
        blocks,
        noise=analysis.trial_noise,
        n_sides=analysis.per_trial("n_sides"),
    )
    fits = with_elastic(analysis.fits, analysis.labelled(elastic))
    return fits, analysis.averaged, analysis.noise, analysis.trial_noise


def _judged(fits, averaged, noise, trial_noise, claims, errors):
    table = judged_claims(fits, averaged, noise, trial_noise, claims, errors)
    return table[~table["claim"].isin(NOT_JUDGED)].reset_index(drop=True)


def world_dataset(
    solutions,
    ratio,
    seed,
    window_mm,
    priors,
    max_trials,
    blocks,
    claims=None,
    depths_mm=None,
    prior_ratio=1.0,
):
    """One dataset of a world (every section of both species at ``ratio``) read, analysed and
    scored against its error-free readings.

    Parameters
    ----------
    solutions : dict
        As :func:`solutions_from_table` gives them.
    ratio : float
        The fingers' modulus ratio.
    seed : int or tuple of int
        Seed of the dataset's errors.
    window_mm, priors, max_trials, blocks
        As for :func:`analyse_dataset`.
    claims : dict, optional
        Settings of the claims (config ``claims``).
    depths_mm : sequence of float, optional
        The depths read; the solutions' if None.
    prior_ratio : float, optional
        The errors the left-right differences cannot measure (:data:`lineload.noise.PRIORS`)
        are made at this multiple of their stated sizes, the same draws scaled; the analysis
        states them at ``priors`` all the same (a world where the stated priors are wrong).

    Returns
    -------
    dict
        ``coverage``, ``verdicts`` and ``ratio``: lists of rows (columns
        :data:`COVERAGE_COLUMNS`, :data:`VERDICT_COLUMNS` and :data:`RATIO_COLUMNS`, without
        ``world`` and ``dataset``).
    """
    if depths_mm is None:
        depths_mm = sorted({key[3] for key in solutions})
    sections = sorted({key[1] for key in solutions})
    fingers = world_fingers(ratio, len(sections))
    made = TRUE_NOISE.scaled_priors(prior_ratio)
    read, true = read_dataset(solutions, fingers, depths_mm, np.random.default_rng(seed), made)
    fits, averaged, noise, trial_noise = analyse_dataset(
        read, window_mm, priors, max_trials, blocks
    )
    true_fits, true_averaged, true_noise, true_trial_noise = analyse_dataset(
        true, window_mm, priors, max_trials, blocks, errors=False
    )
    coverage, ratio_rows = [], []
    for (_, trial), (_, truth_row) in zip(fits.iterrows(), true_fits.iterrows(), strict=True):
        common = {
            "subject": trial["subject"],
            "species": trial["species"],
            "depth_mm": float(trial["depth_mm"]),
        }
        for model, names in CHECKED.items():
            for name in names:
                stem = f"{model}_{name[: -len('_mm')]}"
                low, high = float(trial[f"{stem}_ci_low_mm"]), float(trial[f"{stem}_ci_high_mm"])
                bound = f"{stem}_at_bound"
                value = float(truth_row[f"{model}_{name}"])
                coverage.append(
                    {
                        **common,
                        "model": model,
                        "parameter": name,
                        "true": value,
                        "true_at_bound": bool(truth_row.get(bound, False)),
                        "estimate": float(trial[f"{model}_{name}"]),
                        "low": low,
                        "high": high,
                        "covered": bool(low <= value <= high),
                    }
                )
        low = float(trial["elastic_layered_ratio_ci_low"])
        high = float(trial["elastic_layered_ratio_ci_high"])
        aimed = float(truth_row["elastic_layered_modulus_ratio"])
        ratio_rows.append(
            {
                **common,
                "true_ratio": float(ratio),
                "error_free_ratio": aimed,
                "ratio": float(trial["elastic_layered_modulus_ratio"]),
                "low": low,
                "high": high,
                "covered": bool(low <= ratio <= high),
                "covers_error_free": bool(low <= aimed <= high),
                "excludes_1": bool(low > 1.0),
                "at_end": bool(trial["elastic_layered_ratio_ci_at_bound"]),
            }
        )
    judged = _judged(fits, averaged, noise, trial_noise, claims, True)
    truth = _judged(true_fits, true_averaged, true_noise, true_trial_noise, claims, False)
    verdicts = []
    for claim, verdict, rule_truth in zip(
        judged["claim"], judged["verdict"], truth["verdict"], strict=True
    ):
        # C12's truth is the finger's own; every other claim's the rules' on error-free data
        right = (HOLDS if ratio > 1 else FAILS) if claim == "C12" else rule_truth
        verdicts.append(
            {
                "claim": claim,
                "truth": right,
                "verdict": verdict,
                "wrong": verdict == _OPPOSITE.get(right),
            }
        )
    return {"coverage": coverage, "verdicts": verdicts, "ratio": ratio_rows}


def world_study(
    solutions,
    seed,
    datasets,
    window_mm,
    priors,
    max_trials,
    blocks,
    claims=None,
    ratios=None,
    prior_ratio=1.0,
):
    """Every world (one per ratio) with ``datasets`` datasets each.

    Dataset ``k`` of world ``i`` (the ``i``-th of ``ratios``) is seeded by ``(seed, i, k)``:
    any slice reruns alone with the same numbers, and a ``prior_ratio`` other than 1 makes
    the same draws with the unmeasurable errors scaled (:func:`world_dataset`).

    Returns
    -------
    dict
        ``coverage``, ``verdicts`` and ``ratio``: lists of rows with the columns
        :data:`COVERAGE_COLUMNS`, :data:`VERDICT_COLUMNS` and :data:`RATIO_COLUMNS`; the
        world is named by its ratio and the errors (:func:`world_name`).
    """
    if ratios is None:
        ratios = sorted({key[2] for key in solutions})
    out = {"coverage": [], "verdicts": [], "ratio": []}
    for i, ratio in enumerate(ratios):
        world = world_name(ratio, prior_ratio)
        for k in range(datasets):
            scored = world_dataset(
                solutions,
                ratio,
                (seed, i, k),
                window_mm,
                priors,
                max_trials,
                blocks,
                claims,
                prior_ratio=prior_ratio,
            )
            for part, rows in scored.items():
                out[part] += [{"world": world, "dataset": k, **row} for row in rows]
    return out


def world_name(ratio, prior_ratio=1.0):
    """A world's name: ``homogeneous`` at ratio 1, else ``layered, ratio r``; with
    ``, shared errors Nx`` where the unmeasurable errors are made at N times their stated
    sizes."""
    name = "homogeneous" if ratio == 1 else f"layered, ratio {ratio:g}"
    return name if prior_ratio == 1 else f"{name}, shared errors {prior_ratio:g}x"


def _interval_columns(k, n):
    low, high = binomial_interval(k, n)
    return {"n": n, "k": k, "rate": k / n if n else np.nan, "ci_low": low, "ci_high": high}


def summarise_world_coverage(rows):
    """Coverage by world, model, parameter and species (then all species), with
    Clopper-Pearson intervals: over every trial, and over the trials whose truth is not on
    the fit's search bound (where the truth is the bound, e.g. a waterbed ``L`` held at the
    window's edge, an interval that reaches the bound covers it by construction); with the
    median truth and the median of the estimate over the truth."""
    frame = pd.DataFrame(rows)
    summary = []
    keys = ["world", "model", "parameter"]
    for key, group in frame.groupby(keys, sort=False):
        for species, part in [("all", group), *group.groupby("species", sort=False)]:
            interior = part[~part["true_at_bound"].astype(bool)]
            free = _interval_columns(int(interior["covered"].sum()), len(interior))
            summary.append(
                {
                    **dict(zip(keys, key, strict=True)),
                    "species": species,
                    **_interval_columns(int(part["covered"].sum()), len(part)),
                    "n_true_at_bound": len(part) - len(interior),
                    **{f"{name}_interior": value for name, value in free.items()},
                    "median_true": float(np.median(part["true"])),
                    "median_estimate_over_true": float(np.median(part["estimate"] / part["true"])),
                }
            )
    return summary


def summarise_world_verdicts(rows):
    """:func:`lineload.simulation.verdicts.summarise_verdicts` per world, the world first."""
    frame = pd.DataFrame(rows)
    summary = []
    for world, group in frame.groupby("world", sort=False):
        for row in summarise_verdicts(group.to_dict("records")):
            summary.append({"world": world, **row})
    return summary


def summarise_ratio(rows):
    """The layered fit's ratio per world and species: its interval's coverage of the true
    ratio and how often it excludes 1, with Clopper-Pearson intervals, and the median fitted
    ratio."""
    frame = pd.DataFrame(rows)
    summary = []
    for world, group in frame.groupby("world", sort=False):
        for species, part in [("all", group), *group.groupby("species", sort=False)]:
            covered = _interval_columns(int(part["covered"].sum()), len(part))
            aimed = _interval_columns(int(part["covers_error_free"].sum()), len(part))
            excludes = _interval_columns(int(part["excludes_1"].sum()), len(part))
            summary.append(
                {
                    "world": world,
                    "species": species,
                    "true_ratio": float(part["true_ratio"].iloc[0]),
                    "n_trials": covered["n"],
                    "n_covered": covered["k"],
                    "coverage": covered["rate"],
                    "coverage_ci_low": covered["ci_low"],
                    "coverage_ci_high": covered["ci_high"],
                    "n_covers_error_free": aimed["k"],
                    "covers_error_free_rate": aimed["rate"],
                    "covers_error_free_ci_low": aimed["ci_low"],
                    "covers_error_free_ci_high": aimed["ci_high"],
                    "median_error_free_ratio": float(np.nanmedian(part["error_free_ratio"])),
                    "n_excludes_1": excludes["k"],
                    "excludes_1_rate": excludes["rate"],
                    "excludes_1_ci_low": excludes["ci_low"],
                    "excludes_1_ci_high": excludes["ci_high"],
                    "median_ratio": float(np.nanmedian(part["ratio"])),
                    "n_at_end": int(part["at_end"].sum()),
                }
            )
    return summary
