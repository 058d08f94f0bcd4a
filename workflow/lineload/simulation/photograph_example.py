"""The photograph example: two fingers of the reconstruction photographed at rest and loaded.

Each trial is rendered from the same true profiles as the readings
(:mod:`lineload.simulation.subjects`) with what a camera adds
(:class:`lineload.simulation.photograph_render.Camera`); ``make_synthetic_data.py
--photographs`` writes what :func:`photograph_dataset` returns.
"""

from __future__ import annotations

import numpy as np

from lineload.rawdata.readings import reading_distances_mm
from lineload.simulation.notices import PHOTOGRAPH_NOTICE
from lineload.simulation.subjects import (
    DEFAULT_SEED,
    shipped_subjects,
    trial_deflection_mm,
    trial_parameters,
)

__all__ = [
    "PHOTOGRAPH_DEPTHS_MM",
    "PHOTOGRAPH_SUBJECTS",
    "photograph_dataset",
    "photograph_outlines",
    "photograph_scene",
]

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
        return rest(xs) - trial_deflection_mm(xs, trial, extent_mm=extent) + dz

    return rest, loaded, (dx, float(loaded(dx)))


def photograph_dataset(seed=DEFAULT_SEED, camera=None):
    """The photograph example: every file of its raw-data folder.

    Two monkeys of the reconstruction (:data:`PHOTOGRAPH_SUBJECTS`) at two depths, each
    trial a resting and a loaded side view rendered from the true profiles with what a
    camera adds (:class:`lineload.simulation.photograph_render.Camera`, its defaults unless
    given), the loaded shot moved a little against the resting one, seeded per trial.

    Returns
    -------
    dict
        Relative path -> content: ``NOTICE.txt``, ``subjects.csv``,
        ``images/images.csv`` and ``images/truth.csv`` (the true deflection the
        photographs were rendered from) as text, the photographs (PNG) as bytes.
    """
    import io

    import imageio.v3 as iio

    from lineload.simulation.photograph_render import Camera, render_photograph

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
                w = trial_deflection_mm(distance, trial, side)
                truth += [
                    f"{name},{depth_mm:g},{side},{d:.4f},{v:.6f}"
                    for d, v in zip(distance, w, strict=True)
                ]
    files["images/truth.csv"] = "\n".join(truth) + "\n"
    return files
