"""Print the whole book to one PDF with headless Chromium: a title page with the study's
one-line description, a contents list with page numbers, one bookmark per chapter (see
robomill.pipeline.book_print.print_book).

The job of the rule script ``workflow/scripts/book_pdf.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.pipeline.book_print import print_book
from robomill.pipeline.design_tables import describe_design


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cuts = pd.read_csv(inputs.cuts)
    description = describe_design(cuts) if len(cuts) else "no cuts (impact tests only)"
    pages = print_book(inputs.chapters, outputs.page, outputs.pdf,
                       description=description, chromium=params.chromium)
    log.info("book printed to %s (%d chapters, starting on pages %s)", outputs.pdf,
             len(pages), ", ".join(map(str, pages.values())))
