# Stage 5, report: the provenance record of the build.


def raw_files():
    """Every raw input the build read: subject sheet, profiles, outlines, notice."""
    files = [f"{RAW}/subjects.csv"]
    files += [f"{RAW}/profiles/{s}.csv" for s in SUBJECT_IDS]
    files += [f"{RAW}/outlines/{s}.csv" for s in DATASET["outlines"]]
    if Path(RAW, "NOTICE.txt").is_file():
        files.append(f"{RAW}/NOTICE.txt")
    return files


rule provenance:
    """Hash every raw input and record config, software versions and git commit."""
    input:
        raw=raw_files(),
        # built last, so the record is rewritten whenever any output is
        outputs=[rules.fits_table.output, FIGURE_OUTPUTS, TABLE_OUTPUTS],
    output:
        result("provenance.json"),
    params:
        python=PYTHON,
        script=SCRIPTS / "write_provenance.py",
        config_json=json.dumps(config, sort_keys=True),
        source_dir=workflow.basedir,
    log:
        result("logs", "provenance.log"),
    shell:
        "{params.python} {params.script:q} --raw-dir {RAW:q} --config-json {params.config_json:q}"
        " --source-dir {params.source_dir:q} --output {output:q} {input.raw:q} > {log:q} 2>&1"
