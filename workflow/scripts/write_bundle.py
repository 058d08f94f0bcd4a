"""Rule bundle: the run crate, without the logs, as one zip with SHA256SUMS."""

import os
from pathlib import Path

from lineload.io import output_to, read_json
from lineload.publishing.bundle import write_bundle
from lineload.publishing.citation import citation_or_default
from lineload.publishing.crate import METADATA, build_crate, crate_json


def bundle(files, rules, provenance, citation, crate_metadata, output, date):
    """Write the bundle: every file of the run crate but the logs (they name the folders
    of the build), with a crate that lists exactly those; say what it holds."""
    root = Path(crate_metadata).parent
    built, members = build_crate(
        files, rules, read_json(provenance), citation_or_default(citation), root, logs=False
    )
    members[METADATA] = crate_json(built).encode()
    write_bundle(members, output, date)
    print(f"{output}: {len(members)} files and SHA256SUMS, {os.path.getsize(output)} bytes")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        bundle(
            snakemake.params.files,
            snakemake.params.rules,
            snakemake.input.provenance,
            snakemake.input.citation,
            snakemake.input.crate,
            snakemake.output[0],
            date=snakemake.params.date,
        )
