"""Rule provenance: hashes of the raw inputs, config, versions, commit."""

import os
from pathlib import Path

from lineload.io import output_to, write_text
from lineload.publishing.provenance import provenance_record, to_json
from lineload.runtime.jobparams import given


def write_provenance(raw_files, output, config, repository):
    """Write the provenance record of this build."""
    raw_dir = os.path.dirname(raw_files[0])  # the first is the subject sheet
    record = provenance_record(raw_dir, raw_files, config, repository)
    write_text(to_json(record), output)
    print(
        f"{output}: {len(record['raw_data']['sha256'])} raw files hashed, "
        f"commit {record['git']['commit']} (dirty: {record['git']['dirty']})"
    )


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        write_provenance(
            snakemake.input.raw,
            snakemake.output[0],
            **given(snakemake.params),
            repository=Path(snakemake.scriptdir).parents[1],  # for its git commit
        )
