# Calibration (not part of the default build): do the intervals cover the truth at their
# nominal rate on simulated data with the errors real digitising makes?  Minutes, seeded;
# the table it writes is kept in the repository (docs/calibration/).


rule calibration:
    """Coverage of the fits' 95 % intervals on simulated datasets, per model and error kind."""
    input:
        spec=spec(
            "calibration",
            seed=config["calibration"]["seed"],
            datasets=config["calibration"]["datasets"],
        ),
        code=code("run_coverage.py"),
    output:
        trials=result("calibration", "coverage_trials.csv"),
        summary=result("calibration", "coverage.csv"),
        markdown=result("calibration", "coverage.md"),
    log:
        result("logs", "calibration.log"),
    benchmark:
        result("benchmarks", "calibration.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/run_coverage.py"
