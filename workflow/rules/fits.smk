# Stage 2, fits: every model for each subject and depth, then one table; the
# sensitivity refits beside them.


rule noise:
    """Measure the digitising noise from every trial's left-right differences."""
    input:
        averaged=expand(rules.prepare_profiles.output.averaged, batch=BATCH_IDS),
        # each digitise batch's records: its trials' registration and own reading errors
        quality=expand(rules.digitise.output.quality, batch=list(DIGITISE_BATCHES)),
        code=code("estimate_noise.py"),
    output:
        result("tables", "noise.csv"),
    log:
        result("logs", "noise.log"),
    benchmark:
        result("benchmarks", "noise.tsv")
    priority: PRIORITY["noise"]
    conda:
        ENVIRONMENT
    params:
        priors={k: v for k, v in config["noise"].items() if k != "max_trials"},
        max_trials=config["noise"]["max_trials"],
        window_mm=config["fit_window_mm"],
    script:
        "../scripts/estimate_noise.py"


rule fit_models:
    """Fit the waterbed (paper's, shifted, exact arc) and Boussinesq to each trial of a batch."""
    input:
        averaged=rules.prepare_profiles.output.averaged,
        noise=rules.noise.output[0],
        code=code("fit_models.py"),
    output:
        result("fits", "{batch}.csv"),
    log:
        result("logs", "fit_models", "{batch}.log"),
    benchmark:
        result("benchmarks", "fit_models", "{batch}.tsv")
    priority: PRIORITY["fit_models"]
    conda:
        ENVIRONMENT
    params:
        subjects=batch_subjects,
        window_mm=config["fit_window_mm"],
        other_windows_mm=config["sensitivity"]["windows_mm"],
    script:
        "../scripts/fit_models.py"


rule fits_table:
    """Collect every batch's fits into results/tables/fits.csv (subject-sheet order)."""
    input:
        tables=expand(rules.fit_models.output[0], batch=BATCH_IDS),
        code=code("concat_tables.py"),
    output:
        result("tables", "fits.csv"),
    log:
        result("logs", "fits_table.log"),
    benchmark:
        result("benchmarks", "fits_table.tsv")
    priority: PRIORITY["fits_table"]
    conda:
        ENVIRONMENT
    script:
        "../scripts/concat_tables.py"


# The bending skin (the paper's closing suggestion, lineload.bending): a table of its
# own, beside the fit table, so that the `fits` target stays the paper's models.
rule fit_bending:
    """Fit the bending skin's L and bending length to each trial of a batch."""
    input:
        averaged=rules.prepare_profiles.output.averaged,
        noise=rules.noise.output[0],
        code=code("fit_bending.py"),
    output:
        result("fits", "bending", "{batch}.csv"),
    log:
        result("logs", "fit_bending", "{batch}.log"),
    benchmark:
        result("benchmarks", "fit_bending", "{batch}.tsv")
    priority: PRIORITY["fit_bending"]
    conda:
        ENVIRONMENT
    params:
        subjects=batch_subjects,
        window_mm=config["fit_window_mm"],
        wall=config["bending"]["wall"],
    script:
        "../scripts/fit_bending.py"


rule bending_table:
    """Collect every batch's bending fits into results/tables/bending.csv."""
    input:
        tables=expand(rules.fit_bending.output[0], batch=BATCH_IDS),
        code=code("concat_tables.py"),
    output:
        result("tables", "bending.csv"),
    log:
        result("logs", "bending_table.log"),
    benchmark:
        result("benchmarks", "bending_table.tsv")
    priority: PRIORITY["bending_table"]
    conda:
        ENVIRONMENT
    script:
        "../scripts/concat_tables.py"


# The elastic fingertip of the later literature (docs/elastic-finger.md), fitted by
# interpolation in the kept solution library (the default build never runs the solver):
# a table of its own, so that the `fits` target stays the paper's models.
rule elastic_fits:
    """Fit the homogeneous and the layered elastic finger to each trial, from the library."""
    input:
        averaged=expand(rules.prepare_profiles.output.averaged, batch=BATCH_IDS),
        library=os.path.relpath(REPOSITORY / config["elastic"]["library_file"]),
        noise=rules.noise.output[0],
        code=code("fit_elastic.py"),
    output:
        result("tables", "elastic_fits.csv"),
    log:
        result("logs", "elastic_fits.log"),
    benchmark:
        result("benchmarks", "elastic_fits.tsv")
    priority: PRIORITY["elastic_fits"]
    conda:
        ENVIRONMENT
    params:
        batches=[{s: SUBJECTS[s] for s in BATCHES[b]} for b in BATCH_IDS],
        window_mm=config["fit_window_mm"],
    script:
        "../scripts/fit_elastic.py"


rule fit_sensitivity:
    """Refit a batch with other windows, W0 free, in measured coordinates; U shift and reach."""
    input:
        averaged=rules.prepare_profiles.output.averaged,
        code=code("fit_sensitivity.py"),
    output:
        sensitivity=result("fits", "sensitivity", "{batch}.csv"),
        checks=result("fits", "checks", "{batch}.csv"),
    log:
        result("logs", "fit_sensitivity", "{batch}.log"),
    benchmark:
        result("benchmarks", "fit_sensitivity", "{batch}.tsv")
    priority: PRIORITY["fit_sensitivity"]
    conda:
        ENVIRONMENT
    params:
        subjects=batch_subjects,
        window_mm=config["fit_window_mm"],
        windows_mm=config["sensitivity"]["windows_mm"],
        reach_fraction=config["sensitivity"]["reach_fraction"],
    script:
        "../scripts/fit_sensitivity.py"


rule sensitivity_tables:
    """Collect the refits and per-trial checks; summarise them in Markdown."""
    input:
        sensitivity=expand(rules.fit_sensitivity.output.sensitivity, batch=BATCH_IDS),
        checks=expand(rules.fit_sensitivity.output.checks, batch=BATCH_IDS),
        code=code("sensitivity_tables.py"),
    output:
        sensitivity=result("tables", "sensitivity.csv"),
        checks=result("tables", "trial_checks.csv"),
        markdown=result("tables", "sensitivity.md"),
    log:
        result("logs", "sensitivity_tables.log"),
    benchmark:
        result("benchmarks", "sensitivity_tables.tsv")
    priority: PRIORITY["sensitivity_tables"]
    conda:
        ENVIRONMENT
    params:
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/sensitivity_tables.py"
