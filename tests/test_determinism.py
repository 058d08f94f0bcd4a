"""Two clean builds of everything give byte-identical outputs."""

import shutil

import pytest

from conftest import run_snakemake, write_small_dataset

pytestmark = pytest.mark.e2e  # every test here runs Snakemake

# Timings by design: they differ from run to run and are not results.
NOT_COMPARED = {"logs", "benchmarks"}


def build_outputs(results):
    return {
        path.relative_to(results).as_posix(): path.read_bytes()
        for path in sorted(results.rglob("*"))
        if path.is_file() and path.relative_to(results).parts[0] not in NOT_COMPARED
    }


def test_two_clean_builds_are_byte_identical(tmp_path):
    raw = write_small_dataset(
        tmp_path / "raw",
        subjects={
            "MK": ("monkey", [1.0, 2.0], 5.0),
            "HU": ("human", [1.0, 2.0], 9.0),
        },
    )
    (raw / "NOTICE.txt").write_text("Test data for the determinism check.\n")
    (raw / "outlines").mkdir()
    lines = ["depth_mm,state,x_image_mm,z_image_mm"]
    for state, dip in (("resting", 0.0), ("deformed", 1.0)):
        for x in range(-100, 101, 5):  # image mm at magnification 20: -5 to 5 tissue mm
            z = -((x / 20) ** 2) / 16 - dip * max(0.0, 1 - abs(x / 20) / 4) ** 2
            lines.append(f"1,{state},{x},{20 * z:.3f}")
    (raw / "outlines" / "MK.csv").write_text("\n".join(lines) + "\n")
    results = tmp_path / "results"
    builds = []
    for _ in range(2):
        shutil.rmtree(results, ignore_errors=True)
        process = run_snakemake(raw=raw, results=results)  # default target: everything
        assert process.returncode == 0, process.stderr[-3000:]
        builds.append(build_outputs(results))
    first, second = builds
    assert sorted(first) == sorted(second)
    kinds = {name.rsplit(".", 1)[-1] for name in first}
    assert {"pdf", "png", "csv", "md", "tex", "json"} <= kinds
    differing = [name for name in first if first[name] != second[name]]
    assert differing == []
    assert "data/outlines/MK.csv" in first
    assert first["article/reproduction.pdf"].startswith(b"%PDF")  # the article too
    # the notice reached the outputs that carry one
    assert b"Test data for the determinism check." in first["tables/claims.md"]
