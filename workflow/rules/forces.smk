# Stage 'forces' (chapter 3.1): dynamometer records -> per-cut chunked spectra and
# mean forces -> peaks table, spectra and the identified cutting coefficients.
# One simulator job (virtual cell), one analysis job per cut (one for all the virtual cell's
# cuts), then one gather job.
FORCE_FILES = {f["cut"]: f for f in RAW_FILES if f["kind"] == "force"}


# the manifest entry of a cut's record; the planted truth input (synthetic runs only)
force_entry = lambda w: FORCE_FILES[w.cut]
forces_truth_input = lambda w: (
    optional_input(SYNTHETIC, truth=artefact("synthetic.truth"))
)


rule forces_cut:
    input:
        raw=lambda w: f"{RAW}/{force_entry(w)['path']}",
        study=STUDY,
        code=code_inputs("forces_cut.py"),
    output:
        artefact("forces.cut"),
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
            code=code_inputs("forces_cut.py"),
        output:
            [artefact("forces.cut", cut=c) for c in FORCE_FILES],
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
        cuts=expand(artefact("forces.cut"), cut=FORCE_FILES),
        study=STUDY,
        # a cut judged to chatter is left out of the coefficients' identification
        verdicts=artefact("chatter.verdicts"),
        code=code_inputs("forces_gather.py"),
    output:
        spectra=artefact("forces.spectra"),
        peaks=report(
            artefact("forces.peaks"),
            caption="../report/ch3_forces.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        coefficients=report(
            artefact("forces.cutting_coefficients"),
            caption="../report/ch3_forces.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        means=artefact("forces.mean_forces"),
        harmonics=artefact("forces.harmonics"),
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
        **({"modes": artefact("modal.modes")} if has_kind("impact") else {}),
        peaks=artefact("forces.peaks"),
        spectra=artefact("forces.spectra"),
        means=artefact("forces.mean_forces"),
        coefficients=artefact("forces.cutting_coefficients"),
        cuts=artefact("ingest.cuts"),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("forces_findings.py"),
    output:
        findings=artefact("forces.findings"),
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
        artefact("forces.findings"),
        artefact("forces.spectra"),
        artefact("forces.peaks"),
        artefact("forces.cutting_coefficients"),
        artefact("forces.mean_forces"),
        artefact("forces.harmonics"),


use rule chapter as ch3_forces with:
    input:
        unpack(forces_truth_input),
        **({"modes": artefact("modal.modes")} if has_kind("impact") else {}),
        **chapter_files("ch3_forces"),
        findings=artefact("forces.findings"),
        spectra=artefact("forces.spectra"),
        peaks=artefact("forces.peaks"),
        coefficients=artefact("forces.cutting_coefficients"),
        means=artefact("forces.mean_forces"),
        harmonics=artefact("forces.harmonics"),
        cuts=artefact("ingest.cuts"),
        # the impact test's modes, when the raw folder has one (chapter 3.3)
    output:
        **chapter_outputs("ch3_forces"),
    log:
        chapter_log("ch3_forces"),
    benchmark:
        chapter_benchmark("ch3_forces")
