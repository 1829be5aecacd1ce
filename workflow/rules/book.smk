# The book: every chapter in one self-contained folder, results/thesis/ (target `book`), and
# the whole book as one print-ready PDF, results/thesis/book.pdf (headless Chromium). Without
# a Chromium `all` leaves the PDF out with one warning line; asking for book.pdf fails naming
# the package to install.
import sys

from robomill.pipeline.book_print import find_chromium

# $ROBOMILL_CHROMIUM, else the first browser of book_print.CHROMIUM_NAMES found
CHROMIUM = find_chromium()
# config book.pdf: false leaves the print out of `all` (the index does not link it)
PRINT_BOOK = config["book"]["pdf"]


rule scorecard:
    input:
        chapters=lambda w: [t for t in ALL_TARGETS if t.startswith("results/chapters/")],
        checks=package_data("scorecard.yaml"),
        references=package_data("references.yaml"),
        code=code_inputs("scorecard.py"),
    output:
        csv=report(
            artefact("thesis.scorecard"),
            caption="../report/book.rst",
            category="Book",
            subcategory="Tables",
        ),
    log:
        "results/logs/book/scorecard.log",
    benchmark:
        "results/benchmarks/rules/book/scorecard.tsv"
    conda:
        ENV
    params:
        root=lambda w, output: os.path.dirname(
            os.path.dirname(os.path.dirname(output.csv))
        )
        or ".",
        thesis_study=is_thesis_study(CUTS, EXPERIMENT),
    script:
        "../scripts/scorecard.py"


rule book:
    input:
        chapters=lambda w: [t for t in ALL_TARGETS if t.startswith("results/chapters/")],
        cuts=artefact("ingest.cuts"),
        manifest=MANIFEST,
        scorecard=artefact("thesis.scorecard"),
        code=code_inputs("book.py"),
    output:
        index=report(
            artefact("thesis.index"), caption="../report/book.rst", category="Book"
        ),
    log:
        "results/logs/book/book.log",
    benchmark:
        "results/benchmarks/rules/book/book.tsv"
    conda:
        ENV
    params:
        figures_root=lambda w, input: os.path.join(
            os.path.dirname(os.path.dirname(input.cuts)), "figures"
        ),
        out_dir=lambda w, output: os.path.dirname(output.index),
        benchmarks="results/benchmarks/summary.csv",
        skipped=SKIPPED,
        pdf_name="book.pdf" if CHROMIUM and PRINT_BOOK else None,
    script:
        "../scripts/book.py"


rule book_pdf:
    input:
        index=artefact("thesis.index"),
        chapters=lambda w: [t for t in ALL_TARGETS if t.startswith("results/chapters/")],
        cuts=artefact("ingest.cuts"),
        code=code_inputs("book_pdf.py"),
    output:
        pdf=artefact("thesis.book"),
        page=artefact("thesis.book_print"),
    log:
        "results/logs/book/book_pdf.log",
    benchmark:
        "results/benchmarks/rules/book/book_pdf.tsv"
    conda:
        ENV
    params:
        chromium=CHROMIUM,
    script:
        "../scripts/book_pdf.py"


ALL_TARGETS.append(artefact("thesis.index"))
if CHROMIUM and PRINT_BOOK:
    ALL_TARGETS.append(artefact("thesis.book"))
elif not PRINT_BOOK:
    print(
        "robomill: results/thesis/book.pdf left out of `all`: book.pdf is false",
        file=sys.stderr,
    )
else:
    print(
        "robomill: results/thesis/book.pdf left out of `all`: no Chromium found "
        "(apt-get install chromium)",
        file=sys.stderr,
    )
