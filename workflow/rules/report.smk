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
        spec=spec(
            "provenance",
            raw_dir=RAW,
            config=config,
            source_dir=str(Path(workflow.basedir).parent),
        ),
        raw=raw_files(),
        # built last, so the record is rewritten whenever any output is; listing every
        # intermediate here also makes each a target of the default build
        outputs=[
            rules.prepare_profiles.output,
            rules.fit_models.output,
            rules.fit_sensitivity.output,
            rules.fits_table.output,
            rules.sensitivity_tables.output,
            rules.fit_tables.output,
            rules.claims_table.output,
            FIGURE_FILES,
        ],
        code=code("write_provenance.py"),
    output:
        report_item(
            result("provenance.json"),
            caption="../report/provenance.rst",
            category="Data",
            labels={"file": "provenance record"},
        ),
    log:
        result("logs", "provenance.log"),
    script:
        "../scripts/write_provenance.py"
