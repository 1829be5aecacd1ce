# Stage 'straightness' (chapter 3.2): laser-tracker runs re-ordered in space, their
# spectra in 1/mm, gear spatial frequencies and peak -> gear attribution.
# One simulator job (virtual cell), one analysis job per tracker run (one for all the virtual
# cell's runs), then one gather job.
# (keyed by the run id of robomill.experiment.tracker_run: the one key of a run downstream)
from robomill.experiment import tracker_pass_pairs

TRACKER_RUNS = {tracker_run(f): f for f in RAW_FILES if f["kind"] == "tracker"}


rule straightness_run:
    input:
        raw=lambda w: f"{RAW}/{TRACKER_RUNS[w.run]['path']}",
        study=STUDY,
        cell=CELL,
        code=code_inputs("straightness_run.py"),
    output:
        nc=artefact("straightness.run"),
        peaks=artefact("straightness.run_peaks"),
        gears=artefact("straightness.run_gears"),
    log:
        "results/logs/straightness/run_{run}.log",
    benchmark:
        "results/benchmarks/rules/straightness/run_{run}.tsv"
    wildcard_constraints:
        run="|".join(map(re.escape, TRACKER_RUNS)) or "no_tracker_run",
    conda:
        ENV
    params:
        settings=config["straightness"],
        cell_relpath=CELL_RELPATH,
        runs=lambda w: [tracker_run_spec(w.run, TRACKER_RUNS[w.run])],
    script:
        "../scripts/straightness_run.py"


# The virtual cell's runs all come from one simulator job and always change together: there
# they are analysed in one job (the per-run split would buy no caching, and each job pays
# ~1.5 s of start-up for ~0.2 s of work). A real run's file can change alone: one job per run.
if SYNTHETIC and TRACKER_RUNS:

    rule straightness_runs:
        input:
            raw=[f"{RAW}/{f['path']}" for f in TRACKER_RUNS.values()],
            study=STUDY,
            cell=CELL,
            code=code_inputs("straightness_run.py"),
        output:
            nc=[artefact("straightness.run", run=r) for r in TRACKER_RUNS],
            peaks=[artefact("straightness.run_peaks", run=r) for r in TRACKER_RUNS],
            gears=[artefact("straightness.run_gears", run=r) for r in TRACKER_RUNS],
        log:
            "results/logs/straightness/runs.log",
        benchmark:
            "results/benchmarks/rules/straightness/runs.tsv"
        conda:
            ENV
        params:
            settings=config["straightness"],
            cell_relpath=CELL_RELPATH,
            runs=[tracker_run_spec(r, f) for r, f in TRACKER_RUNS.items()],
        script:
            "../scripts/straightness_run.py"

    ruleorder: straightness_runs > straightness_run


rule straightness_gather:
    input:
        data=kind_input("straightness", "tracker"),
        runs=expand(artefact("straightness.run"), run=TRACKER_RUNS),
        peaks=expand(artefact("straightness.run_peaks"), run=TRACKER_RUNS),
        gears=expand(artefact("straightness.run_gears"), run=TRACKER_RUNS),
        code=code_inputs("straightness_gather.py"),
    output:
        profiles=artefact("straightness.profiles"),
        peaks=report(
            artefact("straightness.peaks"),
            caption="../report/ch3_straightness.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        gears=artefact("straightness.gears"),
    log:
        "results/logs/straightness/gather.log",
    benchmark:
        "results/benchmarks/rules/straightness/gather.tsv"
    conda:
        ENV
    params:
        settings=config["straightness"],
        runs=[{"run": r} for r in TRACKER_RUNS],
    script:
        "../scripts/straightness_gather.py"


# The static deflection under the cutting force (a cut tracked twice: the loaded pass while
# cutting, the air pass along the same path without material; manifest key pass): the loaded
# path minus the air path. Built by `all` where the raw folder has an air pass.
TRACKER_PAIRS = tracker_pass_pairs(TRACKER_RUNS)
TRACKER_PAIRED = list(
    dict.fromkeys(
        r for p in TRACKER_PAIRS for r in (p["loaded_run"], p["air_run"]) if r
    )
)

if TRACKER_PAIRS:

    rule straightness_deflection:
        input:
            raw=[f"{RAW}/{TRACKER_RUNS[r]['path']}" for r in TRACKER_PAIRED],
            study=STUDY,
            code=code_inputs("straightness_deflection.py"),
        output:
            deflection=artefact("straightness.deflection"),
        log:
            "results/logs/straightness/deflection.log",
        benchmark:
            "results/benchmarks/rules/straightness/deflection.tsv"
        conda:
            ENV
        params:
            settings=config["straightness"],
            pairs=TRACKER_PAIRS,
            specs=[tracker_run_spec(r, TRACKER_RUNS[r]) for r in TRACKER_PAIRED],
        script:
            "../scripts/straightness_deflection.py"

    ALL_TARGETS.append(artefact("straightness.deflection"))


rule straightness_truth_check:
    input:
        peaks=artefact("straightness.peaks"),
        profiles=artefact("straightness.profiles"),
        truth=optional_input(SYNTHETIC, [artefact("synthetic.truth")]),
        code=code_inputs("straightness_truth_check.py"),
    output:
        artefact("straightness.truth_check"),
    log:
        "results/logs/straightness/truth_check.log",
    benchmark:
        "results/benchmarks/rules/straightness/truth_check.tsv"
    conda:
        ENV
    params:
        settings=config["straightness"],
    script:
        "../scripts/straightness_truth_check.py"


# Chapter 3.2's findings: the runs, gear and temporal peaks, the verdict on the surface band
# (straightness.threshold), the gear peaks on the surface (chapter 2's peaks, where the study
# profiled surfaces), the planted truth (synthetic), with the stage's scorecard rows
# ("Against the thesis").
rule straightness_findings:
    input:
        **optional_input(has_kind("profile"), surface_peaks=artefact("surface.peaks")),
        peaks=artefact("straightness.peaks"),
        profiles=artefact("straightness.profiles"),
        truth_check=artefact("straightness.truth_check"),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("straightness_findings.py"),
    output:
        findings=artefact("straightness.findings"),
    log:
        "results/logs/straightness/findings.log",
    benchmark:
        "results/benchmarks/rules/straightness/findings.tsv"
    conda:
        ENV
    params:
        surface_band_per_mm=config["straightness"]["surface_band_per_mm"],
        fmax_store_per_mm=config["straightness"]["fmax_store_per_mm"],
        threshold=config["straightness"]["threshold"],
        tol_bins=config["straightness"]["tol_bins"],
        fmin_cycles=config["straightness"]["fmin_cycles"],
        truth_margin=config["straightness"]["truth_margin"],
        thesis_design=THESIS_DESIGN,
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/straightness_findings.py"


rule straightness:
    input:
        artefact("straightness.findings"),
        artefact("straightness.peaks"),
        artefact("straightness.gears"),
        artefact("straightness.profiles"),
        artefact("straightness.truth_check"),


use rule chapter as ch3_straightness with:
    input:
        **chapter_files("ch3_straightness"),
        findings=artefact("straightness.findings"),
        peaks=artefact("straightness.peaks"),
        gears=artefact("straightness.gears"),
        profiles=artefact("straightness.profiles"),
        truth_check=artefact("straightness.truth_check"),
        surface_peaks=artefact("surface.peaks"),
    output:
        **chapter_outputs("ch3_straightness"),
    log:
        chapter_log("ch3_straightness"),
    benchmark:
        chapter_benchmark("ch3_straightness")
