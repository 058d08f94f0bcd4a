# Srinivasan (1989), "Surface deflection of primate fingertip under line load",
# rebuilt from the raw digitised profiles.  Stages, in the order data flows:
#   common  - config and raw inputs validated before anything runs
#   data    - image units -> tissue mm -> left/right mean per subject
#   fits    - waterbed (parabola and exact arc) and Boussinesq fits, fit table
#   figures - the paper's seven figures and the supplementary ones
#   tables  - fit tables, per-species summary and the claims table


configfile: "config/config.yaml"


include: "workflow/rules/common.smk"
include: "workflow/rules/data.smk"
include: "workflow/rules/fits.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/tables.smk"


rule all:
    """Default target: everything the workflow makes."""
    default_target: True
    input:
        rules.fits_table.output,
        FIGURE_OUTPUTS,
        TABLE_OUTPUTS,


rule fits:
    """Only the fit table (and what it needs)."""
    input:
        rules.fits_table.output,
