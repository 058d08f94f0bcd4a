"""Rule digitise: a photographed subject's readings from its rest and loaded photographs.

Each depth's pair is read with lineload.rawdata.photographs.digitise_pair; the readings are
written in the profile contract's form (image units: tissue mm times the subject's
magnification) and checked as a raw profile file is, and a record of how well each
trial was digitised is written beside them.  A photograph that cannot be read stops the
job with one line naming it.
"""

import os
import sys

from lineload.figures.data import figure_digitised
from lineload.figures.style import save_figure
from lineload.io import json_text, load_schema, output_to, write_text
from lineload.rawdata.photographs import (
    ImageError,
    digitise_photographs,
    profile_rows,
    quality_record,
    read_photograph,
)
from lineload.rawdata.readings import reading_distances_mm
from lineload.rawdata.validation import (
    InputError,
    check_thin_trials,
    image_scale_px_per_mm,
    read_columns,
    read_table,
)
from lineload.runtime.jobparams import given


def truth_of(folder, subject):
    """The true readings of ``subject`` where images/truth.csv gives them:
    {(depth_mm, side): (distance_mm, deflection_mm)}; empty without the file."""
    path = os.path.join(folder, "truth.csv")
    if not os.path.isfile(path):
        return {}
    truth = read_table(path, load_schema("truth"))
    mine = truth[truth["subject"] == subject]
    curves = {}
    for (depth_mm, side), rows in mine.groupby(["depth_mm", "side"]):
        rows = rows.sort_values("distance_mm")
        curves[(float(depth_mm), side)] = (
            rows["distance_mm"].to_numpy(float),
            rows["deflection_mm"].to_numpy(float),
        )
    return curves


def digitise(sheet, subject, label, magnification, settings, window_mm, notice, output):
    """Digitise every pair of ``subject``; write its profile, the quality record and the
    quality figure."""
    images = read_table(sheet, load_schema("images"))  # checked already: no problem left
    scale = image_scale_px_per_mm(images)
    folder = os.path.dirname(sheet)
    rows, quality, drawn = [], [], []
    truth = truth_of(folder, subject)
    grid = reading_distances_mm(settings["reach_mm"], settings["first_mm"])
    mine = images[images["subject"] == subject]
    for depth_mm in sorted(set(mine["depth_mm"].astype(float))):
        pair = mine[mine["depth_mm"].astype(float) == depth_mm]
        rest, loaded = (pair[pair["state"] == state].iloc[0] for state in ("rest", "loaded"))
        names = [os.path.join(folder, str(r["file"])) for r in (rest, loaded)]
        pictures = [read_photograph(name, name) for name in names]
        ppmm = float(scale.loc[loaded.name])
        trial = digitise_photographs(
            *pictures, ppmm, grid, settings, tip_x_px=loaded.get("tip_x_px"), names=names
        )
        height, width = pictures[1].shape[:2]
        rows += profile_rows(depth_mm, trial, magnification)
        known = {
            side: truth[(depth_mm, side)] for side in ("left", "right") if (depth_mm, side) in truth
        }
        record = quality_record(depth_mm, trial, known, window_mm)
        drawn.append(
            {
                "depth_mm": depth_mm,
                "image": pictures[1],
                "extent_mm": (0.0, width / ppmm, 0.0, -height / ppmm),
                "outlines": trial.outlines,
                "readings": trial.readings,
                "tip_x_mm": trial.tip_x_mm,
                "truth": known,
            }
        )
        quality.append({"rest": names[0], "loaded": names[1], **record})
        print(
            f"{subject} {depth_mm:g} mm: {sum(trial_counts(trial))} readings, tip at "
            f"{trial.tip_x_mm:.4f} mm, registration residual "
            f"{1000 * trial.registration_rms_mm:.1f} um, "
            f"reading SD {1000 * trial.reading_sd_mm:.1f} um"
        )
    text = "depth_mm,side,distance_image_mm,deflection_image_mm\n" + "".join(
        f"{d:g},{side},{x:.5f},{w:.5f}\n" for d, side, x, w in rows
    )
    write_text(text, output.profile)
    # the readings pass the checks a raw profile file does
    profile = read_columns(output.profile, load_schema("profiles"))
    check_thin_trials(profile, output.profile, magnification, settings["reach_mm"], 1)
    write_text(json_text({"subject": subject, "trials": quality}), output.quality)
    save_figure(figure_digitised(label, drawn, notice), output.pdf, output.png, dpi=200)


def trial_counts(trial):
    return [len(trial.readings[side][0]) for side in ("left", "right")]


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        values = given(snakemake.params)
        try:
            digitise(
                snakemake.input.sheet,
                values["subject"],
                values["label"],
                float(values["magnification"]),
                values["settings"],
                float(values["window_mm"]),
                values["notice"],
                snakemake.output,
            )
        except (ImageError, InputError) as error:
            print(error)
            sys.__stderr__.write(f"Error: {error}\n")
            sys.exit(1)
