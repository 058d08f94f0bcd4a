"""Rule check_raw_data: every raw file against the data contract, every problem at once.

Reads the raw folder (lineload.rawdata.validation.check_dataset), the profile, outline
and photograph files as the check_profiles jobs found them batch by batch (no
photograph is opened here: images/images.csv is read as a sheet), and writes what the
later jobs need to know of it: the depths per subject, the outline depths and
the warnings.  A refused folder prints one line per problem on stderr (and into
the log), writes nothing else and exits with 1; every job that reads raw data
waits for this one.
"""

import os
import sys

from lineload.io import json_text, load_schema, output_to, read_json, write_text
from lineload.rawdata.validation import InputError, check_dataset, report_lines
from lineload.runtime.jobparams import given
from lineload.runtime.startup import check_record, file_metadata, portable_path

#: The tables of the data contract, each with its row schema.
TABLES = ("subjects", "profiles", "outlines", "forces", "images")


def merged(batches):
    """The check_profiles jobs' findings as one, in sheet order (the batches' order)."""
    checked = {
        "depths_mm": {},
        "outlines": {},
        "photographs": {},
        "refused": [],
        "errors": [],
        "warnings": [],
    }
    for path in batches:
        batch = read_json(path)
        for key in ("depths_mm", "outlines", "photographs"):
            checked[key].update(batch[key])
        for key in ("refused", "errors", "warnings"):
            checked[key] += batch[key]
    return checked


def check_raw_data(sheet, files, batches, output, log, input_checks, window_mm, min_points):
    """Check the folder of ``sheet``; write the summary (or every problem into ``log``).
    Returns the lines for the user: at most MAX_REPORTED errors and where the rest are."""
    raw_dir = os.path.dirname(sheet)  # as configured: the messages name it so
    schemas = {name: load_schema(name) for name in TABLES}
    try:
        dataset = check_dataset(
            raw_dir,
            schemas,
            plausibility=input_checks,
            window=(window_mm, min_points),
            checked=merged(batches),
        )
    except InputError as error:
        for line in report_lines(error, limit=len(error.problems)):
            print(line)  # every problem, into the log
        lines = report_lines(error)
        if len(error.problems) > len(lines):
            lines[-1] = lines[-1].replace("not shown", f"not shown here, every one in {log}")
        return lines, 1
    name = portable_path(raw_dir)
    summary = {
        "raw_data": name,
        "depths_mm": dataset["depths_mm"],
        "outlines_mm": dataset["outlines"],
        # the folder named as in every output: no absolute path
        "warnings": [w.replace(f"{raw_dir}/", f"{name}/") for w in dataset["warnings"]],
    }
    write_text(json_text(summary), output)
    # size and time of every file checked: a file later put back with an old time is
    # noticed at the next start (lineload.runtime.startup.restored_files)
    write_text(json_text(file_metadata(files, raw_dir)), check_record(log))  # sheet included
    trials = sum(len(d) for d in dataset["depths_mm"].values())
    print(
        f"{raw_dir}: {len(dataset['depths_mm'])} subjects, {trials} profiles, "
        f"{len(dataset['outlines'])} with outlines; no problem -> {output}"
    )
    lines = [f"Warning: {w}" for w in dataset["warnings"]]
    for line in lines:
        print(line)
    return lines, 0


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        said, status = check_raw_data(
            snakemake.input.sheet,
            snakemake.input.files,
            snakemake.input.batches,
            snakemake.output[0],
            snakemake.log[0],
            **given(snakemake.params),
        )
    sys.stderr.write("".join(f"{line}\n" for line in said))  # the user sees them too
    sys.exit(status)
