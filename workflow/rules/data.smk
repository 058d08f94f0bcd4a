# Stage 1, data: raw image-unit readings -> tissue mm -> left/right mean.


rule prepare_profiles:
    """Convert a batch of subjects' readings to tissue mm and average the two sides."""
    input:
        code=code_inputs("prepare_profiles.py"),
        profiles=lambda wildcards: [
            f"{RAW}/profiles/{s}.csv" for s in BATCHES[wildcards.batch]
        ],
    output:
        converted=report(
            result("data", "converted", "{batch}.csv"),
            caption="../report/converted.rst",
            category="Data",
            subcategory="Readings in tissue mm",
            labels={"subjects": "{batch}"},
        ),
        averaged=report(
            result("data", "averaged", "{batch}.csv"),
            caption="../report/averaged.rst",
            category="Data",
            subcategory="Left/right averages",
            labels={"subjects": "{batch}"},
        ),
    log:
        result("logs", "prepare_profiles", "{batch}.log"),
    conda:
        ENVIRONMENT
    params:
        subjects=lambda wildcards, input: " ".join(
            f"--subject {s} {SUBJECTS[s]['magnification']!r} {shlex.quote(path)}"
            for s, path in zip(BATCHES[wildcards.batch], input.profiles, strict=True)
        ),
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.subjects}"
        " --converted {output.converted:q} --averaged {output.averaged:q} > {log:q} 2>&1"


rule prepare_outline:
    """Convert one subject's traced outlines (Figure 1) to tissue mm."""
    input:
        code=code_inputs("prepare_outline.py"),
        outline=f"{RAW}/outlines/{{subject}}.csv",
    output:
        result("data", "outlines", "{subject}.csv"),
    log:
        result("logs", "prepare_outline", "{subject}.log"),
    conda:
        ENVIRONMENT
    params:
        magnification=lambda wildcards: repr(
            SUBJECTS[wildcards.subject]["magnification"]
        ),
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} --subject {wildcards.subject}"
        " --magnification {params.magnification} --outline {input.outline:q}"
        " --output {output:q} > {log:q} 2>&1"
