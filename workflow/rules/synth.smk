# The virtual cell: planted truth and the manifest of the synthetic raw files.
# Each instrument's simulator rule lives with its stage (surface.smk, forces.smk, ...) and
# writes into results/synthetic/raw/; this file gathers them.


rule synth_truth:
    input:
        code=code(
            "synth.cell",
            "synth.truth",
            "synth.plan",
            "kinematics",
            "synth.profilometer",
            "synth.dynamometer",
            "synth.tracker",
            "synth.impact",
            "synth.ctrack",
            "synth.loadtests",
        ),
    output:
        "results/synthetic/truth.nc",
    log:
        "results/logs/synth/truth.log",
    benchmark:
        "results/benchmarks/rules/synth/truth.tsv"
    conda:
        ENV
    params:
        synth=config["synth"],
        experiment=config["experiment"],
    script:
        "../scripts/synth_truth.py"


rule synth_manifest:
    input:
        files=[f"results/synthetic/raw/{f['path']}" for f in RAW_FILES],
        truth="results/synthetic/truth.nc",
        code=code("io.manifest"),
    output:
        "results/synthetic/raw/manifest.yaml",
    log:
        "results/logs/synth/manifest.log",
    benchmark:
        "results/benchmarks/rules/synth/manifest.tsv"
    conda:
        ENV
    params:
        experiment=EXPERIMENT,
        cuts=[c.as_dict() for c in CUTS],
        files=RAW_FILES,
        raw_dir=lambda w, output: os.path.dirname(output[0]),
    script:
        "../scripts/synth_manifest.py"
