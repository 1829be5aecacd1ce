# Stage 'forces' (chapter 3.1): dynamometer records -> per-cut chunked spectra and
# mean forces -> peaks table, spectra and the identified cutting coefficients.
# One simulator job (virtual cell), one analysis job per cut (one for all the virtual cell's
# cuts), then one gather job.
FORCE_FILES = {f["cut"]: f for f in RAW_FILES if f["kind"] == "force"}


# the manifest entry of a cut's record; the planted truth input (synthetic runs only)
force_entry = lambda w: FORCE_FILES[w.cut]
forces_truth_input = lambda w: (
    optional_input(SYNTHETIC, truth="results/synthetic/truth.nc")
)


rule forces_cut:
    input:
        raw=lambda w: f"{RAW}/{force_entry(w)['path']}",
        study=STUDY,
    output:
        "results/forces/cuts/{cut}.nc",
    log:
        "results/logs/forces/cut_{cut}.log",
    benchmark:
        "results/benchmarks/rules/forces/cut_{cut}.tsv"
    conda:
        ENV
    params:
        settings=config["forces"],
        relpath=lambda w: [force_entry(w)["path"]],
        cut=lambda w: [w.cut],
    script:
        "../scripts/forces_cut.py"


# The virtual cell's records all come from one simulator job and always change together:
# there they are analysed in one job (~0.3 s of work per cut against ~1.5 s of a job's
# start-up). A real record can change alone: one job per cut.
if SYNTHETIC and FORCE_FILES:

    rule forces_cuts:
        input:
            raw=[f"{RAW}/{f['path']}" for f in FORCE_FILES.values()],
            study=STUDY,
        output:
            [f"results/forces/cuts/{c}.nc" for c in FORCE_FILES],
        log:
            "results/logs/forces/cuts.log",
        benchmark:
            "results/benchmarks/rules/forces/cuts.tsv"
        conda:
            ENV
        params:
            settings=config["forces"],
            relpath=[f["path"] for f in FORCE_FILES.values()],
            cut=list(FORCE_FILES),
        script:
            "../scripts/forces_cut.py"

    ruleorder: forces_cuts > forces_cut


rule forces_gather:
    input:
        data=kind_input("forces", "force"),
        cuts=expand("results/forces/cuts/{cut}.nc", cut=FORCE_FILES),
        study=STUDY,
        # a cut judged to chatter is left out of the coefficients' identification
        verdicts="results/chatter/verdicts.csv",
    output:
        spectra="results/forces/spectra.nc",
        peaks=report(
            "results/forces/peaks.csv",
            caption="../report/ch3_forces.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        coefficients=report(
            "results/forces/cutting_coefficients.csv",
            caption="../report/ch3_forces.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        means="results/forces/mean_forces.csv",
        harmonics="results/forces/harmonics.csv",
    log:
        "results/logs/forces/gather.log",
    benchmark:
        "results/benchmarks/rules/forces/gather.tsv"
    conda:
        ENV
    params:
        settings=config["forces"],
    script:
        "../scripts/forces_gather.py"


# Chapter 3.1's findings on the dominant peak, with the verdict against the identified modes
# (forces.mode_match_hz) and the scorecard rows of the stage ("Against the thesis").
rule forces_findings:
    input:
        unpack(forces_truth_input),
        # the impact test's modes, when the raw folder has one (chapter 3.3)
        **({"modes": "results/modal/modes.csv"} if has_kind("impact") else {}),
        peaks="results/forces/peaks.csv",
        spectra="results/forces/spectra.nc",
        means="results/forces/mean_forces.csv",
        coefficients="results/forces/cutting_coefficients.csv",
        cuts="results/ingest/cuts.csv",
        references=str(REPO / "src" / "robomill" / "data" / "references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=str(REPO / "src" / "robomill" / "data" / "scorecard.yaml"),
    output:
        findings="results/forces/findings.yaml",
    log:
        "results/logs/forces/findings.log",
    benchmark:
        "results/benchmarks/rules/forces/findings.tsv"
    conda:
        ENV
    params:
        mode_match_hz=config["forces"]["mode_match_hz"],
        band_hz=config["forces"]["dominant_band_hz"],
        prominence_db=config["forces"]["dominant_prominence_db"],
        settings=config["forces"],
        experiment=dict(EXPERIMENT),
        thesis_design=THESIS_DESIGN,
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/forces_findings.py"


rule forces:
    input:
        "results/forces/findings.yaml",
        "results/forces/spectra.nc",
        "results/forces/peaks.csv",
        "results/forces/cutting_coefficients.csv",
        "results/forces/mean_forces.csv",
        "results/forces/harmonics.csv",


use rule chapter as ch3_forces with:
    input:
        unpack(forces_truth_input),
        **({"modes": "results/modal/modes.csv"} if has_kind("impact") else {}),
        **chapter_files("ch3_forces"),
        findings="results/forces/findings.yaml",
        spectra="results/forces/spectra.nc",
        peaks="results/forces/peaks.csv",
        coefficients="results/forces/cutting_coefficients.csv",
        means="results/forces/mean_forces.csv",
        harmonics="results/forces/harmonics.csv",
        cuts="results/ingest/cuts.csv",
        # the impact test's modes, when the raw folder has one (chapter 3.3)
    output:
        **chapter_outputs("ch3_forces"),
    log:
        chapter_log("ch3_forces"),
    benchmark:
        chapter_benchmark("ch3_forces")
