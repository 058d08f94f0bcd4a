# Stage 2, fits: the three models for each subject and depth, then one table.


rule fit_models:
    """Fit waterbed (parabola), exact arc and Boussinesq to each trial of a batch."""
    input:
        code=code_inputs("fit_models.py"),
        averaged=result("data", "averaged", "{batch}.csv"),
    output:
        result("fits", "{batch}.csv"),
    log:
        result("logs", "fit_models", "{batch}.log"),
    benchmark:
        result("benchmarks", "fit_models", "{batch}.tsv")
    conda:
        ENVIRONMENT
    params:
        subjects=lambda wildcards: subject_species_args(wildcards.batch),
        window_mm=config["fit_window_mm"],
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.subjects} --window-mm {params.window_mm}"
        " --averaged {input.averaged:q} --output {output:q} > {log:q} 2>&1"


rule fits_table:
    """Collect every subject's fits into results/tables/fits.csv (subject-sheet order)."""
    input:
        code=code_inputs("concat_tables.py"),
        tables=expand(result("fits", "{batch}.csv"), batch=BATCH_IDS),
    output:
        report(
            result("tables", "fits.csv"),
            caption="../report/fits.rst",
            category="Fits",
            labels={"table": "fits per subject and depth"},
        ),
    log:
        result("logs", "fits_table.log"),
    benchmark:
        result("benchmarks", "fits_table.tsv")
    conda:
        ENVIRONMENT
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} --output {output:q} {input.tables:q} > {log:q} 2>&1"


rule fit_sensitivity:
    """Refit a batch with other windows, W0 free and the exact arc; U shift and reach."""
    input:
        code=code_inputs("fit_sensitivity.py"),
        averaged=result("data", "averaged", "{batch}.csv"),
    output:
        sensitivity=result("fits", "sensitivity", "{batch}.csv"),
        checks=result("fits", "checks", "{batch}.csv"),
    log:
        result("logs", "fit_sensitivity", "{batch}.log"),
    benchmark:
        result("benchmarks", "fit_sensitivity", "{batch}.tsv")
    priority: 1
    conda:
        ENVIRONMENT
    params:
        subjects=lambda wildcards: subject_species_args(wildcards.batch),
        window_mm=config["fit_window_mm"],
        windows_mm=" ".join(
            "whole" if w is None else str(w)
            for w in config["sensitivity"]["windows_mm"]
        ),
        reach_fraction=config["sensitivity"]["reach_fraction"],
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} {params.subjects} --window-mm {params.window_mm}"
        " --windows-mm {params.windows_mm} --reach-fraction {params.reach_fraction}"
        " --averaged {input.averaged:q} --sensitivity {output.sensitivity:q}"
        " --checks {output.checks:q} > {log:q} 2>&1"


rule sensitivity_tables:
    """Collect the refits and per-trial checks; summarise them in Markdown."""
    input:
        code=code_inputs("sensitivity_tables.py"),
        sensitivity=expand(
            result("fits", "sensitivity", "{batch}.csv"), batch=BATCH_IDS
        ),
        checks=expand(result("fits", "checks", "{batch}.csv"), batch=BATCH_IDS),
    output:
        sensitivity=report(
            result("tables", "sensitivity.csv"),
            caption="../report/sensitivity.rst",
            category="Supplement",
            labels={"table": "sensitivity refits"},
        ),
        checks=report(
            result("tables", "trial_checks.csv"),
            caption="../report/trial_checks.rst",
            category="Supplement",
            labels={"table": "U shift and reach per trial"},
        ),
        markdown=result("tables", "sensitivity.md"),
    log:
        result("logs", "sensitivity_tables.log"),
    benchmark:
        result("benchmarks", "sensitivity_tables.tsv")
    priority: 1
    conda:
        ENVIRONMENT
    params:
        notice=NOTICE,
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} --notice={params.notice:q}"
        " --sensitivity-out {output.sensitivity:q} --checks-out {output.checks:q}"
        " --markdown {output.markdown:q} --sensitivity {input.sensitivity:q}"
        " --checks {input.checks:q} > {log:q} 2>&1"
