# Stage 1, data: raw image-unit readings -> tissue mm -> left/right mean.


rule prepare_profile:
    """Convert one subject's readings to tissue mm and average the two sides."""
    input:
        profile=f"{RAW}/profiles/{{subject}}.csv",
    output:
        converted=result("data", "converted", "{subject}.csv"),
        averaged=result("data", "averaged", "{subject}.csv"),
    params:
        python=PYTHON,
        script=SCRIPTS / "prepare_profile.py",
        magnification=lambda wildcards: SUBJECTS.loc[wildcards.subject, "magnification"],
    log:
        result("logs", "prepare_profile", "{subject}.log"),
    shell:
        "{params.python} {params.script:q} --subject {wildcards.subject}"
        " --magnification {params.magnification} --profile {input.profile:q}"
        " --converted {output.converted:q} --averaged {output.averaged:q} > {log:q} 2>&1"
