"""Build the thesis book (results/thesis/) from the rendered chapters."""

from robomill.pipeline.book import build_book
from robomill.pipeline.provenance import run_provenance
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "book")
inp = snakemake.input
index = build_book(
    inp.chapters,
    snakemake.params.figures_root,
    snakemake.params.out_dir,
    provenance=run_provenance(snakemake.config, inp.manifest),
    cuts_csv=inp.cuts,
    scorecard_csv=inp.get("scorecard"),
    benchmarks_csv=snakemake.params.benchmarks,  # written by `make bench`, used when present
    skipped=snakemake.params.skipped,  # chapters without data in this raw folder, and why
    pdf_name=snakemake.params.pdf_name,  # results/thesis/book.pdf, printed by rule book_pdf
)
log.info("book written to %s (%d chapters)", index, len(inp.chapters))
