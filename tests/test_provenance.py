"""The provenance record: hashes of every raw input, settings, versions, source state."""

import hashlib
import json
import re

from conftest import write_small_dataset
from lineload import provenance


def test_record_hashes_every_raw_file(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    files = sorted(str(p) for p in raw.rglob("*.csv"))
    record = provenance.provenance_record(str(raw), files, {"fit_window_mm": 3.0}, str(tmp_path))
    hashes = record["raw_data"]["sha256"]
    assert set(hashes) == {"subjects.csv", "profiles/MK.csv", "profiles/HU.csv"}
    for name, digest in hashes.items():
        assert digest == hashlib.sha256((raw / name).read_bytes()).hexdigest()
    assert record["config"] == {"fit_window_mm": 3.0}
    assert record["packages"]["numpy"] is not None
    # outside a git work tree the source state is unknown, not invented
    assert record["git"] == {"commit": None, "dirty": None}


def test_a_changed_byte_changes_the_hash(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    path = raw / "profiles" / "MK.csv"
    before = provenance.file_sha256(path)
    path.write_bytes(path.read_bytes().replace(b"left", b"right", 1))
    assert provenance.file_sha256(path) != before


def test_json_is_stable_and_has_no_time(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    files = [str(p) for p in raw.rglob("*.csv")]
    texts = [
        provenance.to_json(provenance.provenance_record(str(raw), order, {}, str(tmp_path)))
        for order in (files, files[::-1])
    ]
    assert texts[0] == texts[1]
    assert json.loads(texts[0])["raw_data"]["folder"] == str(raw)
    assert not re.search(r"\d{4}-\d{2}-\d{2}|\d{2}:\d{2}:\d{2}", texts[0])
