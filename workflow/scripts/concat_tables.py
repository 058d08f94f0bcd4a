"""Entry point of aggregate rules: concatenate per-subject CSV tables in the given order.

Imports no numpy or pandas: it runs once per build over every subject's file,
so its cost should be Python's start-up alone.
"""

import argparse
import csv
import io
import sys

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.io import write_text


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
    write_text(buffer.getvalue(), args.output)
    print(f"{args.output}: {n_rows} rows from {len(args.inputs)} files")


if __name__ == "__main__":
    main()
