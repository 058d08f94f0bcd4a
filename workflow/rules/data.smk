# Stage 1, data: raw image-unit readings -> tissue mm -> left/right mean.


rule prepare_profiles:
    """Convert a batch of subjects' readings to tissue mm and average the two sides."""
    input:
        spec=batch_specs("prepare_profiles"),
        profiles=lambda wildcards: [
            f"{RAW}/profiles/{s}.csv" for s in BATCHES[wildcards.batch]
        ],
        code=code("prepare_profiles.py"),
    output:
        converted=report_item(
            result("data", "converted", "{batch}.csv"),
            caption="../report/converted.rst",
            category="Data",
            subcategory="Readings in tissue mm (CSV)",
            labels={"subjects": "{batch}"},
        ),
        averaged=report_item(
            result("data", "averaged", "{batch}.csv"),
            caption="../report/averaged.rst",
            category="Data",
            subcategory="Left/right averages (CSV)",
            labels={"subjects": "{batch}"},
        ),
    log:
        result("logs", "prepare_profiles", "{batch}.log"),
    benchmark:
        result("benchmarks", "prepare_profiles", "{batch}.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/prepare_profiles.py"


rule prepare_outline:
    """Convert one subject's traced outlines (Figure 1) to tissue mm."""
    input:
        spec=subject_specs("prepare_outline", DATASET["outlines"]),
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
    script:
        "../scripts/prepare_outline.py"
