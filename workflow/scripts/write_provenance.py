"""Entry point of rule provenance: hashes of the raw inputs, config, versions, commit."""

import argparse
import json

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.io import write_text
from lineload.provenance import provenance_record, to_json


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--raw-dir", required=True)
    parser.add_argument("--config-json", required=True, help="the config in force, as JSON")
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("raw_files", nargs="+")
    args = parser.parse_args()

    record = provenance_record(
        args.raw_dir, args.raw_files, json.loads(args.config_json), args.source_dir
    )
    write_text(to_json(record), args.output)
    print(
        f"{args.output}: {len(record['raw_data']['sha256'])} raw files hashed, "
        f"commit {record['git']['commit']} (dirty: {record['git']['dirty']})"
    )


if __name__ == "__main__":
    main()
