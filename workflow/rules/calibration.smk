# Calibration (not part of the default build): do the intervals cover the truth at their
# nominal rate, and how often does each claim's rule reach the right verdict, on simulated
# data with the errors real digitising makes - in the reconstruction's world and in worlds
# where a claim only just fails?  Minutes, seeded; the tables it writes are
# kept in the repository (docs/calibration/).


rule coverage_block:
    """Coverage of the fits' 95 % intervals in one scenario of errors (its index in
    lineload.simulation.coverage.SCENARIOS), every model, on simulated datasets."""
    input:
        code=code("run_coverage_block.py"),
    output:
        temp(result("calibration", "coverage_blocks", "{scenario}.csv")),
    log:
        result("logs", "coverage_block", "{scenario}.log"),
    benchmark:
        result("benchmarks", "coverage_block", "{scenario}.tsv")
    wildcard_constraints:
        scenario=r"[0-9]+",
    conda:
        ENVIRONMENT
    params:
        scenario=lambda w: int(w.scenario),
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["datasets"],
    script:
        "../scripts/run_coverage_block.py"


rule coverage:
    """Coverage of the fits' 95 % intervals on simulated datasets, per model and scenario
    of errors (those the fit assumes, and worlds where its priors are wrong). Gathers
    the scenarios' blocks."""
    input:
        blocks=lambda w: expand(
            rules.coverage_block.output[0], scenario=coverage_blocks()
        ),
        code=code("run_coverage.py"),
    output:
        trials=result("calibration", "coverage_trials.csv"),
        summary=result("calibration", "coverage.csv"),
        markdown=result("calibration", "coverage.md"),
    log:
        result("logs", "coverage.log"),
    benchmark:
        result("benchmarks", "coverage.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["datasets"],
    script:
        "../scripts/run_coverage.py"


rule verdict_calibration:
    """How often each claim's rule says holds, does not hold or cannot be checked, against
    the truth, on reconstructions with fresh digitising errors."""
    input:
        code=code("run_verdict_calibration.py"),
    output:
        datasets=result("calibration", "verdicts_datasets.csv"),
        summary=result("calibration", "verdicts.csv"),
        markdown=result("calibration", "verdicts.md"),
    log:
        result("logs", "verdict_calibration.log"),
    benchmark:
        result("benchmarks", "verdict_calibration.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["verdict_datasets"],
        window_mm=config["fit_window_mm"],
        priors={k: v for k, v in config["noise"].items() if k != "max_trials"},
        max_trials=config["noise"]["max_trials"],
        claims=config["claims"],
        # C13 needs the bending skin's fits
        wall=config["bending"]["wall"],
    script:
        "../scripts/run_verdict_calibration.py"


rule verdict_scenario_block:
    """The verdict calibration's datasets read in one world whose errors are not as
    stated (its index in lineload.simulation.coverage.SCENARIOS), priors as stated."""
    input:
        code=code("run_verdict_scenario_block.py"),
    output:
        temp(result("calibration", "verdict_scenario_blocks", "{scenario}.csv")),
    log:
        result("logs", "verdict_scenario_block", "{scenario}.log"),
    benchmark:
        result("benchmarks", "verdict_scenario_block", "{scenario}.tsv")
    wildcard_constraints:
        scenario=r"[0-9]+",
    conda:
        ENVIRONMENT
    params:
        scenario=lambda w: int(w.scenario),
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["scenario_datasets"],
        window_mm=config["fit_window_mm"],
        priors={k: v for k, v in config["noise"].items() if k != "max_trials"},
        max_trials=config["noise"]["max_trials"],
        claims=config["claims"],
    script:
        "../scripts/run_verdict_scenario_block.py"


rule verdict_scenarios:
    """How often each claim's rule is wrong when the stated priors are wrong (and in the
    coverage study's other misspecified worlds). Gathers the worlds' blocks."""
    input:
        blocks=lambda w: expand(
            rules.verdict_scenario_block.output[0], scenario=coverage_blocks()[1:]
        ),
        code=code("run_verdict_scenarios.py"),
    output:
        datasets=result("calibration", "verdict_scenarios_datasets.csv"),
        summary=result("calibration", "verdict_scenarios.csv"),
        markdown=result("calibration", "verdict_scenarios.md"),
    log:
        result("logs", "verdict_scenarios.log"),
    benchmark:
        result("benchmarks", "verdict_scenarios.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["scenario_datasets"],
    script:
        "../scripts/run_verdict_scenarios.py"


rule boundary_block:
    """One boundary world, both sides, read on one block of datasets."""
    input:
        code=code("run_boundary_block.py"),
    output:
        temp(result("calibration", "boundary_blocks", "{block}.csv")),
    log:
        result("logs", "boundary_block", "{block}.log"),
    benchmark:
        result("benchmarks", "boundary_block", "{block}.tsv")
    wildcard_constraints:
        block=r"[a-z0-9-]+\.[0-9]+",
    conda:
        ENVIRONMENT
    params:
        block=lambda w: w.block,
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["verdict_datasets"],
        block_datasets=config["calibration"]["block_datasets"],
        window_mm=config["fit_window_mm"],
        priors={k: v for k, v in config["noise"].items() if k != "max_trials"},
        max_trials=config["noise"]["max_trials"],
        claims=config["claims"],
    script:
        "../scripts/run_boundary_block.py"


rule boundary_calibration:
    """The verdict of each claim that has a boundary world, either side of that boundary,
    on datasets with fresh errors: how often a rule says "holds" where the claim just
    fails, and "does not hold" where it just holds. Gathers the blocks."""
    input:
        blocks=lambda w: expand(rules.boundary_block.output[0], block=boundary_blocks()),
        code=code("run_boundary_calibration.py"),
    output:
        datasets=result("calibration", "boundary_datasets.csv"),
        summary=result("calibration", "boundary.csv"),
        markdown=result("calibration", "boundary.md"),
    log:
        result("logs", "boundary_calibration.log"),
    benchmark:
        result("benchmarks", "boundary_calibration.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["verdict_datasets"],
    script:
        "../scripts/run_boundary_calibration.py"


rule mechanics_coverage:
    """Coverage of the membrane's N0, E and pre-strain on reconstructions with fresh errors."""
    input:
        code=code("run_mechanics_coverage.py"),
    output:
        subjects=result("calibration", "mechanics_coverage_subjects.csv"),
        summary=result("calibration", "mechanics_coverage.csv"),
        markdown=result("calibration", "mechanics_coverage.md"),
    log:
        result("logs", "mechanics_coverage.log"),
    benchmark:
        result("benchmarks", "mechanics_coverage.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["verdict_datasets"],
        window_mm=config["fit_window_mm"],
        priors={k: v for k, v in config["noise"].items() if k != "max_trials"},
        max_trials=config["noise"]["max_trials"],
        force_sd_N=config["mechanics"]["force_sd_N"],
    script:
        "../scripts/run_mechanics_coverage.py"


rule mechanics_recovery:
    """N0, E and pre-strain recovered from forces of the law the fit inverts and of a
    strain-stiffening membrane, on the same reconstructions."""
    input:
        code=code("run_mechanics_recovery.py"),
    output:
        subjects=result("calibration", "mechanics_recovery_subjects.csv"),
        summary=result("calibration", "mechanics_recovery.csv"),
        markdown=result("calibration", "mechanics_recovery.md"),
    log:
        result("logs", "mechanics_recovery.log"),
    benchmark:
        result("benchmarks", "mechanics_recovery.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        datasets=config["calibration"]["scenario_datasets"],
        window_mm=config["fit_window_mm"],
        priors={k: v for k, v in config["noise"].items() if k != "max_trials"},
        max_trials=config["noise"]["max_trials"],
        force_sd_N=config["mechanics"]["force_sd_N"],
    script:
        "../scripts/run_mechanics_recovery.py"


rule bootstrap:
    """A parametric bootstrap of the data's own fits: do their intervals cover there?"""
    input:
        fits=rules.fits_table.output[0],
        noise=rules.noise.output[0],
        averaged=expand(rules.prepare_profiles.output.averaged, batch=BATCH_IDS),
        code=code("run_bootstrap.py"),
    output:
        trials=result("calibration", "bootstrap_trials.csv"),
        summary=result("calibration", "bootstrap.csv"),
        markdown=result("calibration", "bootstrap.md"),
    log:
        result("logs", "bootstrap.log"),
    benchmark:
        result("benchmarks", "bootstrap.tsv")
    conda:
        ENVIRONMENT
    params:
        seed=config["calibration"]["seed"],
        replicates=config["calibration"]["bootstrap_replicates"],
        window_mm=config["fit_window_mm"],
        notice=lambda wildcards: NOTICE,
    script:
        "../scripts/run_bootstrap.py"


rule calibration:
    """Every calibration: snakemake --cores 2 calibration."""
    input:
        # drawn from the committed tables (docs/calibration): copy the results there first
        GROUP_FILES["calibration"],
        rules.coverage.output,
        rules.verdict_calibration.output,
        rules.verdict_scenarios.output,
        rules.boundary_calibration.output,
        rules.mechanics_coverage.output,
        rules.mechanics_recovery.output,
        rules.bootstrap.output,
