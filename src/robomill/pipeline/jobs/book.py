"""Build the thesis book (results/thesis/) from the rendered chapters.

The job of the rule script ``workflow/scripts/book.py``."""

from __future__ import annotations

import logging

from robomill.pipeline.book import build_book
from robomill.pipeline.provenance import run_provenance


def run(inputs, outputs, params, *, log: logging.Logger, config) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    index = build_book(
        inputs.chapters,
        params.figures_root,
        params.out_dir,
        provenance=run_provenance(config, inputs.manifest),
        cuts_csv=inputs.cuts,
        scorecard_csv=inputs.get("scorecard"),
        benchmarks_csv=params.benchmarks,  # written by `make bench`, used when present
        skipped=params.skipped,  # chapters without data in this raw folder, and why
        pdf_name=params.pdf_name,  # results/thesis/book.pdf, printed by rule book_pdf
    )
    log.info("book written to %s (%d chapters)", index, len(inputs.chapters))
