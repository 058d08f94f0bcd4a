"""Rule digitise: a batch of photographed subjects' readings from their photographs.

Each pair is read with lineload.rawdata.photographs.digitise_pair, one after another
(lineload.rawdata.digitising.digitise_batch); the readings are written in the profile
contract's form after a subject column (image units: tissue mm times the subject's
magnification) and checked as a raw profile file is, and a record of how well each
trial was digitised is written beside them, with a quality figure.  A photograph that
cannot be read stops the job with one line naming it and the PNG beside the job's
log that draws the pair as the digitiser saw it.
"""

import os
import sys

from lineload.figures.data import figure_digitised
from lineload.figures.diagnostic import beside
from lineload.figures.style import save_figure
from lineload.io import json_text, load_schema, output_to, write_text
from lineload.rawdata.digitising import digitise_batch, profile_text, subject_profile
from lineload.rawdata.photographs import ImageError
from lineload.rawdata.validation import InputError, check_thin_trials, read_columns, read_table
from lineload.runtime.jobparams import given


def digitise(sheet, batch, subjects, settings, window_mm, notice, output, diagnostic):
    """Digitise every pair of the batch's ``subjects``; write their readings, the
    quality records and the quality figure (a refused pair is drawn into ``diagnostic``,
    beside the log, and nothing else is written)."""
    if os.path.exists(diagnostic):  # a former run's: this run's refusal only
        os.remove(diagnostic)
    images = read_table(sheet, load_schema("images"))  # checked already: no problem left
    folder = os.path.dirname(sheet)
    truth_path = os.path.join(folder, "truth.csv")
    truth = read_table(truth_path, load_schema("truth")) if os.path.isfile(truth_path) else None
    done = digitise_batch(
        os.path.dirname(folder),
        images,
        subjects,
        settings,
        window_mm,
        truth,
        diagnostic=diagnostic,
    )
    write_text(profile_text(done.rows), output.profile)
    # the readings pass the checks a raw profile file does
    profile = read_columns(output.profile, load_schema("profiles"))
    for subject, about in subjects.items():
        check_thin_trials(
            subject_profile(profile, subject),
            output.profile,
            float(about["magnification"]),
            settings["reach_mm"],
            1,
        )
    write_text(json_text({"batch": batch, "subjects": done.records}), output.quality)
    label = next(iter(subjects.values()))["label"] if len(subjects) == 1 else batch
    save_figure(figure_digitised(label, done.drawn, notice), output.pdf, output.png, dpi=200)


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        values = given(snakemake.params)
        try:
            digitise(
                snakemake.input.sheet,
                values["batch"],
                values["subjects"],
                values["settings"],
                float(values["window_mm"]),
                values["notice"],
                snakemake.output,
                beside(snakemake.log[0]),
            )
        except (ImageError, InputError) as error:
            print(error)
            sys.__stderr__.write(f"Error: {error}\n")
            sys.exit(1)
