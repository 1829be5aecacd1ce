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
        code=code_inputs("modal_frf.py"),
    output:
        frf=artefact("modal.frf"),
        hits=artefact("modal.hits"),
        traces=artefact("modal.hits_nc"),
        uff=artefact("modal.frf_uff"),
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
        frf=artefact("modal.frf"),
        code=code_inputs("modal_identify.py"),
    output:
        modes=report(
            artefact("modal.modes"),
            caption="../report/ch3_modal.rst",
            category="Chapter 3",
            subcategory="Tables",
        ),
        peaks=artefact("modal.peak_picking"),
        stabilization=artefact("modal.stabilization"),
        synth=artefact("modal.frf_synth"),
        shapes=artefact("modal.mode_shapes"),
        mac=artefact("modal.mac"),
        uff=artefact("modal.modes_uff"),
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
        **optional_input(SYNTHETIC, truth=artefact("synthetic.truth")),
        **optional_input(has_kind("force"), forces_peaks=artefact("forces.peaks")),
        frf=artefact("modal.frf"),
        modes=artefact("modal.modes"),
        peaks=artefact("modal.peak_picking"),
        code=code_inputs("modal_report.py"),
    output:
        peak_groups=artefact("modal.peak_groups"),
        truth_check=artefact("modal.truth_check"),
        coupling=artefact("modal.coupling"),
        coupling_pairs=artefact("modal.coupling_pairs"),
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
        frf=artefact("modal.frf"),
        synth=artefact("modal.frf_synth"),
        hits=artefact("modal.hits"),
        modes=artefact("modal.modes"),
        peaks=artefact("modal.peak_picking"),
        stabilization=artefact("modal.stabilization"),
        mac=artefact("modal.mac"),
        peak_groups=artefact("modal.peak_groups"),
        truth_check=artefact("modal.truth_check"),
        coupling=artefact("modal.coupling"),
        coupling_pairs=artefact("modal.coupling_pairs"),
        references=package_data("references.yaml"),
        # the scorecard checks: their reasons are quoted in the findings
        checks=package_data("scorecard.yaml"),
        code=code_inputs("modal_findings.py"),
    output:
        findings=artefact("modal.findings"),
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
        artefact("modal.frf"),
        artefact("modal.modes"),
        artefact("modal.peak_picking"),
        artefact("modal.modes_uff"),
        artefact("modal.peak_groups"),
        artefact("modal.coupling"),
        artefact("modal.findings"),


use rule chapter as ch3_modal with:
    input:
        **chapter_files("ch3_modal"),
        frf=artefact("modal.frf"),
        synth=artefact("modal.frf_synth"),
        traces=artefact("modal.hits_nc"),
        hits=artefact("modal.hits"),
        modes=artefact("modal.modes"),
        peaks=artefact("modal.peak_picking"),
        stabilization=artefact("modal.stabilization"),
        shapes=artefact("modal.mode_shapes"),
        mac=artefact("modal.mac"),
        peak_groups=artefact("modal.peak_groups"),
        truth_check=artefact("modal.truth_check"),
        coupling=artefact("modal.coupling"),
        coupling_pairs=artefact("modal.coupling_pairs"),
        findings=artefact("modal.findings"),
    output:
        **chapter_outputs("ch3_modal"),
    log:
        chapter_log("ch3_modal"),
    benchmark:
        chapter_benchmark("ch3_modal")
