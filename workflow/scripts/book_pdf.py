"""Print the whole book to one PDF with headless Chromium: a title page with the study's
one-line description, a contents list with page numbers, one bookmark per chapter (see
robomill.pipeline.book_print.print_book)."""

import pandas as pd

from robomill.pipeline.book_print import print_book
from robomill.pipeline.design_tables import describe_design
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "book")
cuts = pd.read_csv(snakemake.input.cuts)
description = describe_design(cuts) if len(cuts) else "no cuts (impact tests only)"
pages = print_book(snakemake.input.chapters, snakemake.output.page, snakemake.output.pdf,
                   description=description, chromium=snakemake.params.chromium)
log.info("book printed to %s (%d chapters, starting on pages %s)", snakemake.output.pdf,
         len(pages), ", ".join(map(str, pages.values())))
