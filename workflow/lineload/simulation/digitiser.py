"""The digitiser's own calibration: its stated uncertainties against rendered truth.

A photographed trial's readings come with three uncertainties that the fits take at
their word (:mod:`lineload.rawdata.photographs`): each reading's own SD (the two
outlines' edge errors averaged over its columns), the registration's SD (an offset
shared by every reading of the trial) and, through both, each reading's total SD; and,
where the wedge is seen against the background, the standard error of its apex (from
the scatter of its faces' points about their lines; the noise model's
``wedge_position_sd_mm`` stays a prior, which the tip's measured error here is set
against).

Each pair is rendered (:func:`lineload.simulation.photograph_render.render_photograph`) from a
finger whose resting outline is a circle and whose loaded outline is that circle
lowered by a known deflection, each side its own, with a known shift between the two
shots; scale, field of view, blur, sensor noise, lighting, texture, glare, levels and
depth are drawn for every pair from ranges wider than the photograph example's.  The
digitiser reads the pair as the workflow does (:func:`digitise_pair`), and every stated
SD is set against the error the truth shows:

* registration: the vertical offset found against the shift the pair was rendered with;
* a reading's own error: the reading against the true deflection at the distance from
  the *true* tip of the columns it averaged, less the registration's error (so the tip's
  error, a separate term of the noise model, is not charged to the reading);
* a reading's total error: the same with the registration's error kept;
* the tip: the tip placed against the true one (pixels and um);
* the apex's stated SD: the apex seen against the true tip, as a z-score (error over
  stated SD), where an apex was seen.

A stated SD ``s`` covers an error ``e`` when ``|e| <= 1.96 s`` (nominal 95 %).
``docs/calibration/scripts/digitiser.py`` runs :func:`digitiser_calibration` and writes
``docs/calibration/digitiser.md`` and ``.csv``; ``tests/test_digitiser_calibration.py``
runs it on fewer pairs, and shows that SDs made too small fail.
"""

from __future__ import annotations

import itertools

import numpy as np

from lineload.rawdata.readings import reading_distances_mm
from lineload.simulation.subjects import true_deflection_mm

__all__ = [
    "COVERAGE_Z",
    "DISTANCE_BANDS_MM",
    "PAIR_COLUMNS",
    "coverage_summary",
    "digitiser_calibration",
    "rendered_pair",
]

#: The normal quantile of a two-sided 95 % interval.
COVERAGE_Z = 1.959963984540054
#: Distance bands (mm from the tip) over which the readings' coverage is also given.
DISTANCE_BANDS_MM = (0.0, 0.5, 1.0, 3.0, np.inf)
#: Columns of the calibration's per-pair table.
PAIR_COLUMNS = [
    "seed",
    "pixels_per_mm",
    "depth_mm",
    "blur_px",
    "noise_sd",
    "lighting_gradient",
    "texture_sd",
    "glare",
    "bits",
    "read",
    "tip_error_px",
    "tip_error_um",
    "apex_error_px",
    "apex_sd_px",
    "registration_error_um",
    "registration_sd_um",
    "readings",
    "own_rms_error_um",
    "own_median_sd_um",
    "own_covered",
    "total_covered",
]


def _scene_and_camera(rng):
    """A field of view and a camera drawn for one pair (ranges in the module's text)."""
    from lineload.simulation.photograph_render import Camera

    camera = Camera(
        blur_px=rng.uniform(0.7, 2.5),
        noise_sd=rng.uniform(0.005, 0.04),
        lighting_gradient=rng.uniform(0.0, 0.4),
        texture_sd=rng.uniform(0.01, 0.05),
        texture_px=rng.uniform(2.0, 5.0),
        glare=rng.uniform(0.0, 0.35),
        glare_mm=rng.uniform(0.15, 0.4),
        bits=int(rng.choice([8, 16])),
    )
    return rng.uniform(45.0, 100.0), camera


def rendered_pair(seed):
    """One rendered pair and its truth.

    Parameters
    ----------
    seed : int
        Everything about the pair is drawn from ``numpy.random.default_rng([2611, seed])``.

    Returns
    -------
    dict
        ``rest``, ``loaded`` (images), ``scene``, ``camera``, ``depth_mm``, ``reach_mm``,
        ``grid_mm`` (the distances read), ``shift_mm`` (true dx, dz), ``tip_x_mm`` (true)
        ``deflection`` (side -> callable of the distance from the true tip, mm) and
        ``outlines_mm`` (the true resting and loaded outlines, callables of x).
    """
    from lineload.rawdata.photographs import Scene
    from lineload.simulation.photograph_render import render_photograph

    rng = np.random.default_rng([2611, seed])
    ppmm, camera = _scene_and_camera(rng)
    depth = rng.uniform(0.5, 2.0)
    extents = rng.uniform(3.5, 6.5) * rng.uniform(0.9, 1.1, size=2)
    exponent = rng.uniform(1.8, 2.6)
    near = rng.uniform(0.0, 0.3)
    sx, sz = rng.uniform(-0.05, 0.05, size=2)
    reach = float(extents.max()) + 0.3
    half_width = reach + rng.uniform(1.5, 2.5)
    # the resting finger: a circle wider than the view (its side at most 45 deg)
    radius = max(rng.uniform(8.0, 20.0), 1.5 * half_width)
    height = rng.uniform(3.5, 5.0)
    scene = Scene(
        ppmm,
        -half_width,
        rng.uniform(0.4, 0.8),
        round(2 * half_width * ppmm),
        round(height * ppmm),
    )
    deflection = {
        side: (lambda d, e=e: true_deflection_mm(d, depth, e, exponent, near))
        for side, e in zip(("left", "right"), extents, strict=True)
    }

    def rest(x):
        return -(radius - np.sqrt(radius**2 - np.asarray(x) ** 2))

    def loaded(x):
        xs = np.asarray(x) - sx
        w = np.where(xs < 0, deflection["left"](np.abs(xs)), deflection["right"](np.abs(xs)))
        return rest(xs) - w + sz

    tip = (float(sx), float(loaded(sx)))
    return {
        "rest": render_photograph(rest, scene, camera, rng),
        "loaded": render_photograph(loaded, scene, camera, rng, wedge_tip_mm=tip),
        "scene": scene,
        "camera": camera,
        "depth_mm": float(depth),
        "reach_mm": reach,
        "grid_mm": reading_distances_mm(float(extents.max()), 0.05),
        "shift_mm": (float(sx), float(sz)),
        "tip_x_mm": tip[0],
        "deflection": deflection,
        "outlines_mm": (rest, loaded),
    }


def _pair_errors(seed, settings):
    """Digitise one rendered pair: its row of the per-pair table, and each reading's
    ``(distance_mm, own_error, own_sd, total_error, total_sd)`` (mm)."""
    from lineload.rawdata.photographs import ImageError, digitise_pair

    pair = rendered_pair(seed)
    camera = pair["camera"]
    row = {
        "seed": seed,
        "pixels_per_mm": round(pair["scene"].pixels_per_mm, 3),
        "depth_mm": round(pair["depth_mm"], 4),
        "blur_px": round(camera.blur_px, 3),
        "noise_sd": round(camera.noise_sd, 4),
        "lighting_gradient": round(camera.lighting_gradient, 3),
        "texture_sd": round(camera.texture_sd, 4),
        "glare": round(camera.glare, 3),
        "bits": camera.bits,
    }
    try:
        trial = digitise_pair(
            pair["rest"],
            pair["loaded"],
            pair["scene"],
            pair["grid_mm"],
            reach_mm=pair["reach_mm"],
            smoothing_px=settings["smoothing_px"],
            window_mm=settings["window_mm"],
        )
    except ImageError:
        return {**row, "read": False}, np.empty((0, 5))
    pixel_mm = 1.0 / pair["scene"].pixels_per_mm
    tip_error = trial.tip_x_mm - pair["tip_x_mm"]
    registration_error = trial.shift_mm[1] - pair["shift_mm"][1]
    rows = []
    for side, sign in (("left", -1.0), ("right", 1.0)):
        distance, deflection = trial.readings[side]
        truth = pair["deflection"][side](distance + sign * tip_error)
        own_error = deflection - truth - registration_error
        own_sd = trial.reading_sds_mm[side]
        total_sd = np.hypot(own_sd, trial.registration_sd_mm)
        rows.append(np.column_stack([distance, own_error, own_sd, deflection - truth, total_sd]))
    readings = np.concatenate(rows)
    covered = np.abs(readings[:, [1, 3]]) <= COVERAGE_Z * readings[:, [2, 4]]
    row.update(
        {
            "read": True,
            "tip_error_px": round(tip_error / pixel_mm, 4),
            "tip_error_um": round(1000 * tip_error, 4),
            "apex_error_px": None
            if trial.apex_x_mm is None
            else round((trial.apex_x_mm - pair["tip_x_mm"]) / pixel_mm, 4),
            "apex_sd_px": None if trial.tip_sd_mm is None else round(trial.tip_sd_mm / pixel_mm, 4),
            "registration_error_um": round(1000 * registration_error, 4),
            "registration_sd_um": round(1000 * trial.registration_sd_mm, 4),
            "readings": len(readings),
            "own_rms_error_um": round(1000 * float(np.sqrt(np.mean(readings[:, 1] ** 2))), 4),
            "own_median_sd_um": round(1000 * float(np.median(readings[:, 2])), 4),
            "own_covered": int(covered[:, 0].sum()),
            "total_covered": int(covered[:, 1].sum()),
        }
    )
    return row, readings


def digitiser_calibration(n_pairs, settings, first_seed=0):
    """Render and digitise ``n_pairs`` pairs; every stated SD against its error.

    Parameters
    ----------
    n_pairs : int
        How many pairs (seeds ``first_seed`` ...).
    settings : dict
        The config's ``digitise`` settings (``smoothing_px``, ``window_mm``).
    first_seed : int, optional

    Returns
    -------
    tuple
        ``(pairs, readings)``: a list of per-pair rows (:data:`PAIR_COLUMNS`), and an
        ``(n, 5)`` array of every reading's distance, own error, own SD, total error
        and total SD (mm).
    """
    pairs, readings = [], []
    for seed in range(first_seed, first_seed + n_pairs):
        row, values = _pair_errors(seed, settings)
        pairs.append(row)
        readings.append(values)
    return pairs, np.concatenate(readings)


def coverage_summary(pairs, readings, multiple=1.0):
    """How often the stated SDs, times ``multiple``, cover the errors.

    Parameters
    ----------
    pairs, readings
        As :func:`digitiser_calibration` returns them.
    multiple : float, optional
        Every stated SD times this (1: as stated; below 1: too small, which the
        coverage must show).

    Returns
    -------
    dict
        ``pairs``, ``read``; ``registration``, ``own``, ``total`` coverage (fractions);
        ``own_by_band`` (band label -> coverage, count); the tip's and the
        registration's error in numbers (``tip_rms_px``, ``tip_p95_px``, ``tip_rms_um``,
        ``tip_p95_um``,
        ``registration_bias_um``, ``registration_rms_um``, ``registration_sd_median_um``);
        the apex's stated SD against its error where an apex was seen: ``apex_seen``,
        ``apex_covered`` (count), ``apex`` (coverage), ``apex_ci`` (Clopper-Pearson 95 %
        interval of it), ``apex_z_sd`` (SD of error over stated SD; 1 when the SD is
        right) and ``apex_sd_median_px``.
    """
    from scipy.stats import binomtest

    done = [p for p in pairs if p.get("read")]
    reg_error = np.array([p["registration_error_um"] for p in done])
    reg_sd = multiple * np.array([p["registration_sd_um"] for p in done])
    tip = np.array([p["tip_error_px"] for p in done])
    tip_um = np.array([p["tip_error_um"] for p in done])
    seen = [p for p in done if p.get("apex_sd_px") not in (None, "")]
    apex_z = np.array([p["apex_error_px"] / (multiple * p["apex_sd_px"]) for p in seen])
    apex_covered = int(np.sum(np.abs(apex_z) <= COVERAGE_Z))
    apex_ci = (
        binomtest(apex_covered, len(seen)).proportion_ci(0.95, method="exact") if seen else None
    )
    distance, own_e, own_s, total_e, total_s = readings.T
    own = np.abs(own_e) <= COVERAGE_Z * multiple * own_s
    bands = {}
    for lo, hi in itertools.pairwise(DISTANCE_BANDS_MM):
        inside = (distance > lo) & (distance <= hi)
        label = f"{lo:g}-{hi:g} mm" if np.isfinite(hi) else f"beyond {lo:g} mm"
        bands[label] = (
            float(own[inside].mean()) if inside.any() else float("nan"),
            int(inside.sum()),
        )
    return {
        "pairs": len(pairs),
        "read": len(done),
        "readings": int(distance.size),
        "registration": float(np.mean(np.abs(reg_error) <= COVERAGE_Z * reg_sd)),
        "own": float(own.mean()),
        "total": float(np.mean(np.abs(total_e) <= COVERAGE_Z * multiple * total_s)),
        "own_by_band": bands,
        "tip_rms_px": float(np.sqrt(np.mean(tip**2))),
        "tip_p95_px": float(np.quantile(np.abs(tip), 0.95)),
        "tip_rms_um": float(np.sqrt(np.mean(tip_um**2))),
        "tip_p95_um": float(np.quantile(np.abs(tip_um), 0.95)),
        "registration_bias_um": float(np.mean(reg_error)),
        "registration_rms_um": float(np.sqrt(np.mean(reg_error**2))),
        "registration_sd_median_um": float(np.median(reg_sd)),
        "own_rms_um": float(1000 * np.sqrt(np.mean(own_e**2))),
        "apex_seen": len(seen),
        "apex_covered": apex_covered,
        "apex": apex_covered / len(seen) if seen else float("nan"),
        "apex_ci": (apex_ci.low, apex_ci.high) if seen else (float("nan"), float("nan")),
        "apex_z_sd": float(np.std(apex_z, ddof=1)) if len(seen) > 1 else float("nan"),
        "apex_sd_median_px": float(np.median([multiple * p["apex_sd_px"] for p in seen]))
        if seen
        else float("nan"),
        "own_sd_rms_um": float(1000 * multiple * np.sqrt(np.mean(own_s**2))),
    }
