"""Entry point of the figure rules: read results files, draw the named figures, save them.

Any subset of figures can be drawn in one run (``--figure figure2 --figure figure6``);
each is written as ``<outdir>/<name>.pdf`` and ``<outdir>/<name>.png``.  The subject
list (id, species, label) comes on the command line, so the figure stage reads
results files only.
"""

import argparse
from pathlib import Path

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload import paper, plotting
from lineload.io import read_results_csv

#: Which inputs each figure needs (checked before anything is drawn).
NEEDS = {
    "figure1": ["outline_depth_mm"],
    "figure2": ["averaged", "fits", "example_depth_mm", "fit_window_mm"],
    "figure3": ["schematic_depth_ratio"],
    "figure4": ["schematic_depth_ratio"],
    "figure5": ["schematic_depth_ratio"],
    "figure6": ["averaged", "fits", "fit_window_mm"],
    "figure7": ["averaged", "fits", "fit_window_mm"],
    "supplement_residuals": ["averaged", "fits", "fit_window_mm"],
    "supplement_arc_vs_parabola": ["fits"],
    "supplement_sensitivity": ["sensitivity", "checks"],
    "supplement_coordinates": ["fits", "checks", "noise_mm"],
}


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--figure",
        action="append",
        required=True,
        choices=plotting.FIGURE_NAMES,
        help="figure to draw (repeatable)",
    )
    parser.add_argument("--outdir", required=True, help="folder of the PDF and PNG files")
    parser.add_argument("--dpi", type=int, required=True, help="resolution of the PNG files")
    parser.add_argument("--notice", default="", help="footer text; empty for none")
    parser.add_argument(
        "--subject",
        nargs=3,
        action="append",
        default=[],
        metavar=("ID", "SPECIES", "LABEL"),
        help="one subject, in subject-sheet order (repeatable)",
    )
    parser.add_argument("--averaged", nargs="*", default=[], help="averaged profiles (CSV)")
    parser.add_argument("--fits", help="the fit table (CSV)")
    parser.add_argument(
        "--outline",
        nargs="*",
        default=[],
        help="outlines in tissue mm (CSV), one per Figure 1 subject, in order",
    )
    parser.add_argument("--outline-depth-mm", type=float)
    parser.add_argument(
        "--example-subject",
        action="append",
        default=[],
        help="Figure 2 subject (repeatable, in panel order)",
    )
    parser.add_argument("--example-depth-mm", type=float)
    parser.add_argument("--fit-window-mm", type=float)
    parser.add_argument("--schematic-depth-ratio", type=float)
    parser.add_argument("--sensitivity", help="the sensitivity refits (CSV)")
    parser.add_argument("--checks", help="the per-trial shift and reach (CSV)")
    parser.add_argument("--noise-mm", type=float, help="digitising noise of one reading (mm)")
    args = parser.parse_args()
    for name in args.figure:
        for need in NEEDS[name]:
            if need not in ("averaged", "outline_depth_mm") and getattr(args, need) is None:
                parser.error(f"{name} needs --{need.replace('_', '-')}")
    return args


def read_csvs(paths):
    frames = [read_results_csv(path) for path in paths]
    return pd.concat(frames, ignore_index=True) if frames else None


def main():
    args = parse_args()
    subjects = pd.DataFrame(args.subject, columns=["subject", "species", "label"])
    averaged = read_csvs(args.averaged)
    if averaged is None:
        averaged = pd.DataFrame(columns=["subject", "depth_mm", "distance_mm", "deflection_mm"])
    fits = read_results_csv(args.fits) if args.fits else None
    outlines = read_csvs(args.outline)
    outline_ids = [] if outlines is None else list(dict.fromkeys(outlines["subject"]))
    # One distance scale for Figures 6 and 7, so the two species compare at a glance.
    distance_max_mm = float(averaged["distance_mm"].max()) if len(averaged) else None
    notice = args.notice

    draw = {
        "figure1": lambda: plotting.figure_outlines(
            outlines, subjects, outline_ids, args.outline_depth_mm, notice
        ),
        "figure2": lambda: plotting.figure_examples(
            averaged,
            fits,
            subjects,
            args.example_subject,
            args.example_depth_mm,
            args.fit_window_mm,
            notice,
        ),
        "figure3": lambda: plotting.figure_channel_schematic(args.schematic_depth_ratio, notice),
        "figure4": lambda: plotting.figure_material_point(args.schematic_depth_ratio, notice),
        "figure5": lambda: plotting.figure_free_body(args.schematic_depth_ratio, notice),
        "figure6": lambda: plotting.figure_species_fits(
            averaged, fits, subjects, "monkey", args.fit_window_mm, notice, distance_max_mm
        ),
        "figure7": lambda: plotting.figure_species_fits(
            averaged, fits, subjects, "human", args.fit_window_mm, notice, distance_max_mm
        ),
        "supplement_residuals": lambda: plotting.figure_residuals(
            averaged, fits, subjects, args.fit_window_mm, notice
        ),
        "supplement_arc_vs_parabola": lambda: plotting.figure_arc_vs_parabola(fits, notice),
        "supplement_sensitivity": lambda: plotting.figure_sensitivity(
            read_results_csv(args.sensitivity),
            read_results_csv(args.checks),
            paper.MAX_SHIFT_FRACTION,
            paper.REACH_MM,
            notice,
        ),
        "supplement_coordinates": lambda: plotting.figure_coordinates(
            fits, read_results_csv(args.checks), args.noise_mm, notice
        ),
    }
    print(f"footer: {notice!r}" if notice else "footer: none")
    outdir = Path(args.outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    for name in dict.fromkeys(args.figure):
        fig = draw[name]()
        pdf, png = outdir / f"{name}.pdf", outdir / f"{name}.png"
        plotting.save_figure(fig, pdf, png, args.dpi)
        print(f"{name}: {len(fig.axes)} axes -> {pdf}, {png} ({args.dpi} dpi)")


if __name__ == "__main__":
    main()
