# Srinivasan (1989), "Surface deflection of primate fingertip under line load",
# rebuilt from the raw digitised profiles.  Stages, in the order data flows:
#   common  - config and raw inputs validated before anything runs
#   data    - image units -> tissue mm -> left/right mean per subject
#   fits    - waterbed (parabola and exact arc) and Boussinesq fits, fit table
#   figures - the paper's seven figures and the supplementary ones
#   tables  - fit tables, per-species summary and the claims table
#   report  - provenance record (input hashes, config, versions, commit)


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"


# subject ids name files and go on command lines: the same rule as subjects.schema.yaml;
# a batch is named after its first subject, plus a sign and a count when it holds more
wildcard_constraints:
    subject="[A-Za-z0-9][A-Za-z0-9_-]*",
    batch="[A-Za-z0-9][A-Za-z0-9_-]*([+][0-9]{1,9})?",


include: "workflow/rules/data.smk"
include: "workflow/rules/fits.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/tables.smk"
include: "workflow/rules/report.smk"


rule all:
    """Default target: everything the workflow makes."""
    default_target: True
    input:
        rules.fits_table.output,
        rules.sensitivity_tables.output,
        FIGURE_OUTPUTS,
        TABLE_OUTPUTS,
        rules.provenance.output,


rule fits:
    """Only the fit table (and what it needs)."""
    input:
        rules.fits_table.output,
