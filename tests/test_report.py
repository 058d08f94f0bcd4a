"""The HTML report, read in headless Chromium as a reviewer reads it: the data statement
follows the data, tables are shown as tables, figures with their captions beside them."""

import os
import re
import shutil
import textwrap
from pathlib import Path

import pandas as pd
import pytest

from conftest import SHARED_NOTICE, run_snakemake
from lineload.figures import registry
from lineload.io import read_results_csv
from test_reportpages import rows_not_shown

pytestmark = pytest.mark.e2e

# CI's own image names its browser in CHROMIUM; Debian's package is chromium
CHROMIUM = os.environ.get("CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
# as the machine's notes say: no sandbox as root, no background networking (it is refused)
ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


#: The types the report's view icon shows on the page (any other it downloads).
SHOWN = {"text/html", "image/png", "image/svg+xml", "image/jpeg", "application/pdf"}
#: The text of each header of a page's table (run in the page).
HEADERS = "() => Array.from(document.querySelectorAll('thead th'), th => th.textContent)"
#: The window's width in pixels, a laptop's.
WIDTH = 1400
#: The text of each cell of a page's table body, row by row (run in the page).
BODY_ROWS = """() => Array.from(document.querySelectorAll('tbody tr'),
    row => Array.from(row.cells, cell => cell.textContent))"""


@pytest.fixture(scope="module")
def browser():
    if not Path(CHROMIUM).is_file():
        pytest.skip("no Chromium here (CI installs Debian's chromium package)")
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield chromium
        chromium.close()


def open_item(page, report, steps, item):
    """Open a result of the report: click through the menu, then the item's eye icon;
    return the frame it shows and that frame's text.  Every wait is for a condition
    (an element to appear), never for a fixed time."""
    page.goto(report.as_uri())
    row = page.locator("tr", has=page.get_by_text(item, exact=True)).first
    for step in steps:
        target = page.get_by_text(step, exact=True).first
        # the menu shows the step, or (a category with one subcategory skips that
        # level) already the item's row
        target.or_(row).first.wait_for(state="visible")
        if target.is_visible():
            target.click()
    row.locator("a[iconname=eye]").click()
    # the item's page (an iframe) has loaded once its body shows text
    page.frame_locator("iframe").first.locator("body", has_text=re.compile(r"\S")).wait_for()
    shown = next(f for f in page.frames if f != page.main_frame)
    return shown, " ".join(shown.inner_text("body").split())


@pytest.mark.parametrize("build", ["small_build_with_notice", "small_build"])
def test_report_reads_as_a_reviewer_needs(tmp_path, browser, build, request):
    raw, results = request.getfixturevalue(build)
    notice = SHARED_NOTICE if (raw / "NOTICE.txt").exists() else ""
    report = tmp_path / "report.html"  # the shared build is read, never written
    made = run_snakemake("--report", str(report), raw=raw, results=results)
    assert made.returncode == 0, made.stderr[-3000:]

    page = browser.new_page(viewport={"width": WIDTH, "height": 900}, accept_downloads=True)
    page.goto(report.as_uri())
    page.get_by_text("Provenance").first.wait_for(state="visible")
    front = " ".join(page.inner_text("body").split())
    if notice:
        assert notice in front
    else:
        assert "carries no notice" in front and "synthetic" not in front.lower()
    for category in ("Article", "Claims", "Fits", "Paper figures", "Supplement", "Provenance"):
        assert category in front, category

    # the claims table on the page, a verdict per claim as claims.csv has it
    frame, text = open_item(page, report, ["Claims", "Tables"], "The paper's claims, recomputed")
    claims = pd.read_csv(results / "tables" / "claims.csv")
    rows = frame.locator("tbody tr")
    assert rows.count() == len(claims)
    for i, (claim, verdict) in enumerate(zip(claims["claim"], claims["verdict"], strict=True)):
        cells = rows.nth(i).locator("td").all_inner_texts()
        assert cells[0] == claim and verdict in cells, (claim, verdict, cells[:6])
    assert "Every statement of the paper the claims table tests" in text  # the caption
    # a figure with its caption beside it, the list of figures beside it taking at most
    # two fifths of the window (a list of whole titles took 53 %, the figure 45 %)
    frame, text = open_item(
        page,
        report,
        ["Paper figures", "Figures"],
        textwrap.shorten(registry.FIGURES[1].title, 40, placeholder=" …"),
    )
    assert frame.locator("img").count() == 1 and "log axis" in text
    assert page.locator("nav").first.bounding_box()["width"] <= 0.4 * WIDTH
    # a data file's rows on its page, as its CSV has them (and a page that lost a row
    # would be caught)
    converted = sorted((results / "data" / "converted").glob("*.csv"))[0]
    frame, text = open_item(page, report, ["Data", "Readings in tissue mm"], converted.stem)
    table = read_results_csv(converted)
    shown = frame.evaluate(BODY_ROWS)
    assert len(shown) == len(table) > 0 and rows_not_shown(shown, table) == []
    assert "both sides of the wedge" in text  # its caption
    frame.evaluate("document.querySelector('tbody tr:nth-child(2)').remove()")
    assert rows_not_shown(frame.evaluate(BODY_ROWS), table)
    # the supplements numbered on from the paper's figures, as in the article, and listed
    # in that order (the report sorts labels as text: "Figure 10" must not precede 8)
    page.goto(report.as_uri())
    page.get_by_text("Supplement", exact=True).first.click()
    figures = page.get_by_text("Figures", exact=True).first
    if figures.is_visible():
        figures.click()
    page.locator("tbody tr").first.wait_for()
    listed = [
        " ".join(row.split("\t")[0].split()) for row in page.locator("tbody tr").all_inner_texts()
    ]
    supplements = [f for f in registry.FIGURES if f.category == "Supplement"]
    first = registry.FIGURES.index(supplements[0]) + 1
    assert listed == [f"Figure {first + i}" for i in range(len(supplements))]
    # every item's view icon shows it: Snakemake's report only downloads a CSV or JSON
    # (its template decides by the type), so each data file is on the report as its
    # page, the file that page's download
    types = page.evaluate("Object.values(results).map(r => [r.name, r.mime_type])")
    assert [name for name, mime in types if mime not in SHOWN] == []
    # the elastic fits as a table with labels and units, and the CSV to download
    frame, text = open_item(
        page,
        report,
        ["Fits", "Tables"],
        textwrap.shorten("The elastic finger per subject and depth", 40, placeholder=" …"),
    )
    elastic = read_results_csv(results / "tables" / "elastic_fits.csv")
    assert frame.locator("tbody tr").count() == len(elastic) > 0
    headers = frame.evaluate(HEADERS)
    assert "elastic layered RMSE (mm)" in headers and "depth (mm)" in headers
    assert "elastic layered modulus ratio" in headers
    with page.expect_download() as download:
        frame.get_by_text("Download elastic_fits.csv").click()
    saved = Path(download.value.path()).read_bytes()
    assert saved == (results / "tables" / "elastic_fits.csv").read_bytes()
    # the provenance record on a page of its own under Provenance
    frame, text = open_item(page, report, ["Provenance", "Pages"], "the provenance record")
    assert '"sha256"' in text and "Download provenance.json" in text
    # the software page names the versions
    frame, text = open_item(page, report, ["Provenance", "Pages"], "versions and source")
    assert "snakemake" in text and "typst" in text
    # the rule graph drawn to be read, with its caption
    frame, text = open_item(page, report, ["Provenance", "Pages"], "the rule graph")
    assert frame.locator("img").count() == 1 and "feeds directly" in text
    page.close()
