"""Acceptance of the digitiser on hard photographs a lab's bench takes.

Held out: the pairs are drawn by :mod:`lineload.simulation.hard_photographs`, a renderer
apart from the example's (exact arcs and parabola-plus-log blends with each side its own
L, disc or Gaussian defocus, photon and read noise, strong vignetting and a lighting
gradient, a turned camera, gamma, 8/16-bit, grey and colour, scale bars, rulers and
labels where labs put them, the wedge in the resting view, glare).  Each pair is written
to disc (PNG or TIFF, alternately), read back by
:func:`lineload.rawdata.photographs.read_photograph` and digitised by
:func:`lineload.rawdata.photographs.digitise_photographs` with the config's default
settings, except ``reach_mm`` (the larger side's L plus 0.3 mm, as a lab sets it for its
fingers).  Per pair:

* the averaged (left-right mean) profile's RMS error over the fit window (3 mm) against
  the true mean at the same distances;
* L fitted to the averaged profile (:func:`lineload.fitting.batch.fit_waterbed`, W0 the
  depth) with a covariance from the trial's own stated uncertainties (independent part
  halved by the average, the registration's shared part in every reading), and whether
  its 95 % interval holds the L the same fit gives on the true mean at the same distances
  (the truth is no parabola: "the truth's L" is the parabola closest to it);
* seconds to digitise the pair (read from disc excluded).

Run: ``python docs/calibration/scripts/photographs_hard.py [n_pairs] [seed]``
(writes ``docs/calibration/photographs_hard.md`` and ``photographs_hard.csv``).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import imageio.v3 as iio
import numpy as np
from scipy.stats import binomtest

from lineload.fitting.batch import fit_waterbed
from lineload.io import config_defaults
from lineload.rawdata.photographs import ImageError, digitise_photographs, read_photograph
from lineload.rawdata.readings import reading_distances_mm
from lineload.simulation.hard_photographs import draw_case, render_pair, true_deflection_mm

HERE = Path(__file__).resolve().parents[1]
FIT_WINDOW_MM = 3.0


def settings_for(case):
    """The config's digitise defaults, reach_mm set for the case's fingers."""
    settings = dict(config_defaults("digitise"))
    settings["reach_mm"] = float(np.ceil(10 * (max(case.L_left_mm, case.L_right_mm) + 0.3)) / 10)
    return settings


def averaged(trial):
    """Distances both sides were read at within the fit window, and their mean."""
    sides = [dict(zip(np.round(d, 4), w, strict=True)) for d, w in trial.readings.values()]
    common = sorted(set(sides[0]) & set(sides[1]))
    distance = np.array([d for d in common if d <= FIT_WINDOW_MM])
    mean = np.array([(sides[0][d] + sides[1][d]) / 2 for d in distance])
    return distance, mean


def one_pair(k, seed, folder):
    """Render, write, read and digitise pair ``k``; one row of the results."""
    rng = np.random.default_rng([seed, k])
    case = draw_case(rng)
    rest, loaded, tip_column = render_pair(case, rng)
    suffix = ".tif" if k % 2 else ".png"
    names = [str(Path(folder) / f"pair{k}_{state}{suffix}") for state in ("rest", "loaded")]
    for name, image in zip(names, (rest, loaded), strict=True):
        iio.imwrite(name, image)
    pictures = [read_photograph(name, name) for name in names]
    settings = settings_for(case)
    grid = reading_distances_mm(settings["reach_mm"], settings["first_mm"])
    row = {
        "pair": k,
        "depth_mm": case.depth_mm,
        "L_left_mm": round(case.L_left_mm, 3),
        "L_right_mm": round(case.L_right_mm, 3),
        "shape": case.shape,
        "blur": f"{case.blur} {case.blur_px:.1f} px",
        "gamma": case.gamma,
        "bits": case.bits,
        "colour": case.colour,
        "format": suffix[1:],
        "bar": f"{case.bar_kind} {case.bar}" if case.bar else "none",
        "wedge_at_rest": case.rest_gap_mm is not None,
        "rotation_deg": round(case.rotation_deg, 3),
        "vignetting": round(case.vignetting, 2),
    }
    start = time.perf_counter()
    try:
        trial = digitise_photographs(*pictures, case.pixels_per_mm, grid, settings, names=names)
    except ImageError as error:
        return {**row, "read": False, "refusal": str(error).replace(folder, "")}
    seconds = time.perf_counter() - start
    distance, mean = averaged(trial)
    truth = (
        true_deflection_mm(case, "left", distance) + true_deflection_mm(case, "right", distance)
    ) / 2
    rms_um = 1000 * float(np.sqrt(np.mean((mean - truth) ** 2)))
    shared = trial.registration_sd_mm**2
    own = max(trial.reading_sd_mm**2 - shared, 0.0) / 2
    covariance = own * np.eye(distance.size) + shared
    fitted = fit_waterbed(distance, mean, case.depth_mm, covariance).params
    target = fit_waterbed(distance, truth, case.depth_mm).params["L_mm"]
    tip_error_px = (trial.tip_x_mm * case.pixels_per_mm - 0.5) - tip_column
    readable = sum(int(np.sum(d <= FIT_WINDOW_MM)) for d, _ in trial.readings.values())
    unread = [(d, r) for side in trial.unread.values() for d, r in side if d <= FIT_WINDOW_MM]
    in_window = 2 * int(np.sum(grid <= FIT_WINDOW_MM))
    return {
        **row,
        "read": True,
        "refusal": "",
        "rms_um": round(rms_um, 2),
        "tip_error_px": round(float(tip_error_px), 2),
        "tip_sd_px": None
        if trial.tip_sd_mm is None
        else round(trial.tip_sd_mm * case.pixels_per_mm, 3),
        "readings_in_window": f"{readable}/{in_window}",
        "furthest_unread_mm": max((d for d, _ in unread), default=0.0),
        "unread_glare": sum(r.startswith("glare") for _, r in unread),
        "unread_no_edge": sum(r.startswith("no edge") for _, r in unread),
        "unread_other": sum(not r.startswith(("glare", "no edge")) for _, r in unread),
        "L_truth_mm": round(target, 3),
        "L_mm": round(fitted["L_mm"], 3),
        "L_ci_low_mm": round(fitted["L_ci_low_mm"], 3),
        "L_ci_high_mm": round(fitted["L_ci_high_mm"], 3),
        "covered": bool(fitted["L_ci_low_mm"] <= target <= fitted["L_ci_high_mm"]),
        "seconds": round(seconds, 3),
    }


def main(n_pairs=18, seed=38):
    import pandas as pd

    with tempfile.TemporaryDirectory() as folder:
        rows = [one_pair(k, seed, folder + "/") for k in range(n_pairs)]
    table = pd.DataFrame(rows)
    table.to_csv(HERE / "photographs_hard.csv", index=False)
    read = table[table["read"]]
    covered = int(read["covered"].sum()) if len(read) else 0
    ci = binomtest(covered, max(len(read), 1)).proportion_ci(0.95) if len(read) else None
    lines = [
        "# The digitiser on hard photographs",
        "",
        "Written by `docs/calibration/scripts/photographs_hard.py` "
        f"(`python docs/calibration/scripts/photographs_hard.py {n_pairs} {seed}`); the pairs "
        "come from `lineload.simulation.hard_photographs`, a renderer apart from the "
        "example's (see the script's notes). One row per pair in `photographs_hard.csv`.",
        "",
        f"- pairs read: {len(read)} of {len(table)}",
    ]
    if len(read):
        z_tip = (read["tip_error_px"] / read["tip_sd_px"]).dropna()
        lines += [
            f"- averaged profile's RMS error over the fit window: median "
            f"{read['rms_um'].median():.2f} um, worst {read['rms_um'].max():.2f} um",
            f"- the wedge's tip against the truth: median |error| "
            f"{read['tip_error_px'].abs().median():.2f} px, worst "
            f"{read['tip_error_px'].abs().max():.2f} px",
            f"- the tip's error against its stated standard error (where the apex was seen, "
            f"{int(read['tip_sd_px'].notna().sum())} pairs): RMS "
            f"{float(np.sqrt(np.mean(z_tip**2))):.2f}, largest {float(z_tip.abs().max()):.2f}, "
            f"{int((z_tip.abs() <= 1.96).sum())} within 1.96",
            f"- L's 95 % interval holds the truth's L in {covered} of {len(read)} pairs "
            f"(Clopper-Pearson 95 %: {ci.low:.2f}-{ci.high:.2f})",
            f"- readings in the fit window left unread: {int(read['unread_glare'].sum())} for "
            f"glare (or the wedge above the edge), {int(read['unread_no_edge'].sum())} with "
            f"no edge, {int(read['unread_other'].sum())} for another reason; the furthest "
            f"{read['furthest_unread_mm'].max():g} mm from the tip",
            f"- seconds to digitise a pair: median {read['seconds'].median():.2f}, "
            f"worst {read['seconds'].max():.2f}",
        ]
    refused = table[~table["read"]]
    for _, r in refused.iterrows():
        lines.append(f"- refused, pair {r['pair']} ({r['bar']}): {r['refusal']}")
    (HERE / "photographs_hard.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
