"""The remembered input check: what invalidates it, and that a broken input still fails."""

import json
import shutil

import pytest

from conftest import REPO, run_snakemake, write_small_dataset
from lineload import checkcache

CONFIG = {"raw_data": "raw", "fit_window_mm": 3.0}


def make_code(tmp_path):
    code = tmp_path / "check.py"
    code.write_text("RULES = 1\n", encoding="utf-8")
    return [code]


def test_fingerprint_is_stable_and_sees_every_input(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    code = make_code(tmp_path)
    key = checkcache.fingerprint(CONFIG, raw, code)
    assert key == checkcache.fingerprint(dict(CONFIG), raw, code)
    assert len(key) == 64

    seen = {key}

    def changed(config=CONFIG):
        new = checkcache.fingerprint(config, raw, code)
        assert new not in seen
        seen.add(new)

    profile = raw / "profiles" / "MK.csv"
    original = profile.read_bytes()
    profile.write_bytes(original.replace(b"0.", b"1.", 1))  # same size, other bytes
    changed()
    profile.write_bytes(original)
    assert checkcache.fingerprint(CONFIG, raw, code) == key  # back to the same bytes

    (raw / "profiles" / "XX.csv").write_text("stray\n", encoding="utf-8")  # a new file
    changed()
    (raw / "outlines").mkdir(exist_ok=True)
    (raw / "outlines" / "MK.csv").write_text("x\n", encoding="utf-8")
    changed()
    (raw / "subjects.csv").write_text(
        (raw / "subjects.csv").read_text(encoding="utf-8") + "\n", encoding="utf-8"
    )
    changed()
    changed({**CONFIG, "fit_window_mm": 2.0})
    code[0].write_text("RULES = 2\n", encoding="utf-8")
    changed()


def test_fingerprint_of_a_missing_folder_differs_from_an_empty_one(tmp_path):
    code = make_code(tmp_path)
    missing = checkcache.fingerprint(CONFIG, tmp_path / "nowhere", code)
    (tmp_path / "empty").mkdir()
    assert missing != checkcache.fingerprint(CONFIG, tmp_path / "empty", code)


def test_store_then_load_round_trip_keeps_order(tmp_path):
    path = tmp_path / "cache" / "check.json"
    result = {"subjects": {"Z9": {"species": "human"}, "A1": {"species": "monkey"}}}
    checkcache.store(path, "k1", result)
    loaded = checkcache.load(path, "k1")
    assert loaded == result
    assert list(loaded["subjects"]) == ["Z9", "A1"]  # subject-sheet order, not sorted
    assert checkcache.load(path, "k2") is None  # another fingerprint: no result
    assert not [p for p in path.parent.iterdir() if p.name.startswith(".tmp-")]


def test_unreadable_or_foreign_cache_is_a_miss(tmp_path):
    path = tmp_path / "check.json"
    assert checkcache.load(path, "k") is None  # no file
    path.write_text("{not json", encoding="utf-8")
    assert checkcache.load(path, "k") is None
    path.write_text(json.dumps(["k"]), encoding="utf-8")
    assert checkcache.load(path, "k") is None
    path.write_text(json.dumps({"fingerprint": "k", "result": 3}), encoding="utf-8")
    assert checkcache.load(path, "k") is None


def test_anything_but_the_exact_complete_entry_is_a_miss(tmp_path):
    path = tmp_path / "check.json"
    result = {"config": {"fit_window_mm": 3.0}, "subjects": {"A1": {"species": "monkey"}}}
    checkcache.store(path, "k", result)
    entry = json.loads(path.read_text(encoding="utf-8"))
    assert checkcache.load(path, "k") == result

    def miss(changed):
        path.write_text(json.dumps(changed), encoding="utf-8")
        return checkcache.load(path, "k") is None

    # an edited result with the right fingerprint
    edited = json.loads(json.dumps(entry))
    edited["result"]["config"]["fit_window_mm"] = 2.0
    assert miss(edited)
    # a field removed from the result, or from the entry, or one added to it
    trimmed = json.loads(json.dumps(entry))
    del trimmed["result"]["subjects"]
    assert miss(trimmed)
    assert miss({k: v for k, v in entry.items() if k != "digest"})
    assert miss({**entry, "extra": 1})
    # the untouched entry still loads: the misses above came from the edits
    path.write_text(json.dumps(entry), encoding="utf-8")
    assert checkcache.load(path, "k") == result


def test_store_into_an_unwritable_place_is_silently_skipped(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("", encoding="utf-8")
    checkcache.store(blocker / "check.json", "k", {"a": 1})  # parent is a file
    assert checkcache.load(blocker / "check.json", "k") is None


@pytest.mark.e2e
def test_workflow_rechecks_a_dataset_broken_after_a_passed_check(tmp_path, snakemake_available):
    """A passed check is remembered, but a later corruption is still caught, with no output."""
    raw = write_small_dataset(tmp_path / "raw")
    work, results = tmp_path / "work", tmp_path / "out"
    shutil.copytree(REPO / "config", work / "config")  # the configfile is read from --directory
    cache = work / ".snakemake" / "lineload" / "input-check.json"

    first = run_snakemake("fits", "--dry-run", raw=str(raw), results=str(results), cwd=work)
    assert first.returncode == 0, first.stdout + first.stderr
    stored = json.loads(cache.read_text(encoding="utf-8"))
    assert list(stored["result"]["subjects"]) == ["MK", "HU"]
    assert stored["result"]["config"]["fit_window_mm"] == 3.0  # defaults filled in
    stamp = cache.stat().st_mtime_ns

    again = run_snakemake("fits", "--dry-run", raw=str(raw), results=str(results), cwd=work)
    assert again.returncode == 0, again.stdout + again.stderr
    assert cache.stat().st_mtime_ns == stamp  # remembered, not checked and written again

    profile = raw / "profiles" / "MK.csv"
    lines = profile.read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    cells = lines[2].split(",")
    cells[header.index("depth_mm")] = "deep"
    lines[2] = ",".join(cells)
    profile.write_text("\n".join(lines) + "\n", encoding="utf-8")

    # the valid dry runs wrote the jobs' specs; the broken run must add or change nothing
    def snapshot():
        return {p: p.read_bytes() for p in results.rglob("*") if p.is_file()}

    before = snapshot()
    broken = run_snakemake("fits", raw=str(raw), results=str(results), cwd=work)
    output = broken.stdout + broken.stderr
    assert broken.returncode != 0, output
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    assert errors == [errors[0]] and f"{raw}/profiles/MK.csv, line 3" in errors[0], output
    assert snapshot() == before
    assert json.loads(cache.read_text(encoding="utf-8"))["fingerprint"] == stored["fingerprint"]
