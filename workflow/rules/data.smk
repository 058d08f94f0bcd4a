# Stage 1, data: raw image-unit readings -> tissue mm -> left/right mean.


rule prepare_profile:
    """Convert one subject's readings to tissue mm and average the two sides."""
    input:
        profile=f"{RAW}/profiles/{{subject}}.csv",
    output:
        converted=report(
            result("data", "converted", "{subject}.csv"),
            caption="../report/converted.rst",
            category="Data",
            subcategory="Readings in tissue mm",
            labels={"subject": "{subject}"},
        ),
        averaged=report(
            result("data", "averaged", "{subject}.csv"),
            caption="../report/averaged.rst",
            category="Data",
            subcategory="Left/right averages",
            labels={"subject": "{subject}"},
        ),
    log:
        result("logs", "prepare_profile", "{subject}.log"),
    conda:
        ENVIRONMENT
    params:
        python=PYTHON,
        script=SCRIPTS / "prepare_profile.py",
        magnification=lambda wildcards: SUBJECTS.loc[wildcards.subject, "magnification"],
    shell:
        "{params.python} {params.script:q} --subject {wildcards.subject}"
        " --magnification {params.magnification} --profile {input.profile:q}"
        " --converted {output.converted:q} --averaged {output.averaged:q} > {log:q} 2>&1"


rule prepare_outline:
    """Convert one subject's traced outlines (Figure 1) to tissue mm."""
    input:
        outline=f"{RAW}/outlines/{{subject}}.csv",
    output:
        result("data", "outlines", "{subject}.csv"),
    log:
        result("logs", "prepare_outline", "{subject}.log"),
    conda:
        ENVIRONMENT
    params:
        python=PYTHON,
        script=SCRIPTS / "prepare_outline.py",
        magnification=lambda wildcards: SUBJECTS.loc[wildcards.subject, "magnification"],
    shell:
        "{params.python} {params.script:q} --subject {wildcards.subject}"
        " --magnification {params.magnification} --outline {input.outline:q}"
        " --output {output:q} > {log:q} 2>&1"
