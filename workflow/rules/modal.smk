# Stage 'modal' (thesis §3.3, any test layout): impact hits (CSV or UFF 58 time histories)
# or UFF 58 FRFs -> FRFs H(response point, reference point) -> peak picking, LSCF
# stabilization chart, modes (f_n, zeta, complex shapes over the measured points, modal
# mass/stiffness with a driving point, MAC, sanity flags), UFF 55 mode shapes.


wildcard_constraints:
    hit_dir="[XYZ]",
    hit="[0-9]+",


MODAL_HITS = [f for f in RAW_FILES if f["kind"] == "impact"]


rule modal_frf:
    input:
        data=kind_input("modal", "impact"),
        hits=[f"{RAW}/{f['path']}" for f in MODAL_HITS],
        study=STUDY,
    output:
        frf="results/modal/frf.nc",
        hits="results/modal/hits.csv",
        traces="results/modal/hits.nc",
        uff="results/modal/frf.uff",
    log:
        "results/logs/modal/frf.log",
    benchmark:
        "results/benchmarks/rules/modal/frf.tsv"
    conda:
        ENV
    params:
        modal=config["modal"],
        files=[{k: v for k, v in f.items() if k != "sha256"} for f in MODAL_HITS],
    script:
        "../scripts/modal_frf.py"


rule modal_identify:
    input:
        frf="results/modal/frf.nc",
    output:
        modes=report(
            "results/modal/modes.csv",
            caption="../report/ch3_modal.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        peaks="results/modal/peak_picking.csv",
        stabilization="results/modal/stabilization.csv",
        synth="results/modal/frf_synth.nc",
        shapes="results/modal/mode_shapes.csv",
        mac="results/modal/mac.csv",
        uff="results/modal/modes.uff",
    log:
        "results/logs/modal/identify.log",
    benchmark:
        "results/benchmarks/rules/modal/identify.tsv"
    conda:
        ENV
    params:
        modal=config["modal"],
        experiment_band_hz=EXPERIMENT.get("modal_band_hz"),
        level=config["plan"]["interval_level"],
    script:
        "../scripts/modal_identify.py"


rule modal_report:
    input:
        **optional_input(SYNTHETIC, truth="results/synthetic/truth.nc"),
        **optional_input(has_kind("force"), forces_peaks="results/forces/peaks.csv"),
        frf="results/modal/frf.nc",
        modes="results/modal/modes.csv",
        peaks="results/modal/peak_picking.csv",
    output:
        peak_groups="results/modal/peak_groups.csv",
        truth_check="results/modal/truth_check.csv",
        coupling="results/modal/coupling.csv",
        coupling_pairs="results/modal/coupling_pairs.csv",
    log:
        "results/logs/modal/report.log",
    benchmark:
        "results/benchmarks/rules/modal/report.tsv"
    conda:
        ENV
    params:
        coupling_tolerance=config["modal"]["coupling_tolerance"],
    script:
        "../scripts/modal_report.py"


rule modal_findings:
    input:
        frf="results/modal/frf.nc",
        synth="results/modal/frf_synth.nc",
        hits="results/modal/hits.csv",
        modes="results/modal/modes.csv",
        peaks="results/modal/peak_picking.csv",
        stabilization="results/modal/stabilization.csv",
        mac="results/modal/mac.csv",
        peak_groups="results/modal/peak_groups.csv",
        truth_check="results/modal/truth_check.csv",
        coupling="results/modal/coupling.csv",
        coupling_pairs="results/modal/coupling_pairs.csv",
        references=str(REPO / "src" / "robomill" / "data" / "references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=str(REPO / "src" / "robomill" / "data" / "scorecard.yaml"),
    output:
        findings="results/modal/findings.yaml",
    log:
        "results/logs/modal/findings.log",
    benchmark:
        "results/benchmarks/rules/modal/findings.tsv"
    conda:
        ENV
    params:
        coherence_min=config["modal"]["coherence_min"],
        coupling_tolerance=config["modal"]["coupling_tolerance"],
        stability={k: config["modal"][k] for k in ("tol_f", "tol_zeta", "mac_min")},
        thesis_study=THESIS_STUDY,
    script:
        "../scripts/modal_findings.py"


rule modal:
    input:
        "results/modal/frf.nc",
        "results/modal/modes.csv",
        "results/modal/peak_picking.csv",
        "results/modal/modes.uff",
        "results/modal/peak_groups.csv",
        "results/modal/coupling.csv",
        "results/modal/findings.yaml",


use rule chapter as ch3_modal with:
    input:
        **chapter_files("ch3_modal"),
        frf="results/modal/frf.nc",
        synth="results/modal/frf_synth.nc",
        traces="results/modal/hits.nc",
        hits="results/modal/hits.csv",
        modes="results/modal/modes.csv",
        peaks="results/modal/peak_picking.csv",
        stabilization="results/modal/stabilization.csv",
        shapes="results/modal/mode_shapes.csv",
        mac="results/modal/mac.csv",
        peak_groups="results/modal/peak_groups.csv",
        truth_check="results/modal/truth_check.csv",
        coupling="results/modal/coupling.csv",
        coupling_pairs="results/modal/coupling_pairs.csv",
        findings="results/modal/findings.yaml",
    output:
        **chapter_outputs("ch3_modal"),
    log:
        chapter_log("ch3_modal"),
    benchmark:
        chapter_benchmark("ch3_modal")
