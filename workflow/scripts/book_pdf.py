"""Print the whole book to one PDF with headless Chromium: a title page with the study's
one-line description, a contents list with page numbers, one bookmark per chapter (see
robomill.pipeline.book_print.print_book).
The job: robomill.pipeline.jobs.book_pdf."""

from robomill.pipeline.jobs import book_pdf
from robomill.pipeline.runlog import setup

book_pdf.run(snakemake.input, snakemake.output, snakemake.params,
             log=setup(snakemake.log[0], "book"))
