# Stage 2b, mechanics: what the fitted shapes and the optional force readings say
# about the membrane (pre-tension, stiffness, pre-strain; lineload/mechanics.py).


rule mechanics:
    """Load angle and strain of each trial's exact arc; a subject's forces fitted by N0 + E eps."""
    input:
        fits=rules.fits_table.output[0],
        forces=FORCES,
        code=code("fit_mechanics.py"),
    output:
        subjects=result("tables", "mechanics.csv"),
        trials=result("tables", "mechanics_trials.csv"),
    log:
        result("logs", "mechanics.log"),
    benchmark:
        result("benchmarks", "mechanics.tsv")
    priority: PRIORITY["mechanics"]
    conda:
        ENVIRONMENT
    params:
        contact_length_mm=CONTACT_LENGTH_MM,
        force_sd_N=config["mechanics"]["force_sd_N"],
    script:
        "../scripts/fit_mechanics.py"
