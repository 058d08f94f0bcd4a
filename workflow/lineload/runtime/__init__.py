"""What the Snakemake workflow needs while it plans a run (standard library only at import).

Modules
-------
startup
    Checks of the config and the folders before any job runs; cleanup of a refused run.
settings
    The config with the schema's defaults filled in.
jobparams
    The values each job is given through ``params:``.
codedeps
    Which package modules each workflow script runs (declared as the rule's inputs).
buildlock
    One build per results folder.
interrupt
    Stopping cleanly on SIGTERM.
lazy
    Deferred imports for parse time.
"""
