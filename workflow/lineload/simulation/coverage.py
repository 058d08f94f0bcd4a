"""Do the intervals cover?  Simulated datasets with digitising errors, fitted as the workflow fits.

Each simulated dataset has the shipped design (the subjects and depths of
:func:`lineload.simulation.subjects.shipped_subjects`).  Every trial's true profile comes
from one model - the paper's parabola (eq. 19), the exact arc, or the modified
Boussinesq form - with parameters drawn in the paper's ranges, and is read on
the shipped reading grid with every error of :mod:`lineload.noise`: independent
and correlated reading errors and an offset per side, a rotation, a shared offset
and tilt, a depth error and a misplaced wedge, rounded as the enlargement rounds.
The workflow's own steps follow: the noise is measured from the dataset's
left-right differences (the priors at their true sizes, the shared offset's stated
as the mean's whole constant error, side offsets included:
:meth:`lineload.noise.NoiseModel.as_stated`), and the same model is
fitted by generalised least squares.  An interval covers when it holds the
parameter the data were made with.

Two kinds of noise the estimator does not assume test its robustness: tracing
errors with a squared-exponential correlation, and reading errors from a
Student t with three degrees of freedom.

The rest of the scenarios make the calibration able to catch its own
assumptions: worlds where the stated priors are wrong while the fits keep them.
The errors the left-right differences cannot measure (:data:`lineload.noise.PRIORS`:
the shared offset and tilt, the depth error, the misplaced wedge) are made at 0.5,
2 and 3 times their stated sizes, and the depth error alone at 30 um; a resting
curvature error that is the same on both sides (so the differences cannot see it
either) is made although the noise model has no room for it; and 5 % of the
readings are misread by 6 reading SDs.  In every one the fit states the priors at
their stated sizes (:data:`lineload.simulation.errors.TRUE_NOISE`), as a lab whose
priors are wrong would: the scenario changes only what the forward error model
(:func:`lineload.simulation.errors.read_side_mm`) makes.
"""

from __future__ import annotations

import math

import numpy as np

from lineload.fitting.batch import fit_windowed
from lineload.models import arc_deflection_mm, boussinesq_deflection_mm, waterbed_deflection_mm
from lineload.noise import (
    PRIORS,
    draw_side_errors_mm,
    estimate_noise,
    trial_differences,
)
from lineload.rawdata.readings import reading_distances_mm
from lineload.simulation.errors import (
    AS_ASSUMED,
    IMAGE_RESOLUTION_MM,
    MISREAD_FRACTION,
    MISREAD_SDS,
    RESTING_CURVATURE_SD_PER_MM,
    TRUE_NOISE,
    Scenario,
    TrialErrors,
    draw_misreads_mm,
    read_side_mm,
)
from lineload.simulation.rates import binomial_interval
from lineload.simulation.subjects import MAGNIFICATION, shipped_subjects

__all__ = [
    "COVERAGE_COLUMNS",
    "COVERAGE_STUDY_COLUMNS",
    "PRIOR_RATIOS",
    "SCENARIOS",
    "SCENARIO_COLUMNS",
    "TRIAL_COLUMNS",
    "TRUE_NOISE",
    "Scenario",
    "bootstrap_study",
    "coverage_rows",
    "coverage_study",
    "described",
    "simulate_dataset",
    "summarise_coverage",
]

#: Span of L drawn for the membrane models (mm): the paper's 10-15 mm (claim C5).
L_RANGE_MM = (10.0, 15.0)
#: Zero crossing x0 of the Boussinesq form (mm), beyond the 3 mm window.
X0_RANGE_MM = (4.0, 8.0)
#: Nearest distance to the wedge at which the Boussinesq form is evaluated (mm): its
#: logarithm is infinite at the tip, where a misplaced wedge's reading can land
#: (:data:`lineload.simulation.errors.SEEN_FLOOR_MM`).
BOUSSINESQ_FLOOR_MM = 1e-3
#: Resolution of a reading in tissue mm (0.1 mm on a 20x enlargement).
RESOLUTION_MM = IMAGE_RESOLUTION_MM / MAGNIFICATION

#: The parameters whose intervals are checked, per model.
CHECKED = {
    "waterbed": ("L_mm",),
    "arc": ("L_mm",),
    "boussinesq": ("A_mm", "x0_mm"),
}

TRIAL_COLUMNS = [
    "scenario",
    "model",
    "dataset",
    "parameter",
    "species",
    "depth_mm",
    "true",
    "low",
    "high",
    "covered",
]

COVERAGE_COLUMNS = [
    "scenario",
    "model",
    "parameter",
    "species",
    "depth_mm",
    "n_trials",
    "n_covered",
    "coverage",
    "ci_low",
    "ci_high",
]


#: Columns the coverage study's summary adds after ``scenario``: what the scenario
#: makes differently from what the fit states, and the ratio of the true to the stated
#: size of every prior (1 where the priors are as stated).
SCENARIO_COLUMNS = ["misspecified", "prior_ratio"]
#: Columns of the coverage study's summary (``docs/calibration/coverage.csv``).
COVERAGE_STUDY_COLUMNS = [COVERAGE_COLUMNS[0], *SCENARIO_COLUMNS, *COVERAGE_COLUMNS[1:]]

#: True over stated size of every prior in the misspecified-priors scenarios.
PRIOR_RATIOS = (0.5, 2.0, 3.0)


SCENARIOS = (
    AS_ASSUMED,
    Scenario(
        "squared-exponential tracing",
        kernel="squared_exponential",
        misspecified="tracing correlation",
    ),
    Scenario("heavy-tailed readings (t, 3 df)", df=3.0, misspecified="reading tails"),
    # appended after the first three, so their seeds (seed, i, j, k) are unchanged
    *(
        Scenario(
            f"shared errors {ratio:g}x their stated sizes",
            misspecified="shared errors' sizes",
            prior_ratio=ratio,
        )
        for ratio in PRIOR_RATIOS
    ),
    Scenario(
        "depth error 30 um (stated 10 um)",
        misspecified="depth error 3x",
        true_sizes=(("depth_sd_mm", 0.03),),
    ),
    Scenario(
        "resting curvature (both sides alike)",
        misspecified="resting curvature",
        curvature_sd_per_mm=RESTING_CURVATURE_SD_PER_MM,
    ),
    Scenario(
        f"misreads ({100 * MISREAD_FRACTION:g} % at {MISREAD_SDS:g} SD)",
        misspecified="misreads",
        misread_fraction=MISREAD_FRACTION,
    ),
)


def _true_profile(model, distance_mm, depth_mm, params):
    if model == "waterbed":
        return waterbed_deflection_mm(distance_mm, depth_mm, params["L_mm"])
    if model == "arc":
        return arc_deflection_mm(distance_mm, depth_mm, params["L_mm"])
    if model == "boussinesq":
        # the logarithm is infinite at the wedge's tip: evaluated 1 um from it at least
        near_mm = np.maximum(distance_mm, BOUSSINESQ_FLOOR_MM)
        return boussinesq_deflection_mm(near_mm, params["A_mm"], params["x0_mm"])
    raise ValueError(f"unknown model {model!r}")


def _draw_params(rng, model, depth_mm, first_mm):
    if model in ("waterbed", "arc"):
        return {"L_mm": float(rng.uniform(*L_RANGE_MM))}
    x0_mm = float(rng.uniform(*X0_RANGE_MM))
    # the deflection at the first reading equals the depth
    return {"A_mm": depth_mm / math.log(x0_mm / first_mm), "x0_mm": x0_mm}


def _read_trial(rng, model, params, distance_mm, depth_mm, noise, scenario):
    """Both sides of one trial made by ``model`` and read with every digitising error
    (:func:`lineload.simulation.errors.read_side_mm`), rounded as the enlargement rounds."""
    rotation = rng.normal(0.0, noise.rotation_sd)
    wedge_mm = rng.normal(0.0, noise.wedge_position_sd_mm)
    depth_error_mm = rng.normal(0.0, noise.depth_sd_mm)
    offset_mm = rng.normal(0.0, noise.shared_offset_sd_mm)
    shared_tilt = rng.normal(0.0, noise.shared_tilt_sd)
    # drawn only where the scenario makes it: the other scenarios' streams stay as they were
    curvature = (
        rng.normal(0.0, scenario.curvature_sd_per_mm) if scenario.curvature_sd_per_mm else 0.0
    )
    errors = TrialErrors(offset_mm, rotation, shared_tilt, depth_error_mm, wedge_mm, curvature)
    sides = {}
    for side in ("left", "right"):
        side_errors_mm = draw_side_errors_mm(rng, distance_mm, noise, scenario.kernel, scenario.df)
        if scenario.misread_fraction:
            side_errors_mm = side_errors_mm + draw_misreads_mm(
                rng,
                len(distance_mm),
                scenario.misread_fraction,
                scenario.misread_sds * noise.reading_sd_mm,
            )
        read_mm = read_side_mm(
            lambda seen_mm: _true_profile(model, seen_mm, depth_mm, params),
            distance_mm,
            side,
            depth_mm,
            errors,
            side_errors_mm,
        )
        sides[side] = np.round(read_mm / RESOLUTION_MM) * RESOLUTION_MM
    return {
        "depth_mm": float(depth_mm),
        "params": params,
        "distance_mm": distance_mm,
        "left_mm": sides["left"],
        "right_mm": sides["right"],
        "mean_mm": 0.5 * (sides["left"] + sides["right"]),
    }


def simulate_dataset(model, seed, window_mm=3.0, scenario=SCENARIOS[0], noise=TRUE_NOISE):
    """One dataset of the shipped design, every trial made by ``model``.

    Parameters
    ----------
    model : {"waterbed", "arc", "boussinesq"}
    seed : int or sequence of int
        Seed of this dataset (``numpy.random.default_rng``).
    window_mm : float, optional
        Readings are made out to a little beyond the fit window.
    scenario : Scenario, optional
    noise : NoiseModel, optional
        The stated size of every error; the data are made with the scenario's true
        sizes (:meth:`Scenario.true_noise`).

    Returns
    -------
    list of dict
        One per trial: ``species``, ``depth_mm``, ``params`` (the truth),
        ``distance_mm``, ``left_mm``, ``right_mm`` and ``mean_mm``.
    """
    rng = np.random.default_rng(seed)
    distance_mm = reading_distances_mm(window_mm + 0.5)
    true_noise = scenario.true_noise(noise)
    trials = []
    for subject in shipped_subjects():
        for depth_mm in subject.depths_mm:
            params = _draw_params(rng, model, depth_mm, float(distance_mm[0]))
            trial = _read_trial(rng, model, params, distance_mm, depth_mm, true_noise, scenario)
            trials.append({"species": subject.species, **trial})
    return trials


def coverage_rows(model, seed, window_mm=3.0, scenario=SCENARIOS[0], noise=TRUE_NOISE):
    """Simulate one dataset, measure its noise, fit ``model``; one row per trial and parameter.

    The data are made with the scenario's true sizes; the fit states the priors at
    ``noise``'s (a scenario whose true sizes differ is a world where they are wrong).

    Returns
    -------
    list of dict
        ``scenario``, ``model``, ``parameter``, ``species``, ``depth_mm``,
        ``true``, ``low``, ``high`` and ``covered``.
    """
    trials = simulate_dataset(model, seed, window_mm, scenario, noise)
    return _covered(trials, model, window_mm, noise, scenario.name)


def _covered(trials, model, window_mm, noise, scenario_name):
    """Measure the trials' noise (priors at ``noise``'s, or at a trial's own ``noise``),
    fit ``model``, compare with the truth."""
    differences = [
        trial_differences(t["distance_mm"], t["left_mm"], t["right_mm"], window_mm) for t in trials
    ]
    measured = estimate_noise(differences).model
    # stated as a lab that knew the sizes would state them: the side offsets, which the
    # differences do not measure, in the shared-offset prior (NoiseModel.as_stated)
    per_trial = [
        measured.with_priors(**{p: getattr(t.get("noise", noise).as_stated(), p) for p in PRIORS})
        for t in trials
    ]
    fits = fit_windowed(
        [t["distance_mm"] for t in trials],
        [t["mean_mm"] for t in trials],
        [t["depth_mm"] for t in trials],
        window_mm,
        (model,),
        noise=per_trial,
    )[model]
    rows = []
    for i, trial in enumerate(trials):
        for name in CHECKED[model]:
            stem = name[: -len("_mm")]
            low = fits.params[f"{stem}_ci_low_mm"][i]
            high = fits.params[f"{stem}_ci_high_mm"][i]
            true = trial["params"][name]
            rows.append(
                {
                    "scenario": scenario_name,
                    "model": model,
                    "parameter": name,
                    "species": trial["species"],
                    "depth_mm": trial["depth_mm"],
                    "true": true,
                    "low": float(low),
                    "high": float(high),
                    "covered": bool(low <= true <= high),
                }
            )
    return rows


def bootstrap_study(fitted, seed, n_replicates, noise, window_mm=3.0, models=tuple(CHECKED)):
    """A parametric bootstrap of a dataset's own fits: do its intervals cover there?

    Each replicate makes every trial again from its fitted model (the data's
    fitted parameters, its own reading grid out to a little beyond the window),
    reads it with every error of the measured noise model, measures the noise
    again from the replicate's left-right differences and fits it as the
    workflow does.  An interval covers when it holds the fitted value the
    replicate was made from.  This checks the intervals at the data's own design
    and fitted parameters.  It is not the data's world: every replicate is made by
    the model it is fitted with, so the model is exactly right there, while on the
    data every model leaves a misfit larger than the noise; and the priors' errors
    are made at their stated sizes (the misspecified worlds of :data:`SCENARIOS` show
    what wrong sizes do).

    Parameters
    ----------
    fitted : list of dict
        One per trial: ``species``, ``depth_mm``, ``distance_mm`` (the trial's
        reading grid) and, per model of ``models``, its fitted parameters
        (``{"waterbed": {"L_mm": ...}, ...}``; a model whose parameters are not
        all finite is left out for that trial); optionally ``noise``, the
        trial's own NoiseModel (a photographed trial's registration error).
    seed : int
        Replicate ``k`` of model ``j`` is seeded by ``(seed, j, k)``.
    n_replicates : int
    noise : NoiseModel
        The measured noise with its priors (the noise table).
    window_mm : float, optional
    models : sequence of str, optional

    Returns
    -------
    list of dict
        Columns :data:`TRIAL_COLUMNS`, scenario ``parametric bootstrap``.
    """
    scenario = Scenario("parametric bootstrap")
    rows = []
    for j, model in enumerate(models):
        usable = [
            t for t in fitted if all(math.isfinite(t[model][name]) for name in CHECKED[model])
        ]
        for k in range(n_replicates):
            rng = np.random.default_rng((seed, j, k))
            trials = [
                {
                    "species": t["species"],
                    "noise": t.get("noise", noise),
                    **_read_trial(
                        rng,
                        model,
                        t[model],
                        t["distance_mm"],
                        t["depth_mm"],
                        t.get("noise", noise),
                        scenario,
                    ),
                }
                for t in usable
            ]
            for row in _covered(trials, model, window_mm, noise, scenario.name):
                rows.append({**row, "dataset": k})
    return rows


def summarise_coverage(rows):
    """Coverage by scenario, model and parameter; then by species and depth as well.

    Parameters
    ----------
    rows : iterable of dict
        As :func:`coverage_rows` gives them.

    Returns
    -------
    list of dict
        Columns :data:`COVERAGE_COLUMNS`; ``species`` and ``depth_mm`` are
        ``"all"`` in the pooled rows.
    """
    groups = {}
    for row in rows:
        for species, depth in (("all", "all"), (row["species"], row["depth_mm"])):
            key = (row["scenario"], row["model"], row["parameter"], species, depth)
            groups.setdefault(key, []).append(row["covered"])
    summary = []
    for (scenario, model, parameter, species, depth), covered in groups.items():
        n, k = len(covered), int(sum(covered))
        low, high = binomial_interval(k, n)
        summary.append(
            {
                "scenario": scenario,
                "model": model,
                "parameter": parameter,
                "species": species,
                "depth_mm": depth,
                "n_trials": n,
                "n_covered": k,
                "coverage": k / n,
                "ci_low": low,
                "ci_high": high,
            }
        )
    return summary


def described(summary, scenarios=SCENARIOS):
    """The coverage summary with :data:`SCENARIO_COLUMNS`: each row's scenario's
    ``misspecified`` and ``prior_ratio``.

    Raises
    ------
    KeyError
        If a row's scenario is not one of ``scenarios``.
    """
    by_name = {scenario.name: scenario for scenario in scenarios}
    return [
        {
            **row,
            "misspecified": by_name[row["scenario"]].misspecified,
            "prior_ratio": by_name[row["scenario"]].prior_ratio,
        }
        for row in summary
    ]


def coverage_study(
    seed, n_datasets, models=tuple(CHECKED), scenarios=SCENARIOS, window_mm=3.0, only=None
):
    """Every trial of ``n_datasets`` simulated datasets per scenario and model.

    Dataset ``k`` of scenario ``i`` and model ``j`` is seeded by
    ``(seed, i, j, k)``: any slice reruns alone with the same numbers.

    Parameters
    ----------
    seed, n_datasets : int
    models : sequence of str, optional
    scenarios : sequence of Scenario, optional
    window_mm : float, optional
    only : sequence of int, optional
        Run only these scenarios (their positions ``i`` in ``scenarios``, which seed
        them); all if None.

    Returns
    -------
    list of dict
        Columns :data:`TRIAL_COLUMNS`.
    """
    rows = []
    for i, scenario in enumerate(scenarios):
        if only is not None and i not in only:
            continue
        for j, model in enumerate(models):
            for k in range(n_datasets):
                for row in coverage_rows(model, (seed, i, j, k), window_mm, scenario):
                    rows.append({**row, "dataset": k})
    return rows
