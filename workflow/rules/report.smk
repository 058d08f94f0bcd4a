# Stage 5, report: the provenance record of the build.


rule provenance:
    """Hash every raw input and record config, software versions and git commit."""
    input:
        raw=raw_files(),
        # built last, so the record is rewritten whenever any output is
        outputs=[rules.fits_table.output, FIGURE_OUTPUTS, TABLE_OUTPUTS],
    output:
        report(
            result("provenance.json"),
            caption="../report/provenance.rst",
            category="Data",
            labels={"file": "provenance record"},
        ),
    log:
        result("logs", "provenance.log"),
    conda:
        ENVIRONMENT
    params:
        python=PYTHON,
        script=SCRIPTS / "write_provenance.py",
        config_json=json.dumps(config, sort_keys=True),
        source_dir=workflow.basedir,
    shell:
        "{params.python} {params.script:q} --raw-dir {RAW:q} --config-json {params.config_json:q}"
        " --source-dir {params.source_dir:q} --output {output:q} {input.raw:q} > {log:q} 2>&1"
