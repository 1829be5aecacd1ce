# Stage 'hexapod' (chapter 6.3 of the reference studies, Rybak n.d.): Stewart–Gough platform inverse and forward dynamics,
# the vertical move with a force error, and the sensitivity map (one job per actuator).

HEXAPOD_ACTUATORS = config["hexapod"]["sensitivity"]["actuators"]


wildcard_constraints:
    actuator="[1-6]",


rule hexapod_dynamics:
    input:
        code=code_inputs("hexapod_dynamics.py"),
    output:
        trajectory=artefact("hexapod.trajectory"),
        forces=artefact("hexapod.forces"),
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
    input:
        code=code_inputs("hexapod_sensitivity_shard.py"),
    output:
        artefact("hexapod.sensitivity_actuator"),
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
            artefact("hexapod.sensitivity_actuator"),
            actuator=HEXAPOD_ACTUATORS,
        ),
        code=code_inputs("hexapod_sensitivity.py"),
    output:
        artefact("hexapod.sensitivity"),
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
        sensitivity=artefact("hexapod.sensitivity"),
        forces=artefact("hexapod.forces"),
        code=code_inputs("hexapod_force_accuracy.py"),
    output:
        artefact("hexapod.force_accuracy"),
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
        trajectory=artefact("hexapod.trajectory"),
        forces=artefact("hexapod.forces"),
        sensitivity=artefact("hexapod.sensitivity"),
        force_accuracy=artefact("hexapod.force_accuracy"),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("hexapod_findings.py"),
    output:
        findings=artefact("hexapod.findings"),
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
        artefact("hexapod.findings"),
        artefact("hexapod.trajectory"),
        artefact("hexapod.force_accuracy"),
        artefact("hexapod.forces"),
        artefact("hexapod.sensitivity"),


use rule chapter as ch6_hexapod with:
    input:
        **chapter_files("ch6_hexapod"),
        findings=artefact("hexapod.findings"),
        trajectory=artefact("hexapod.trajectory"),
        forces=artefact("hexapod.forces"),
        sensitivity=artefact("hexapod.sensitivity"),
        force_accuracy=artefact("hexapod.force_accuracy"),
    output:
        **chapter_outputs("ch6_hexapod"),
    log:
        chapter_log("ch6_hexapod"),
    benchmark:
        chapter_benchmark("ch6_hexapod")
