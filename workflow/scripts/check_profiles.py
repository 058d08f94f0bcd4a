"""Rule check_profiles: one batch's profile, outline and photograph files against the data contract.

The raw-data check's part that reads the large files, run batch by batch so that it
uses every core (and the cluster): lineload.rawdata.validation.check_subject_files on the
batch's subjects, and check_images on their photographs (each read here, once).  The
problems are written down, not raised: rule check_raw_data gathers every batch's, with
the checks of the whole folder, and refuses the folder with all of them at once.  A
refused photograph pair is drawn as the digitiser saw it into a PNG beside the job's log
(lineload.figures.diagnostic), which its refusal names; an accepted batch has none.
"""

import os

from lineload.figures.diagnostic import Refusals, beside
from lineload.io import json_text, load_schema, output_to, write_text
from lineload.rawdata.validation import (
    Problems,
    check_images,
    check_subject_files,
    plausibility_defaults,
)
from lineload.runtime.jobparams import given


def checked_photographs(raw_dir, subjects, limits, digitise, found, diagnose=None):
    """Check the photographs of ``subjects`` (ids), adding their problems to ``found``
    (each refused pair also to ``diagnose``, :meth:`Refusals.note`).

    Returns subject -> the depths of its pairs that passed.  The problems of the sheet
    itself (images/images.csv) are the gathering job's to report: those found with no
    photograph read are left out here.
    """
    if not os.path.isfile(os.path.join(raw_dir, "images", "images.csv")):
        return {}
    schema = load_schema("images")
    sheet_only = Problems()
    check_images(raw_dir, schema, subjects, None, sheet_only, digitise, limits, read=())
    mine = Problems()
    depths = check_images(
        raw_dir, schema, subjects, None, mine, digitise, limits, read=subjects, diagnose=diagnose
    )
    found.errors += [e for e in mine.errors if e not in sheet_only.errors]
    found.warnings += [w for w in mine.warnings if w not in sheet_only.warnings]
    return depths


def check_profiles(
    sheet, output, diagnostic, subjects, input_checks, window_mm, min_points, digitise
):
    """Check the files of ``subjects`` (id -> its sheet row) in the folder of ``sheet``;
    each refused photograph pair is drawn into ``diagnostic`` (a PNG beside the log),
    which is written only when a pair is refused."""
    raw_dir = os.path.dirname(sheet)  # as configured: the messages name it so
    schemas = {name: load_schema(name) for name in ("profiles", "outlines")}
    # the subjects with a profile file (one without is the whole folder's check to report)
    listed = [s for s in subjects if os.path.isfile(os.path.join(raw_dir, "profiles", f"{s}.csv"))]
    found = Problems()
    limits = {**plausibility_defaults(), **input_checks}
    depths_mm, outlines, refused = check_subject_files(
        raw_dir,
        schemas,
        listed,
        {s: subjects[s]["magnification"] for s in listed},
        found,
        limits,
        (window_mm, min_points),
    )
    if os.path.exists(diagnostic):  # a former run's: this run's refusals only
        os.remove(diagnostic)
    refusals = Refusals(diagnostic)
    photographs = checked_photographs(
        raw_dir, list(subjects), limits, digitise, found, refusals.note
    )
    refusals.write()
    checked = {
        "subjects": listed,
        "depths_mm": depths_mm,
        "outlines": outlines,
        "photographs": photographs,
        "refused": [s for s in listed if s in refused],
        "errors": found.errors,
        "warnings": found.warnings,
    }
    write_text(json_text(checked), output)
    print(
        f"{len(listed)} subjects' profiles checked, {len(outlines)} outlines, "
        f"{len(photographs)} photographed: {len(found.errors)} problems -> {output}"
    )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        check_profiles(
            snakemake.input.sheet,
            snakemake.output[0],
            beside(snakemake.log[0]),
            **given(snakemake.params),
        )
