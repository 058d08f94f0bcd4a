"""Write the synthetic raw-data folder (subjects.csv, forces.csv, profiles/, outlines/).

Without ``--monkeys``/``--humans`` this rebuilds the shipped reconstruction
byte for byte::

    python workflow/scripts/make_synthetic_data.py --out data/raw \
        --verdicts data/built_in_verdicts.json

With them it writes a scale dataset of fingers with drawn parameters, e.g.
for benchmarks::

    python workflow/scripts/make_synthetic_data.py --out /tmp/big --monkeys 500 --humans 500

``--photographs`` writes the photograph example instead (two monkeys at two depths,
each trial a resting and a loaded side view rendered from the true profiles)::

    python workflow/scripts/make_synthetic_data.py --photographs --out data/photographs

``--print-parameters`` prints the true parameters (per subject, then per
trial, then the membranes behind the forces) as Markdown tables instead of
writing files.  The generator itself is ``lineload.simulation.synthetic``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import lineload.simulation.synthetic as synthetic
from lineload.io import json_text, replaced_atomically, write_text

#: Sub-folders whose CSV files the generator owns.
GENERATED_FOLDERS = ("profiles", "outlines")


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("data/raw"),
        help="raw-data folder to write (default: data/raw)",
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=synthetic.DEFAULT_SEED,
        help=f"dataset seed (default: {synthetic.DEFAULT_SEED})",
    )
    parser.add_argument(
        "--monkeys",
        type=int,
        default=None,
        help="scale mode: number of monkeys with drawn parameters",
    )
    parser.add_argument(
        "--humans",
        type=int,
        default=None,
        help="scale mode: number of humans with drawn parameters",
    )
    parser.add_argument(
        "--verdicts",
        type=Path,
        default=None,
        help="also write the verdicts the generator builds in (JSON) to this file; shipped "
        "data only (data/built_in_verdicts.json)",
    )
    parser.add_argument(
        "--shuffle", action="store_true", help="shuffle the rows of each profile file (seeded)"
    )
    parser.add_argument(
        "--clean",
        action="store_true",
        help="delete CSV files in profiles/ and outlines/ that this run "
        "does not write (otherwise they stop the run)",
    )
    parser.add_argument(
        "--photographs",
        action="store_true",
        help="write the photograph example (subjects.csv, images/) instead",
    )
    parser.add_argument(
        "--print-parameters",
        action="store_true",
        help="print the true parameters (per subject and per trial, and the membranes "
        "behind the forces) as Markdown and exit",
    )
    args = parser.parse_args(argv)
    for name in ("monkeys", "humans"):
        value = getattr(args, name)
        if value is not None and value < 0:
            parser.error(f"--{name} must be >= 0")
    if (args.monkeys is not None or args.humans is not None) and not (args.monkeys or args.humans):
        parser.error("a scale dataset needs at least one subject")
    return args


def stale_files(out, files):
    """CSV files in the generated sub-folders of ``out`` that ``files`` does not contain."""
    stale = []
    for folder in GENERATED_FOLDERS:
        for path in sorted((out / folder).glob("*.csv")):
            if path.relative_to(out).as_posix() not in files:
                stale.append(path)
    return stale


def main(argv=None):
    args = parse_args(argv)
    scale = args.monkeys is not None or args.humans is not None
    if args.print_parameters:
        subjects = (
            synthetic.draw_subjects(args.monkeys or 0, args.humans or 0, args.seed)
            if scale
            else synthetic.shipped_subjects()
        )
        sys.stdout.write(synthetic.subject_markdown(subjects) + "\n")
        sys.stdout.write(synthetic.parameter_markdown(subjects))
        if any(s.contact_length_mm is not None for s in subjects):
            sys.stdout.write("\n" + synthetic.membrane_markdown(subjects) + "\n")
            sys.stdout.write(synthetic.force_markdown(subjects, args.seed))
        return 0
    if args.photographs:
        files = synthetic.photograph_dataset(seed=args.seed)
        for relative, content in files.items():
            if isinstance(content, bytes):
                with replaced_atomically(args.out / relative) as temporary:
                    Path(temporary).write_bytes(content)
            else:
                write_text(content, args.out / relative)
        print(f"wrote {len(files)} files to {args.out}")
        return 0
    files = synthetic.build_dataset(
        seed=args.seed,
        n_monkeys=args.monkeys if scale else None,
        n_humans=args.humans if scale else None,
        shuffle=args.shuffle,
    )
    stale = stale_files(args.out, files)
    if stale and not args.clean:
        listed = ", ".join(str(p) for p in stale[:5]) + (" ..." if len(stale) > 5 else "")
        sys.exit(
            f"error: {args.out} holds {len(stale)} CSV file(s) this run would not write "
            f"({listed}); they would be read as data. Remove them or pass --clean."
        )
    for path in stale:
        path.unlink()
    for relative, text in files.items():
        write_text(text, args.out / relative)
    if args.verdicts is not None and not scale:
        write_text(json_text(synthetic.built_in_verdicts()), args.verdicts)
    n_profiles = sum(name.startswith("profiles/") for name in files)
    print(f"wrote {len(files)} files ({n_profiles} profiles) to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
