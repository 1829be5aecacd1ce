# The book: every chapter in one self-contained folder, results/thesis/ (target `book`).


rule scorecard:
    input:
        chapters=lambda w: [t for t in ALL_TARGETS if t.startswith("results/chapters/")],
        code=code("scorecard"),
        checks=str(REPO / "src" / "robomill" / "data" / "scorecard.yaml"),
    output:
        csv=report(
            "results/thesis/scorecard.csv",
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
    script:
        "../scripts/scorecard.py"


rule book:
    input:
        chapters=lambda w: [t for t in ALL_TARGETS if t.startswith("results/chapters/")],
        cuts="results/ingest/cuts.csv",
        manifest=MANIFEST,
        scorecard="results/thesis/scorecard.csv",
        code=code("book", "provenance"),
    output:
        index=report(
            "results/thesis/index.html", caption="../report/book.rst", category="Book"
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
    script:
        "../scripts/book.py"


ALL_TARGETS.append("results/thesis/index.html")
