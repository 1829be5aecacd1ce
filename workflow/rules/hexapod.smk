# Stage 'hexapod' (chapter 6.3 of the reference studies, Rybak n.d.): Stewart–Gough platform inverse and forward dynamics,
# the vertical move with a force error, and the sensitivity map (one job per actuator).

HEXAPOD_ACTUATORS = config["hexapod"]["sensitivity"]["actuators"]


wildcard_constraints:
    actuator="[1-6]",


rule hexapod_dynamics:
    output:
        trajectory="results/hexapod/trajectory.nc",
        forces="results/hexapod/forces.nc",
    log:
        "results/logs/hexapod/dynamics.log",
    benchmark:
        "results/benchmarks/rules/hexapod/dynamics.tsv"
    conda:
        ENV
    params:
        hexapod=config["hexapod"],
    script:
        "../scripts/hexapod_dynamics.py"


rule hexapod_sensitivity_shard:
    output:
        "results/hexapod/sensitivity/actuator_{actuator}.nc",
    log:
        "results/logs/hexapod/sensitivity_{actuator}.log",
    benchmark:
        "results/benchmarks/rules/hexapod/sensitivity_{actuator}.tsv"
    conda:
        ENV
    params:
        hexapod=config["hexapod"],
        actuator=lambda wildcards: int(wildcards.actuator),
    script:
        "../scripts/hexapod_sensitivity_shard.py"


rule hexapod_sensitivity:
    input:
        shards=expand(
            "results/hexapod/sensitivity/actuator_{actuator}.nc",
            actuator=HEXAPOD_ACTUATORS,
        ),
    output:
        "results/hexapod/sensitivity.nc",
    log:
        "results/logs/hexapod/sensitivity.log",
    benchmark:
        "results/benchmarks/rules/hexapod/sensitivity.tsv"
    conda:
        ENV
    params:
        hexapod=config["hexapod"],
    script:
        "../scripts/hexapod_sensitivity.py"


rule hexapod_force_accuracy:
    input:
        sensitivity="results/hexapod/sensitivity.nc",
        forces="results/hexapod/forces.nc",
    output:
        "results/hexapod/force_accuracy.csv",
    log:
        "results/logs/hexapod/force_accuracy.log",
    benchmark:
        "results/benchmarks/rules/hexapod/force_accuracy.tsv"
    conda:
        ENV
    script:
        "../scripts/hexapod_force_accuracy.py"


# Chapter 6's findings: the assumed hexapod, the programme and its replay, the instability,
# the vertical move against the seed's, the drift map and the force accuracy; with the
# stage's scorecard rows ("Against the source").
rule hexapod_findings:
    input:
        trajectory="results/hexapod/trajectory.nc",
        forces="results/hexapod/forces.nc",
        sensitivity="results/hexapod/sensitivity.nc",
        force_accuracy="results/hexapod/force_accuracy.csv",
        references=str(REPO / "src" / "robomill" / "data" / "references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=str(REPO / "src" / "robomill" / "data" / "scorecard.yaml"),
    output:
        findings="results/hexapod/findings.yaml",
    log:
        "results/logs/hexapod/findings.log",
    benchmark:
        "results/benchmarks/rules/hexapod/findings.tsv"
    conda:
        ENV
    params:
        hexapod=config["hexapod"],
    script:
        "../scripts/hexapod_findings.py"


rule hexapod:
    input:
        "results/hexapod/findings.yaml",
        "results/hexapod/trajectory.nc",
        "results/hexapod/force_accuracy.csv",
        "results/hexapod/forces.nc",
        "results/hexapod/sensitivity.nc",


use rule chapter as ch6_hexapod with:
    input:
        **chapter_files("ch6_hexapod"),
        findings="results/hexapod/findings.yaml",
        trajectory="results/hexapod/trajectory.nc",
        forces="results/hexapod/forces.nc",
        sensitivity="results/hexapod/sensitivity.nc",
        force_accuracy="results/hexapod/force_accuracy.csv",
    output:
        **chapter_outputs("ch6_hexapod"),
    log:
        chapter_log("ch6_hexapod"),
    benchmark:
        chapter_benchmark("ch6_hexapod")
