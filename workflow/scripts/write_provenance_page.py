"""Rule provenance_page: the provenance record as a page of the report, the record itself
its download (Snakemake's report shows HTML on the page but only downloads a JSON)."""

from pathlib import Path

from lineload.io import output_to, write_text
from lineload.publishing.reportpages import caption, download_link, record_page
from lineload.runtime.jobparams import given


def write_provenance_page(record, caption_file, output, config, notice):
    """Write the page: the record as it is, its caption, and the file to download."""
    data = Path(record).read_bytes()
    text = record_page(
        "The provenance record",
        data.decode("utf-8"),
        caption(caption_file, config),
        notice,
        download_link(Path(record).name, data, "application/json"),
    )
    write_text(text, output)
    print(f"{output}: the provenance record ({len(data)} bytes) on a page")


if __name__ == "__main__":
    with output_to(snakemake.log[0]):
        write_provenance_page(
            snakemake.input.record,
            snakemake.input.caption,
            snakemake.output[0],
            **given(snakemake.params),
        )
