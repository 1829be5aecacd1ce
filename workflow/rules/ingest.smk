# Ingestion: the manifest is validated and every listed file checked against its sha256.
# Per-file readers (one job per cut / run) live with their stage and read the study
# (results/ingest/study.yaml), which verifies each file they read.


rule ingest_manifest:
    input:
        manifest=MANIFESTS,
        code=code_inputs("ingest_manifest.py"),
    output:
        cuts=artefact("ingest.cuts"),
        files=artefact("ingest.files"),
    log:
        "results/logs/ingest/manifest.log",
    benchmark:
        "results/benchmarks/rules/ingest/manifest.tsv"
    conda:
        ENV
    script:
        "../scripts/ingest_manifest.py"


rule ingest_cell:
    input:
        code=code_inputs("cell_write.py"),
    output:
        artefact("ingest.cell"),
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


# The study, read once: the manifest validated and written with every cut's resolved design
# (robomill.study); every analysis rule reads it (input `study`), none the manifest.
rule ingest_study:
    input:
        manifest=MANIFESTS,
        code=code_inputs("ingest_study.py"),
    output:
        STUDY,
    log:
        "results/logs/ingest/study.log",
    benchmark:
        "results/benchmarks/rules/ingest/study.tsv"
    conda:
        ENV
    params:
        # the block layout for a manifest that gives none (the virtual cell's, or the one this
        # configuration assumes), resolved into the study once
        layout=config["experiment"]["layout"],
    script:
        "../scripts/ingest_study.py"


# Chapter 0's findings: the cuts, their process (spindle speed, tooth passing, feed per
# tooth c = v / (N n)) and design; with the scorecard rows of cuts.csv ("Against the thesis").
rule ingest_findings:
    input:
        cuts=artefact("ingest.cuts"),
        references=package_data("references.yaml"),
        checks=package_data("scorecard.yaml"),
        code=code_inputs("ingest_findings.py"),
    output:
        findings=artefact("ingest.findings"),
    log:
        "results/logs/ingest/findings.log",
    benchmark:
        "results/benchmarks/rules/ingest/findings.tsv"
    conda:
        ENV
    params:
        experiment=dict(EXPERIMENT),
        thesis_design=THESIS_DESIGN,
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/ingest_findings.py"
