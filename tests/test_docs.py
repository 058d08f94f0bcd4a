"""The documentation holds together: a short README, every page reachable, no dead link."""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs"
README_MAX_LINES = 200
#: Pages linked from the README while they are being written on other branches; a
#: missing one is allowed only while it is named here.
PENDING: set[str] = set()

_FENCE = re.compile(r"^```.*?^```", re.S | re.M)
_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def anchor(heading):
    """GitHub's anchor of a Markdown heading: lower case, punctuation dropped, '-' for spaces."""
    text = heading.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    text = _FENCE.sub("", path.read_text(encoding="utf-8"))
    return {anchor(h) for h in re.findall(r"^#{1,6} (.+)$", text, re.M)}


def links(path):
    """The relative link targets of a Markdown page (code blocks and web addresses left out)."""
    text = _FENCE.sub("", path.read_text(encoding="utf-8"))
    return [t for t in _LINK.findall(text) if not re.match(r"[a-z]+:", t)]


def broken_links(path, pending=()):
    """Each relative link of ``path`` whose file, folder or heading does not exist."""
    broken = []
    for target in links(path):
        file, _, fragment = target.partition("#")
        resolved = (path.parent / file).resolve() if file else path
        if not resolved.exists():
            if resolved.relative_to(REPO).as_posix() not in pending:
                broken.append(target)
            continue
        if fragment and resolved.suffix == ".md" and fragment not in anchors(resolved):
            broken.append(target)
    return broken


def pages():
    return [
        REPO / "README.md",
        REPO / "config" / "README.md",
        REPO / "data" / "README.md",
        *sorted(DOCS.rglob("*.md")),
    ]


def test_the_readme_is_short():
    lines = (REPO / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= README_MAX_LINES, len(lines)


@pytest.mark.parametrize("page", pages(), ids=lambda p: p.relative_to(REPO).as_posix())
def test_every_relative_link_resolves(page):
    assert broken_links(page, PENDING) == []


def test_every_docs_page_is_linked_from_the_readme_or_the_index():
    linked = set()
    for page in (REPO / "README.md", DOCS / "index.md"):
        for target in links(page):
            linked.add((page.parent / target.partition("#")[0]).resolve())
    unlinked = [
        page.relative_to(REPO).as_posix()
        for page in sorted(DOCS.rglob("*.md"))
        if page.resolve() not in linked and page != DOCS / "index.md"
    ]
    assert unlinked == []
    assert DOCS / "index.md" in {p for p in linked}  # the index itself is reachable


def test_a_dead_link_or_heading_is_found(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "REPO", tmp_path)
    (tmp_path / "there.md").write_text("# A heading, with `code`\n")
    page = tmp_path / "page.md"
    page.write_text(
        "[ok](there.md) [ok](there.md#a-heading-with-code) [web](https://example.org/x)\n"
        "[gone](missing.md) [bad anchor](there.md#no-such-heading) ![img](gone.png)\n"
        "```\n[in code](ignored.md)\n```\n[pending](later.md)\n"
    )
    assert broken_links(page, pending={"later.md"}) == [
        "missing.md",
        "there.md#no-such-heading",
        "gone.png",
    ]


def quoted_but_not_found(text, base):
    """The percentages of each paragraph of ``text`` that none of the calibration pages
    it links (relative to ``base``) contains: numbers copied from a page that has moved on."""
    missing = []
    for paragraph in re.split(r"\n\s*\n", text):
        linked = [t.partition("#")[0] for t in _LINK.findall(paragraph)]
        sources = [base / t for t in linked if "calibration/" in t and t.endswith(".md")]
        if not sources:
            continue
        pages_text = " ".join(p.read_text(encoding="utf-8") for p in sources if p.exists())
        for number in re.findall(r"\b\d+\.\d %", paragraph):
            if number not in pages_text:
                missing.append(number)
    return missing


def test_the_readmes_calibration_numbers_are_the_calibration_pages():
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    assert re.search(r"\d+\.\d %", readme)  # the README quotes some
    assert quoted_but_not_found(readme, REPO) == []


def test_a_number_the_calibration_no_longer_gives_is_found(tmp_path):
    page = tmp_path / "docs" / "calibration" / "coverage.md"
    page.parent.mkdir(parents=True)
    page.write_text("| as assumed | waterbed | L_mm | 96.5 % |\n", encoding="utf-8")
    text = "Cover 96.5 % and 91.0 % ([coverage](docs/calibration/coverage.md))."
    assert quoted_but_not_found(text, tmp_path) == ["91.0 %"]
