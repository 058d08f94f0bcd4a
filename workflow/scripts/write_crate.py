"""Rule crate: the run as a Workflow Run RO-Crate in the results folder.

The raw inputs and the workflow's source are copied into the crate (inputs/, source/),
so the results folder holds everything the crate names; then rocrate writes the
metadata from the files, the provenance record and the citation file.
"""

import os
import shutil
from pathlib import Path

from lineload.io import output_to, read_json
from lineload.publishing.citation import citation_or_default
from lineload.publishing.crate import build_crate, write_crate


def copy_into(files, root, raw_dir, repository):
    """Copy the raw inputs and the source to their names under the crate's root."""
    origin = {"input": Path(raw_dir), "source": Path(repository)}
    for item in files:
        if item["kind"] in origin:
            target = Path(root, item["name"])
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(origin[item["kind"]] / item["from"], target)


def crate(files, rules, provenance, citation, output, raw_dir, repository):
    """Copy the inputs and the source in, then write ro-crate-metadata.json."""
    root = Path(output.metadata).parent
    for folder in (output.inputs, output.source):
        Path(folder).mkdir(parents=True, exist_ok=True)
    copy_into(files, root, raw_dir, repository)
    built, members = build_crate(
        files, rules, read_json(provenance), citation_or_default(citation), root
    )
    write_crate(built, root)
    kinds = {}
    for item in files:
        if item["name"] in members:
            kinds[item["kind"]] = kinds.get(item["kind"], 0) + 1
    print(f"{output.metadata}: " + ", ".join(f"{n} {kind} files" for kind, n in kinds.items()))


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        crate(
            snakemake.params.files,
            snakemake.params.rules,
            snakemake.input.provenance,
            snakemake.input.citation,
            snakemake.output,
            raw_dir=os.path.dirname(snakemake.input.raw[0]),  # the subject sheet's folder
            repository=Path(snakemake.scriptdir).resolve().parents[1],  # the checkout
        )
