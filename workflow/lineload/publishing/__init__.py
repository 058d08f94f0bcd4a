"""Publishing the results: tables, the article, the report's pages, the crate and bundle.

Modules
-------
tables
    The fit, claim and summary tables as text.
article
    The facts the article's text is written from.
reportpages
    The pages of the Snakemake report.
crate
    The run's RO-Crate.
bundle
    The archive of a results folder.
citation
    How the project is cited.
provenance
    What a build read and ran: hashes of the raw files, versions, the git state.
"""
