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
    output:
        nc="results/straightness/runs/{run}.nc",
        peaks="results/straightness/runs/{run}_peaks.csv",
        gears="results/straightness/runs/{run}_gears.csv",
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
        output:
            nc=[f"results/straightness/runs/{r}.nc" for r in TRACKER_RUNS],
            peaks=[f"results/straightness/runs/{r}_peaks.csv" for r in TRACKER_RUNS],
            gears=[f"results/straightness/runs/{r}_gears.csv" for r in TRACKER_RUNS],
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
        runs=expand("results/straightness/runs/{run}.nc", run=TRACKER_RUNS),
        peaks=expand("results/straightness/runs/{run}_peaks.csv", run=TRACKER_RUNS),
        gears=expand("results/straightness/runs/{run}_gears.csv", run=TRACKER_RUNS),
    output:
        profiles="results/straightness/profiles.nc",
        peaks=report(
            "results/straightness/peaks.csv",
            caption="../report/ch3_straightness.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        gears="results/straightness/gears.csv",
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
        output:
            deflection="results/straightness/deflection.csv",
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

    ALL_TARGETS.append("results/straightness/deflection.csv")


rule straightness_truth_check:
    input:
        peaks="results/straightness/peaks.csv",
        profiles="results/straightness/profiles.nc",
        truth=optional_input(SYNTHETIC, ["results/synthetic/truth.nc"]),
    output:
        "results/straightness/truth_check.csv",
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
        **optional_input(has_kind("profile"), surface_peaks="results/surface/peaks.csv"),
        peaks="results/straightness/peaks.csv",
        profiles="results/straightness/profiles.nc",
        truth_check="results/straightness/truth_check.csv",
        references=str(REPO / "src" / "robomill" / "data" / "references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=str(REPO / "src" / "robomill" / "data" / "scorecard.yaml"),
    output:
        findings="results/straightness/findings.yaml",
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
        "results/straightness/findings.yaml",
        "results/straightness/peaks.csv",
        "results/straightness/gears.csv",
        "results/straightness/profiles.nc",
        "results/straightness/truth_check.csv",


use rule chapter as ch3_straightness with:
    input:
        **chapter_files("ch3_straightness"),
        findings="results/straightness/findings.yaml",
        peaks="results/straightness/peaks.csv",
        gears="results/straightness/gears.csv",
        profiles="results/straightness/profiles.nc",
        truth_check="results/straightness/truth_check.csv",
        surface_peaks="results/surface/peaks.csv",
    output:
        **chapter_outputs("ch3_straightness"),
    log:
        chapter_log("ch3_straightness"),
    benchmark:
        chapter_benchmark("ch3_straightness")
