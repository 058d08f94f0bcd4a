"""The digitiser's stated uncertainties against rendered truth: docs/calibration/digitiser.md.

Renders ``--pairs`` photograph pairs of known fingers (:mod:`lineload.simulation.digitiser`:
scale, view, blur, sensor noise, lighting, texture, glare, levels, depth and the shift
between the shots drawn per pair), digitises each with the config's ``digitise``
defaults, and writes how often each stated uncertainty covers its error: the
registration's, each reading's own and each reading's total, overall and by distance
from the wedge, how far the tip lands from the truth, and how often the apex's stated SD
covers its error.  The per-pair table goes to
``digitiser.csv`` beside it.

Run after any change to the digitiser (the edge finder, the tip, the readings):
``python docs/calibration/scripts/digitiser.py`` (about 0.15 s of CPU a pair).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from lineload.io import config_defaults, write_rows, write_text
from lineload.simulation.digitiser import PAIR_COLUMNS, coverage_summary, digitiser_calibration

HERE = Path(__file__).resolve().parent.parent
#: The stated SDs times these: 1 is as stated; the others show how the coverage moves
#: when they are too small or too large.
MULTIPLES = (0.5, 0.8, 1.0, 1.25)
#: The coverage asked of a stated SD at a nominal 95 %.
BAND = (0.90, 0.985)


def percent(value):
    return f"{100 * value:.1f} %"


def page(summaries, seconds, settings):
    stated = summaries[1.0]
    wedge_um = 1000 * config_defaults("noise")["wedge_position_sd_mm"]
    lines = [
        "# The digitiser's own calibration",
        "",
        "Written by `docs/calibration/scripts/digitiser.py` (rerun it after any change to",
        "the digitiser); the per-pair table is [digitiser.csv](digitiser.csv).",
        "",
        f"{stated['pairs']} pairs rendered by `lineload.simulation.digitiser.rendered_pair`",
        "(seeds 0 on), each with its own scale (45-100 pixels per mm), view, blur",
        "(0.7-2.5 px), sensor noise (0.5-4 % of full scale), lighting gradient (0-40 %),",
        "skin texture, glare at the wedge, 8- or 16-bit levels, depth (0.5-2 mm), both sides'",
        "deformed regions (3.2-7.2 mm) and a shift of up to 50 um between the two shots, and",
        f"digitised with the config's defaults (`smoothing_px` {settings['smoothing_px']:g},",
        f"`window_mm` {settings['window_mm']:g}). {stated['read']} of {stated['pairs']} were",
        f"read; {stated['readings']} readings. {seconds:.0f} s of CPU in all.",
        "",
        "A stated SD covers an error when the error is within 1.96 times it (nominal 95 %).",
        "Each reading's *own* error leaves out the registration's (an offset shared by the",
        "trial) and the tip's (the reading is compared with the truth at the distance of",
        "its columns from the true tip); the *total* keeps the registration's.",
        "",
        "| stated SD times | registration | a reading's own | a reading's total |",
        "|---|---|---|---|",
    ]
    for multiple, summary in summaries.items():
        lines.append(
            f"| {multiple:g} | {percent(summary['registration'])} | {percent(summary['own'])} "
            f"| {percent(summary['total'])} |"
        )
    lines += [
        "",
        "A reading's own coverage by distance from the wedge (SDs as stated):",
        "",
        "| distance | coverage | readings |",
        "|---|---|---|",
    ]
    for band, (share, count) in stated["own_by_band"].items():
        lines.append(f"| {band} | {percent(share)} | {count} |")
    lines += [
        "",
        "Sizes: a reading's own error is "
        f"{stated['own_rms_um']:.2f} um RMS against a stated {stated['own_sd_rms_um']:.2f} um "
        f"RMS; the registration's error is {stated['registration_rms_um']:.2f} um RMS (mean "
        f"{stated['registration_bias_um']:+.2f} um) against a median stated SD of "
        f"{stated['registration_sd_median_um']:.2f} um.",
        "",
        f"The tip lands {stated['tip_rms_px']:.2f} px from the truth (RMS; 95 % within "
        f"{stated['tip_p95_px']:.2f} px), {stated['tip_rms_um']:.1f} um RMS (95 % within "
        f"{stated['tip_p95_um']:.1f} um).",
        "",
        "The apex's own SD (`tip_sd_um` in the quality record, where the wedge is seen "
        "against the background):",
        f"the apex was seen in {stated['apex_seen']} of {stated['read']} pairs; its stated SD "
        f"(median {stated['apex_sd_median_px']:.3f} px) covers its error in "
        f"{stated['apex_covered']} of them, {percent(stated['apex'])} (Clopper-Pearson 95 %: "
        f"{percent(stated['apex_ci'][0])}-{percent(stated['apex_ci'][1])}); the error over the "
        f"stated SD has an SD of {stated['apex_z_sd']:.2f} (1 when the SD is right). The "
        f"coverage is {'within' if BAND[0] <= stated['apex'] <= BAND[1] else 'outside'} the "
        f"band asked of a nominal 95 % ({percent(BAND[0])}-{percent(BAND[1])}).",
        "",
        "| stated SD times | apex covered | z-score SD |",
        "|---|---|---|",
    ]
    for multiple, summary in summaries.items():
        lines.append(f"| {multiple:g} | {percent(summary['apex'])} | {summary['apex_z_sd']:.2f} |")
    lines += [
        "",
        "The apex's SD is the two faces' lines' covariance carried to where they cross.",
        "Each line's covariance is the least-squares sandwich with its residual's",
        "autocovariance down the face (up to its first non-positive lag), the residual's",
        "variance raised for the line's two parameters out of the points' effective count",
        "(their count over the correlation's integrated length). The rule before it (the",
        "white-noise variance times (1 + r) / (1 - r), r the residual's lag-1 correlation, as",
        "for an AR(1) chain) covered 237 of these 240 apexes (98.8 %, z-score SD 0.73): too",
        "wide, since the smoothing's correlation falls off faster than an AR(1) chain's.",
        f"The fits still take the config's prior `noise: wedge_position_sd_mm` ({wedge_um:g} um)",
        f"for the tip's error, {'above' if wedge_um > stated['tip_rms_um'] else 'below'} the "
        "tip's RMS error here.",
        "",
        "How the SDs are stated (lineload.rawdata.photographs): each outline's edge",
        "errors are its residual about a moving quartic over 1 mm (each side of the wedge",
        "on its own), scaled by what the quartic takes of errors correlated as the",
        "residual's own autocorrelation says; their local mean square over 0.5 mm either",
        "side of a reading gives its variance, the two photographs' added. The",
        "registration's SD is the least-squares sandwich with the far residual's",
        "autocovariance up to its first non-positive lag. No factor is fitted to these",
        "renderings.",
        "",
    ]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=240)
    parser.add_argument("--out", type=Path, default=HERE)
    args = parser.parse_args()
    settings = config_defaults("digitise")
    start = time.process_time()
    pairs, readings = digitiser_calibration(args.pairs, settings)
    seconds = time.process_time() - start
    summaries = {m: coverage_summary(pairs, readings, m) for m in MULTIPLES}
    rows = [{column: pair.get(column, "") for column in PAIR_COLUMNS} for pair in pairs]
    write_rows(rows, PAIR_COLUMNS, args.out / "digitiser.csv")
    write_text(page(summaries, seconds, settings), args.out / "digitiser.md")
    stated = summaries[1.0]
    print(
        f"{stated['read']}/{stated['pairs']} pairs read; coverage: registration "
        f"{percent(stated['registration'])}, own {percent(stated['own'])}, total "
        f"{percent(stated['total'])}, apex {percent(stated['apex'])} (z SD "
        f"{stated['apex_z_sd']:.2f}); {seconds:.0f} s CPU"
    )


if __name__ == "__main__":
    main()
