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
    inp = inputs
    index = build_book(
        inp.chapters,
        params.figures_root,
        params.out_dir,
        provenance=run_provenance(config, inp.manifest),
        cuts_csv=inp.cuts,
        scorecard_csv=inp.get("scorecard"),
        benchmarks_csv=params.benchmarks,  # written by `make bench`, used when present
        skipped=params.skipped,  # chapters without data in this raw folder, and why
        pdf_name=params.pdf_name,  # results/thesis/book.pdf, printed by rule book_pdf
    )
    log.info("book written to %s (%d chapters)", index, len(inp.chapters))
