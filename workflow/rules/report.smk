# Stage 5, report: the provenance record of the build.


rule provenance:
    """Hash every raw input and record config, software versions and git commit."""
    input:
        code=code_inputs("write_provenance.py"),
        raw=raw_files(),
        # built last, so the record is rewritten whenever any output is
        outputs=[
            rules.fits_table.output,
            rules.sensitivity_tables.output,
            FIGURE_OUTPUTS,
            TABLE_OUTPUTS,
        ],
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
        raw=lambda wildcards, input: str(Path(input.raw[0]).parent),
        config_json=json.dumps(config, sort_keys=True),
        # the repository holding workflow/scripts/write_provenance.py
        source_dir=lambda wildcards, input: str(Path(input.code[0]).parents[2]),
    shell:
        "$LINELOAD_PYTHON {input.code[0]:q} --raw-dir {params.raw:q}"
        " --config-json {params.config_json:q}"
        " --source-dir {params.source_dir:q} --output {output:q} {input.raw:q} > {log:q} 2>&1"


rule rulegraph:
    """Draw the graph of rules (not part of the default target: it runs Snakemake itself)."""
    input:
        code=code_inputs("make_rulegraph.py"),
        # the graph is drawn for this dataset (its figures depend on the species present)
        sheet=f"{RAW}/subjects.csv",
    output:
        dot=result("rulegraph", "rulegraph.dot"),
        png=result("rulegraph", "rulegraph.png"),
        pdf=result("rulegraph", "rulegraph.pdf"),
    log:
        result("logs", "rulegraph.log"),
    conda:
        ENVIRONMENT
    params:
        snakefile=workflow.main_snakefile,
        raw=lambda wildcards, input: str(Path(input.sheet).parent),
        results=lambda wildcards, output: str(Path(output.dot).parents[1]),
    shell:
        "$LINELOAD_PYTHON -m snakemake --snakefile {params.snakefile:q} --rulegraph dot"
        " --nolock --quiet all --config raw_data={params.raw:q} results={params.results:q}"
        " > {output.dot:q} 2> {log:q}"
        " && $LINELOAD_PYTHON {input.code[0]:q} --dot {output.dot:q} --png {output.png:q}"
        " --pdf {output.pdf:q} >> {log:q} 2>&1"
