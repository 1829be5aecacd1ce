"""Print the whole book to one PDF with headless Chromium (see robomill.pipeline.book.print_pdf)."""

from robomill.pipeline.book import print_document, print_pdf
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "book")
page = print_document(snakemake.input.chapters, snakemake.output.page)
pdf = print_pdf(page, snakemake.output.pdf, chromium=snakemake.params.chromium)
log.info("book printed to %s (%d chapters)", pdf, len(snakemake.input.chapters))
