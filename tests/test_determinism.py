"""Two clean builds of everything give byte-identical outputs."""

import pytest

from conftest import SHARED_NOTICE, build_outputs

pytestmark = pytest.mark.e2e  # every test here runs Snakemake


def test_two_clean_builds_are_byte_identical(small_build_with_notice, checkout_build):
    # the same data built twice, each shared with other tests, each in a copy of the
    # checkout: once with the raw and results folders outside it, once inside
    builds = [build_outputs(small_build_with_notice[1]), build_outputs(checkout_build[1])]
    first, second = builds
    assert sorted(first) == sorted(second)
    kinds = {name.rsplit(".", 1)[-1] for name in first}
    assert {"pdf", "png", "csv", "md", "tex", "json"} <= kinds
    differing = [name for name in first if first[name] != second[name]]
    assert differing == []
    assert "data/outlines/MK.csv" in first
    assert first["article/reproduction.pdf"].startswith(b"%PDF")  # the article too
    assert b'"@id": "logs/article.log"' in first["ro-crate-metadata.json"]  # logs listed
    # the notice reached the outputs that carry one
    assert SHARED_NOTICE.encode() in first["tables/claims.md"]
