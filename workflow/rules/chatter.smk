# Stage 'chatter' [Shagniev 2019]: stability lobes for configured machines (one job per
# case), the seed's time-domain robot-tool-surface model with detection and adaptive depth
# (chapter 6.1), and the study robot's lobes, mode-coupling check and chatter-free
# recommendations (chapter 4).

CHATTER_CASES = {c["name"]: c for c in config["chatter"]["cases"]}
# Why the force cuts' design cannot identify the cutting coefficients (one feed per tooth,
# fewer than 3 cuts), or None: the study's lobes need them (the registry's design condition
# cutting_coefficients, robomill.registry; forces_gather writes them as NaN with the reason).
COEFFICIENTS_UNMET = unmet_requirement(
    "cutting_coefficients", CUTS, EXPERIMENT, RAW_FILES
)


wildcard_constraints:
    chatter_case="|".join(CHATTER_CASES) if CHATTER_CASES else "NONE",


rule chatter_case:
    input:
        code=code_inputs("chatter_case.py"),
    output:
        nc=artefact("chatter.case"),
    log:
        "results/logs/chatter/cases/{chatter_case}.log",
    benchmark:
        "results/benchmarks/rules/chatter/cases/{chatter_case}.tsv"
    conda:
        ENV
    # one BLAS/OpenMP thread: Snakemake sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and
    # MKL_NUM_THREADS of a script's process to its threads (many small eigenproblems:
    # more threads only add overhead)
    threads: 1
    params:
        case=lambda w: CHATTER_CASES[w.chatter_case],
        accuracy=config["chatter"]["accuracy"],
        depth_max_mm=config["chatter"]["depth_max_mm"],
    script:
        "../scripts/chatter_case.py"


rule chatter_seed:
    input:
        code=code_inputs("chatter_seed.py"),
    output:
        nc=artefact("chatter.simulation"),
    log:
        "results/logs/chatter/simulation.log",
    benchmark:
        "results/benchmarks/rules/chatter/simulation.tsv"
    conda:
        ENV
    # one BLAS/OpenMP thread: Snakemake sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and
    # MKL_NUM_THREADS of a script's process to its threads (many small eigenproblems:
    # more threads only add overhead)
    threads: 1
    params:
        seed=config["chatter"]["seed"],
        accuracy=config["chatter"]["accuracy"],
    script:
        "../scripts/chatter_seed.py"


rule chatter_thesis:
    input:
        data=kind_input("chatter", "impact", "force"),
        # the lobes need K_tc, K_rc: stop with one line if the cuts cannot identify them
        identified=design_input(
            "chatter", "identified cutting coefficients", COEFFICIENTS_UNMET
        ),
        modes=artefact("modal.modes"),
        coefficients=artefact("forces.cutting_coefficients"),
        peaks=artefact("forces.peaks"),
        # each cut's own speed, depth, direction and tool (robomill.study)
        study=STUDY,
        code=code_inputs("chatter_thesis.py"),
    output:
        lobes=artefact("chatter.lobes"),
        recommendations=report(
            artefact("chatter.recommendations"),
            caption="../report/ch4.rst",
            category="Chapter 4",
            subcategory="Tables",
        ),
    log:
        "results/logs/chatter/thesis.log",
    benchmark:
        "results/benchmarks/rules/chatter/thesis.tsv"
    # the longest chain of the study's end (lobes, findings, chapter 6.1, scorecard): before
    # the chapters ready beside it, whose inputs the greedy scheduler would rank first
    priority: 10
    conda:
        ENV
    # one BLAS/OpenMP thread: Snakemake sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS and
    # MKL_NUM_THREADS of a script's process to its threads (many small eigenproblems:
    # more threads only add overhead)
    threads: 1
    params:
        thesis=config["chatter"]["thesis"],
        accuracy=config["chatter"]["accuracy"],
    script:
        "../scripts/chatter_thesis.py"


# Chatter verdicts from the time records (chapter 4 "Chatter from recordings"): every cut's
# dynamometer force record and every sound or vibration recording, one row each.
VERDICT_FILES = [f for f in RAW_FILES if f["kind"] in ("force", "sound", "vibration")]


rule chatter_verdicts:
    input:
        raw=[f"{RAW}/{f['path']}" for f in VERDICT_FILES],
        study=STUDY,
        code=code_inputs("chatter_verdicts.py"),
    output:
        verdicts=report(
            artefact("chatter.verdicts"),
            caption="../report/ch4.rst",
            category="Chapter 4",
            subcategory="Tables",
        ),
        spectrograms=artefact("chatter.spectrograms"),
        findings=artefact("chatter.verdict_findings"),
    log:
        "results/logs/chatter/verdicts.log",
    benchmark:
        "results/benchmarks/rules/chatter/verdicts.tsv"
    conda:
        ENV
    params:
        settings=config["chatter"]["verdicts"],
    script:
        "../scripts/chatter_verdicts.py"


if VERDICT_FILES:
    ALL_TARGETS.append(artefact("chatter.verdicts"))


# the study's robot (chapter 4) only where the folder has its modes and forces and the force
# cuts identify the cutting coefficients; the reference studies (chapter 6.1: the configured
# cases and Shagniev 2019) in any run
CHATTER_ROBOT = has_kind("impact") and has_kind("force") and not COEFFICIENTS_UNMET


rule chatter_findings:
    input:
        **optional_input(
            CHATTER_ROBOT,
            lobes=artefact("chatter.lobes"),
            recommendations=artefact("chatter.recommendations"),
        ),
        cases=expand(artefact("chatter.case"), chatter_case=CHATTER_CASES),
        simulation=artefact("chatter.simulation"),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("chatter_findings.py"),
    output:
        findings=artefact("chatter.findings"),
    log:
        "results/logs/chatter/findings.log",
    benchmark:
        "results/benchmarks/rules/chatter/findings.tsv"
    priority: 10
    conda:
        ENV
    params:
        safety_fraction=config["chatter"]["thesis"]["safety_fraction"],
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/chatter_findings.py"


rule chatter:
    input:
        expand(artefact("chatter.case"), chatter_case=CHATTER_CASES),
        artefact("chatter.simulation"),
        artefact("chatter.lobes"),
        artefact("chatter.recommendations"),
        artefact("chatter.findings"),
        artefact("chatter.verdicts"),


use rule chapter as ch4 with:
    input:
        **chapter_files("ch4"),
        lobes=artefact("chatter.lobes"),
        recommendations=artefact("chatter.recommendations"),
        findings=artefact("chatter.findings"),
        verdicts=artefact("chatter.verdicts"),
        spectrograms=artefact("chatter.spectrograms"),
        verdict_findings=artefact("chatter.verdict_findings"),
    output:
        **chapter_outputs("ch4"),
    log:
        chapter_log("ch4"),
    benchmark:
        chapter_benchmark("ch4")


# Chapter 6.1 (reference studies): the lobe methods on the configured published cases and the
# Shagniev 2019 robot-tool-surface model; no data of the study.
use rule chapter as ch6_chatter with:
    input:
        **chapter_files("ch6_chatter"),
        cases=expand(artefact("chatter.case"), chatter_case=CHATTER_CASES),
        simulation=artefact("chatter.simulation"),
        findings=artefact("chatter.findings"),
    output:
        **chapter_outputs("ch6_chatter"),
    log:
        chapter_log("ch6_chatter"),
    benchmark:
        chapter_benchmark("ch6_chatter")
