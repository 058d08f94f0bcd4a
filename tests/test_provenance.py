"""The provenance record: hashes of every raw input, settings, versions, source state."""

import json
import re

from conftest import write_small_dataset
from lineload.publishing import provenance


def test_record_hashes_every_raw_file(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    files = sorted(str(p) for p in raw.rglob("*.csv"))
    record = provenance.provenance_record(str(raw), files, {"fit_window_mm": 3.0}, str(tmp_path))
    hashes = record["raw_data"]["sha256"]
    assert set(hashes) == {"subjects.csv", "profiles/MK.csv", "profiles/HU.csv"}
    for name, digest in hashes.items():  # each file's own digest, as file_sha256 gives it
        assert re.fullmatch("[0-9a-f]{64}", digest) and digest == provenance.file_sha256(raw / name)
    assert len(set(hashes.values())) == len(hashes)
    assert record["config"] == {"fit_window_mm": 3.0}
    assert record["packages"]["numpy"] is not None
    # outside a git work tree the source state is unknown, not invented
    assert record["git"] == {"commit": None, "dirty": None}


def test_file_hash_is_sha256(tmp_path):
    # the test vectors of FIPS 180-2 for SHA-256: "abc" and the empty message
    (tmp_path / "abc").write_bytes(b"abc")
    (tmp_path / "empty").write_bytes(b"")
    assert provenance.file_sha256(tmp_path / "abc") == (
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    )
    assert provenance.file_sha256(tmp_path / "empty") == (
        "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    )


def test_a_changed_byte_changes_the_hash(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    path = raw / "profiles" / "MK.csv"
    files = [str(p) for p in raw.rglob("*.csv")]
    before = provenance.file_sha256(path)
    folder = provenance.provenance_record(str(raw), files, {}, str(tmp_path))["raw_data"]
    path.write_bytes(path.read_bytes().replace(b"left", b"right", 1))
    assert provenance.file_sha256(path) != before
    # the folder's own hash, its name where it lies outside the working folder, follows
    after = provenance.provenance_record(str(raw), files, {}, str(tmp_path))["raw_data"]
    assert after["folder"] == folder["folder"] == "raw"
    assert after["folder_sha256"] != folder["folder_sha256"]


def test_folder_inside_the_working_folder_is_named_relative_to_it(tmp_path, monkeypatch):
    raw = write_small_dataset(tmp_path / "lab" / "raw")
    monkeypatch.chdir(tmp_path)
    files = [str(p) for p in raw.rglob("*.csv")]
    record = provenance.provenance_record(str(raw), files, {}, str(tmp_path))
    assert record["raw_data"]["folder"] == "lab/raw"


def test_json_is_stable_and_has_no_time(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    files = [str(p) for p in raw.rglob("*.csv")]
    texts = [
        provenance.to_json(provenance.provenance_record(str(raw), order, {}, str(tmp_path)))
        for order in (files, files[::-1])
    ]
    assert texts[0] == texts[1]
    # a folder outside the working folder is named, not located: no absolute path
    assert json.loads(texts[0])["raw_data"]["folder"] == "raw"
    assert str(tmp_path) not in texts[0]
    assert not re.search(r"\d{4}-\d{2}-\d{2}|\d{2}:\d{2}:\d{2}", texts[0])
