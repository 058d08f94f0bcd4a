# Stage 1, data: every raw file checked; raw image-unit readings -> tissue mm ->
# left/right mean.  Every job that reads raw data waits for the check
# (checked_raw_data, common.smk), so a refused folder leaves nothing but its log.


rule check_profiles:
    """Check a batch of subjects' profile, outline and photograph files (the large part
    of the check: each photograph is read here, once)."""
    input:
        sheet=f"{RAW}/subjects.csv",
        profiles=lambda wildcards: [
            RAW_FILES["profiles"][f"{s}.csv"]
            for s in BATCHES[wildcards.batch]
            if f"{s}.csv" in RAW_FILES["profiles"]
        ],
        outlines=lambda wildcards: [
            RAW_FILES["outlines"][f"{s}.csv"]
            for s in BATCHES[wildcards.batch]
            if f"{s}.csv" in RAW_FILES["outlines"]
        ],
        # the photographs' sheet (and the truth, which it is checked against) and the
        # batch's photographs that are there (one that is not is the check's to report)
        images=[
            RAW_FILES["images"][n]
            for n in ("images.csv", "truth.csv")
            if n in RAW_FILES["images"]
        ],
        photographs=lambda wildcards: [
            f for s in BATCHES[wildcards.batch] for f in PHOTOGRAPHS.get(s, [])
        ],
        code=code("check_profiles.py"),
    output:
        result("data", "checked", "{batch}.json"),
    log:
        # (and, beside it, {batch}.png, only where a photograph pair is refused: the
        # pairs as the digitiser saw them, named by the refusal; not declared, so
        # neither Snakemake nor a refused folder's clean-up removes it, nor does an
        # accepted batch get an empty one)
        result("logs", "check_profiles", "{batch}.log"),
    benchmark:
        result("benchmarks", "check_profiles", "{batch}.tsv")
    conda:
        ENVIRONMENT
    params:
        subjects=batch_subjects,
        input_checks=config["input_checks"],
        window_mm=config["fit_window_mm"],
        min_points=config["min_points_in_window"],
        # each pair is read as its job will read it: one that cannot be is refused here
        digitise=config["digitise"],
    script:
        "../scripts/check_profiles.py"


checkpoint check_raw_data:
    """Check every raw file against the data contract: every problem at once, one line each.

    The profiles and outlines are read batch by batch (check_profiles); this job checks
    the rest of the folder and gathers their findings."""
    input:
        sheet=f"{RAW}/subjects.csv",
        batches=expand(rules.check_profiles.output[0], batch=BATCH_IDS),
        # every file of the folder, a stray one too (the check warns about it)
        files=RAW_FILES["all"],
        code=code("check_raw_data.py"),
    output:
        result("data", "raw_check.json"),
    log:
        result("logs", "check_raw_data.log"),
    benchmark:
        result("benchmarks", "check_raw_data.tsv")
    conda:
        ENVIRONMENT
    params:
        input_checks=config["input_checks"],
        window_mm=config["fit_window_mm"],
        min_points=config["min_points_in_window"],
    script:
        "../scripts/check_raw_data.py"


# A raw file put back with its old time since the last check (cp -p, rsync, a backup):
# Snakemake would not see it; say which, and how to have its results made again.
if workflow.is_main_process:
    for path in startup.restored_files(
        RAW_FILES["all"],
        RAW,
        startup.check_record(rules.check_raw_data.log[0]),
        rules.check_raw_data.output[0],
    ):
        print(
            f"Warning: {path} differs from the file checked last time but is not newer than "
            "the results, so Snakemake would keep them (was it put back with its old time, by "
            f"cp -p, rsync or a backup?); run `touch {path}` and build again to redo them",
            file=sys.stderr,
        )


rule digitise:
    """Read a batch of photographed subjects' profiles from their rest and loaded
    photographs, one pair at a time."""
    input:
        checked=checked_raw_data,
        sheet=f"{RAW}/images/images.csv",
        photographs=lambda wildcards: [
            f for s in DIGITISE_BATCHES[wildcards.batch] for f in PHOTOGRAPHS[s]
        ],
        # the truth, where the folder gives it (images/truth.csv): for the quality record
        truth=(
            [RAW_FILES["images"]["truth.csv"]]
            if "truth.csv" in RAW_FILES["images"]
            else []
        ),
        code=code("digitise.py"),
    output:
        profile=result("digitised", "{batch}.csv"),
        quality=result("digitised", "{batch}.json"),
        pdf=result("digitised", "{batch}.pdf"),
        png=report_item(
            result("digitised", "{batch}.png"),
            caption="../report/digitised.rst",
            category="Data",
            subcategory="Photographs digitised",
            labels={"subjects": "{batch}"},
        ),
    log:
        # (and {batch}.png beside it where a pair is refused, as check_profiles does)
        result("logs", "digitise", "{batch}.log"),
    benchmark:
        result("benchmarks", "digitise", "{batch}.tsv")
    conda:
        ENVIRONMENT
    params:
        batch=lambda wildcards: wildcards.batch,
        subjects=lambda wildcards: {
            s: SUBJECTS[s] for s in DIGITISE_BATCHES[wildcards.batch]
        },
        settings=config["digitise"],
        window_mm=config["fit_window_mm"],
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/digitise.py"


rule prepare_profiles:
    """Convert a batch of subjects' readings to tissue mm and average the two sides."""
    input:
        checked=checked_raw_data,
        profiles=profile_files,
        code=code("prepare_profiles.py"),
    output:
        converted=result("data", "converted", "{batch}.csv"),
        averaged=result("data", "averaged", "{batch}.csv"),
    log:
        result("logs", "prepare_profiles", "{batch}.log"),
    benchmark:
        result("benchmarks", "prepare_profiles", "{batch}.tsv")
    priority: PRIORITY["prepare_profiles"]
    conda:
        ENVIRONMENT
    params:
        subjects=batch_subjects,
    script:
        "../scripts/prepare_profiles.py"


rule prepare_outline:
    """Convert one subject's traced outlines (Figure 1) to tissue mm."""
    input:
        checked=checked_raw_data,
        outline=f"{RAW}/outlines/{{subject}}.csv",
        code=code("prepare_outline.py"),
    output:
        result("data", "outlines", "{subject}.csv"),
    log:
        result("logs", "prepare_outline", "{subject}.log"),
    benchmark:
        result("benchmarks", "prepare_outline", "{subject}.tsv")
    conda:
        ENVIRONMENT
    params:
        subject=lambda wildcards: wildcards.subject,
        magnification=lambda wildcards: SUBJECTS[wildcards.subject]["magnification"],
    script:
        "../scripts/prepare_outline.py"
