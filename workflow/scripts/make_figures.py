"""Entry point of the figure rules: read results files, draw the named figures, save them.

Any subset of the registered figures (``lineload.figures.registry.FIGURES``) can be
drawn in one run (``--figure figure2 --figure figure6``); each is written as
``<outdir>/<name>.pdf`` and ``<outdir>/<name>.png``.  What a figure needs comes from
the registry: each of its arguments is read from the command line here, and the
subject list (id, species, label) comes on the command line too, so the figure stage
reads results files only.
"""

import argparse
import importlib
from pathlib import Path

import pandas as pd

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.figures import registry
from lineload.figures.style import save_figure
from lineload.io import read_results_csv


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--figure",
        action="append",
        required=True,
        choices=[figure.name for figure in registry.FIGURES],
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
    # options without a default: a figure that takes one cannot be drawn without it
    # (no averaged profiles or outlines is not an error: the figure says so)
    required = {
        "fits": args.fits,
        "sensitivity": args.sensitivity,
        "checks": args.checks,
        "fit_window_mm": args.fit_window_mm,
        "example_depth_mm": args.example_depth_mm,
        "schematic_depth_ratio": args.schematic_depth_ratio,
        "noise_mm": args.noise_mm,
    }
    for name in args.figure:
        for argument in registry.figure_named(name).arguments:
            if argument in required and required[argument] is None:
                parser.error(f"{name} needs --{argument.replace('_', '-')}")
    return args


def read_csvs(paths):
    frames = [read_results_csv(path) for path in paths]
    return pd.concat(frames, ignore_index=True) if frames else None


def argument_values(args, names):
    """The value of every named argument of :data:`registry.ARGUMENTS`, from the command line."""
    values = {}
    for name in names:
        if name == "averaged":
            averaged = read_csvs(args.averaged)
            if averaged is None:
                averaged = pd.DataFrame(
                    columns=["subject", "depth_mm", "distance_mm", "deflection_mm"]
                )
            values[name] = averaged
        elif name == "outlines":
            values[name] = read_csvs(args.outline)
        elif name == "outline_subjects":
            # the subjects of the outline files given, in order
            outlines = values["outlines"] if "outlines" in values else read_csvs(args.outline)
            values[name] = [] if outlines is None else list(dict.fromkeys(outlines["subject"]))
        elif name in ("fits", "sensitivity", "checks"):
            path = getattr(args, name)
            values[name] = read_results_csv(path) if path else None
        elif name == "subjects":
            values[name] = pd.DataFrame(args.subject, columns=["subject", "species", "label"])
        elif name == "example_subjects":
            values[name] = args.example_subject
        else:  # notice and the numeric settings, spelled as their option
            values[name] = getattr(args, name)
    return values


def main():
    args = parse_args()
    figures = [registry.figure_named(name) for name in dict.fromkeys(args.figure)]
    needed = {name for figure in figures for name in figure.arguments}
    values = argument_values(args, [name for name in registry.ARGUMENTS if name in needed])
    notice = args.notice
    print(f"footer: {notice!r}" if notice else "footer: none")
    outdir = Path(args.outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    for figure in figures:
        draw = getattr(importlib.import_module(figure.import_path), figure.function)
        fig = draw(**{name: values[name] for name in figure.arguments}, **dict(figure.fixed))
        pdf, png = outdir / f"{figure.name}.pdf", outdir / f"{figure.name}.png"
        save_figure(fig, pdf, png, args.dpi)
        print(f"{figure.name}: {len(fig.axes)} axes -> {pdf}, {png} ({args.dpi} dpi)")


if __name__ == "__main__":
    main()
