# Stage 2, fits: the three models for each subject and depth, then one table.


rule fit_subject:
    """Fit waterbed (parabola), exact arc and Boussinesq to each depth of one subject."""
    input:
        averaged=result("data", "averaged", "{subject}.csv"),
    output:
        result("fits", "{subject}.csv"),
    params:
        python=PYTHON,
        script=SCRIPTS / "fit_subject.py",
        species=lambda wildcards: SUBJECTS.loc[wildcards.subject, "species"],
        window_mm=config["fit_window_mm"],
    log:
        result("logs", "fit_subject", "{subject}.log"),
    shell:
        "{params.python} {params.script:q} --subject {wildcards.subject}"
        " --species {params.species} --window-mm {params.window_mm}"
        " --averaged {input.averaged:q} --output {output:q} > {log:q} 2>&1"


rule fits_table:
    """Collect every subject's fits into results/tables/fits.csv (subject-sheet order)."""
    input:
        expand(result("fits", "{subject}.csv"), subject=SUBJECT_IDS),
    output:
        result("tables", "fits.csv"),
    params:
        python=PYTHON,
        script=SCRIPTS / "concat_tables.py",
    log:
        result("logs", "fits_table.log"),
    shell:
        "{params.python} {params.script:q} --output {output:q} {input:q} > {log:q} 2>&1"
