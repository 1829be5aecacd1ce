# Ingestion: the manifest is validated and every listed file checked against its sha256.
# Per-file readers (one job per cut / run) live with their stage and read the same manifest.


rule ingest_manifest:
    input:
        manifest=MANIFEST,
    output:
        cuts="results/ingest/cuts.csv",
        files="results/ingest/files.csv",
    log:
        "results/logs/ingest/manifest.log",
    benchmark:
        "results/benchmarks/rules/ingest/manifest.tsv"
    conda:
        ENV
    script:
        "../scripts/ingest_manifest.py"


rule ingest_cell:
    output:
        "results/ingest/cell.yaml",
    log:
        "results/logs/ingest/cell.log",
    benchmark:
        "results/benchmarks/rules/ingest/cell.tsv"
    conda:
        ENV
    params:
        cell=config["cell"],
    script:
        "../scripts/cell_write.py"
