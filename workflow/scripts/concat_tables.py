"""Entry point of aggregate rules: concatenate per-subject CSV tables in the given order.

Uses only the standard library (no numpy/pandas import): it runs once per build
over every subject's file, and its cost is the start-up of Python alone.
"""

import argparse
import csv
import io
import os
import sys
import tempfile


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--output", required=True)
    parser.add_argument("inputs", nargs="+")
    args = parser.parse_args()

    header = None
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    n_rows = 0
    for path in args.inputs:
        with open(path, newline="", encoding="utf-8") as handle:
            reader = csv.reader(handle)
            this_header = next(reader)
            if header is None:
                header = this_header
                writer.writerow(header)
            elif this_header != header:
                sys.exit(f"{path}: columns differ from {args.inputs[0]}")
            for row in reader:
                writer.writerow(row)
                n_rows += 1
    directory = os.path.dirname(os.path.abspath(args.output))
    os.makedirs(directory, exist_ok=True)
    handle, tmp = tempfile.mkstemp(dir=directory, suffix=".tmp")
    with os.fdopen(handle, "w", encoding="utf-8", newline="") as stream:
        stream.write(buffer.getvalue())
    os.replace(tmp, args.output)
    print(f"{args.output}: {n_rows} rows from {len(args.inputs)} files")


if __name__ == "__main__":
    main()
