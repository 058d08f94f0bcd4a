"""Rule check_profiles: one batch's profile and outline files against the data contract.

The raw-data check's part that reads the large files, run batch by batch so that it
uses every core (and the cluster): lineload.rawdata.validation.check_subject_files on the
batch's subjects.  The problems are written down, not raised: rule check_raw_data
gathers every batch's, with the checks of the whole folder, and refuses the folder
with all of them at once.
"""

import os

from lineload.io import json_text, load_schema, output_to, write_text
from lineload.rawdata.validation import Problems, check_subject_files, plausibility_defaults
from lineload.runtime.jobparams import given


def check_profiles(sheet, output, subjects, input_checks, window_mm, min_points):
    """Check the files of ``subjects`` (id -> its sheet row) in the folder of ``sheet``."""
    raw_dir = os.path.dirname(sheet)  # as configured: the messages name it so
    schemas = {name: load_schema(name) for name in ("profiles", "outlines")}
    # the subjects with a profile file (one without is the whole folder's check to report)
    listed = [s for s in subjects if os.path.isfile(os.path.join(raw_dir, "profiles", f"{s}.csv"))]
    found = Problems()
    depths_mm, outlines, refused = check_subject_files(
        raw_dir,
        schemas,
        listed,
        {s: subjects[s]["magnification"] for s in listed},
        found,
        {**plausibility_defaults(), **input_checks},
        (window_mm, min_points),
    )
    checked = {
        "subjects": listed,
        "depths_mm": depths_mm,
        "outlines": outlines,
        "refused": [s for s in listed if s in refused],
        "errors": found.errors,
        "warnings": found.warnings,
    }
    write_text(json_text(checked), output)
    print(
        f"{len(listed)} subjects' profiles checked, {len(outlines)} outlines: "
        f"{len(found.errors)} problems -> {output}"
    )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        check_profiles(snakemake.input.sheet, snakemake.output[0], **given(snakemake.params))
